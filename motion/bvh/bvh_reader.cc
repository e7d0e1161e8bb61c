#include "motion/bvh/bvh_reader.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "motion/bvh/root_convention.h"
#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"

namespace mocap {
namespace {

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

// Splits the text into white-space separated tokens while tracking line numbers.
class Tokenizer {
 public:
  Tokenizer(std::string_view text, std::string_view source) : text_(text), source_(source) {}

  // Next token, or empty at end of input. Does not cross into the MOTION data.
  std::string_view Next() {
    SkipSpace();
    const size_t start = pos_;
    while (pos_ < text_.size() && !IsSpace(text_[pos_])) ++pos_;
    token_line_ = line_;
    return text_.substr(start, pos_ - start);
  }
  std::string_view Peek() {
    const size_t saved_pos = pos_;
    const int saved_line = line_;
    std::string_view token = Next();
    pos_ = saved_pos;
    line_ = saved_line;
    return token;
  }
  // Rest of the current line (for "Frames:" and "Frame Time:" headers), consuming its newline.
  std::string_view RestOfLine() {
    const size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    std::string_view rest = text_.substr(start, pos_ - start);
    if (pos_ < text_.size()) {
      ++pos_;
      ++line_;
    }
    return rest;
  }
  void SkipSpace() {
    while (pos_ < text_.size() && IsSpace(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }
  absl::Status Error(std::string_view what) const {
    return absl::InvalidArgumentError(StrCat(source_, ":", token_line_, ": ", what));
  }
  absl::Status ErrorAtLine(int line, std::string_view what) const {
    return absl::InvalidArgumentError(StrCat(source_, ":", line, ": ", what));
  }
  size_t pos() const { return pos_; }
  int line() const { return line_; }
  std::string_view text() const { return text_; }

 private:
  std::string_view text_;
  std::string_view source_;
  size_t pos_ = 0;
  int line_ = 1;
  int token_line_ = 1;
};

std::string Quote(std::string_view token) {
  if (token.empty()) return "end of file";
  if (token.size() > 40) return StrCat("'", token.substr(0, 40), "...'");
  return StrCat("'", token, "'");
}

// Parses one float, accepting a leading '+' and rejecting NaN/inf. Returns the end pointer or
// nullptr on failure.
const char* ParseFloat(const char* begin, const char* end, float& value) {
  if (begin < end && *begin == '+') {
    ++begin;
    if (begin < end && (*begin == '+' || *begin == '-')) return nullptr;
  }
  auto [ptr, ec] = std::from_chars(begin, end, value);
  if (ec == std::errc::result_out_of_range) {
    // Underflow (e.g. 1e-50) reads as zero; overflow stays an error.
    char buffer[64];
    const size_t length = std::min<size_t>(static_cast<size_t>(ptr - begin), sizeof(buffer) - 1);
    std::memcpy(buffer, begin, length);
    buffer[length] = '\0';
    const double wide = std::strtod(buffer, nullptr);
    if (!(std::abs(wide) < 1.0)) return nullptr;
    value = 0.0f;
    return ptr;
  }
  if (ec != std::errc() || !std::isfinite(value)) return nullptr;
  return ptr;
}

absl::StatusOr<float> ExpectFloat(Tokenizer& tokens, std::string_view what) {
  std::string_view token = tokens.Next();
  float value = 0;
  const char* end = token.data() + token.size();
  if (token.empty() || ParseFloat(token.data(), end, value) != end) {
    return tokens.Error(StrCat("expected a finite number for ", what, ", found ", Quote(token)));
  }
  return value;
}

absl::Status Expect(Tokenizer& tokens, std::string_view expected) {
  std::string_view token = tokens.Next();
  if (token != expected) {
    return tokens.Error(StrCat("expected '", expected, "', found ", Quote(token)));
  }
  return absl::OkStatus();
}

absl::StatusOr<ChannelType> ParseChannel(std::string_view token) {
  static constexpr std::pair<std::string_view, ChannelType> kNames[] = {
      {"Xposition", ChannelType::kXposition}, {"Yposition", ChannelType::kYposition},
      {"Zposition", ChannelType::kZposition}, {"Xrotation", ChannelType::kXrotation},
      {"Yrotation", ChannelType::kYrotation}, {"Zrotation", ChannelType::kZrotation}};
  for (const auto& [name, type] : kNames) {
    if (token == name) return type;
  }
  return absl::InvalidArgumentError("unknown channel");
}

class HierarchyParser {
 public:
  explicit HierarchyParser(Tokenizer& tokens) : tokens_(tokens) {}

  absl::StatusOr<Skeleton> Parse() {
    MOCAP_RETURN_IF_ERROR(Expect(tokens_, "HIERARCHY"));
    MOCAP_RETURN_IF_ERROR(Expect(tokens_, "ROOT"));
    MOCAP_RETURN_IF_ERROR(ParseJoint(-1, 0));
    std::string_view next = tokens_.Peek();
    if (next == "ROOT") {
      tokens_.Next();
      return tokens_.Error("a second ROOT is not supported (one skeleton per file)");
    }
    Skeleton skeleton(std::move(joints_));
    if (absl::Status status = skeleton.Validate(); !status.ok()) {
      return tokens_.Error(StrCat("invalid hierarchy: ", status.message()));
    }
    return skeleton;
  }

 private:
  static constexpr int kMaxDepth = 256;

  absl::Status ParseJoint(int parent, int depth) {
    if (depth > kMaxDepth) return tokens_.Error("hierarchy nested too deeply");
    if (static_cast<int>(joints_.size()) >= Skeleton::kMaxJoints) {
      return tokens_.Error(StrCat("more than ", Skeleton::kMaxJoints, " joints"));
    }
    std::string_view name = tokens_.Next();
    if (name.empty() || name == "{" || name == "}") {
      return tokens_.Error(StrCat("expected a joint name, found ", Quote(name)));
    }
    for (const Joint& existing : joints_) {
      if (existing.name == name) return tokens_.Error(StrCat("duplicate joint name ", Quote(name)));
    }
    const int index = static_cast<int>(joints_.size());
    joints_.push_back(Joint{.name = std::string(name), .parent = parent});
    MOCAP_RETURN_IF_ERROR(Expect(tokens_, "{"));
    MOCAP_RETURN_IF_ERROR(Expect(tokens_, "OFFSET"));
    Eigen::Vector3f offset;
    for (int axis = 0; axis < 3; ++axis) {
      MOCAP_ASSIGN_OR_RETURN(offset[axis], ExpectFloat(tokens_, StrCat("OFFSET of ", name)));
    }
    joints_[index].offset = offset;
    if (tokens_.Peek() == "CHANNELS") {
      tokens_.Next();
      std::string_view count_token = tokens_.Next();
      int count = -1;
      auto [ptr, ec] = std::from_chars(count_token.data(), count_token.data() + count_token.size(), count);
      if (ec != std::errc() || ptr != count_token.data() + count_token.size() || count < 0 || count > 6) {
        return tokens_.Error(StrCat("expected a channel count from 0 to 6, found ", Quote(count_token)));
      }
      for (int c = 0; c < count; ++c) {
        std::string_view channel_token = tokens_.Next();
        auto channel = ParseChannel(channel_token);
        if (!channel.ok()) {
          return tokens_.Error(StrCat("unknown channel ", Quote(channel_token), " on joint ", Quote(name),
                                      " (expected X/Y/Z position or rotation)"));
        }
        for (ChannelType seen : joints_[index].channels) {
          if (seen == *channel) {
            return tokens_.Error(StrCat("channel ", Quote(channel_token), " repeated on joint ", Quote(name)));
          }
        }
        joints_[index].channels.push_back(*channel);
      }
    }
    while (true) {
      std::string_view token = tokens_.Next();
      if (token == "}") return absl::OkStatus();
      if (token == "JOINT") {
        MOCAP_RETURN_IF_ERROR(ParseJoint(index, depth + 1));
      } else if (token == "End") {
        MOCAP_RETURN_IF_ERROR(Expect(tokens_, "Site"));
        MOCAP_RETURN_IF_ERROR(Expect(tokens_, "{"));
        MOCAP_RETURN_IF_ERROR(Expect(tokens_, "OFFSET"));
        Eigen::Vector3f end_site;
        for (int axis = 0; axis < 3; ++axis) {
          MOCAP_ASSIGN_OR_RETURN(end_site[axis], ExpectFloat(tokens_, StrCat("End Site of ", name)));
        }
        MOCAP_RETURN_IF_ERROR(Expect(tokens_, "}"));
        if (joints_[index].end_site) {
          return tokens_.Error(StrCat("joint ", Quote(name), " has two End Sites"));
        }
        joints_[index].end_site = end_site;
      } else if (token.empty() || token == "MOTION") {
        return tokens_.Error(StrCat("unbalanced braces: joint ", Quote(name), " is not closed before ", Quote(token)));
      } else {
        return tokens_.Error(
            StrCat("expected JOINT, End Site or '}' in joint ", Quote(name), ", found ", Quote(token)));
      }
    }
  }

  Tokenizer& tokens_;
  std::vector<Joint> joints_;
};

// Parses "Frames: N" / "Frame Time: T" where the value follows a colon on the same line.
std::string_view AfterColon(std::string_view line) {
  const size_t colon = line.find(':');
  std::string_view rest = colon == std::string_view::npos ? std::string_view() : line.substr(colon + 1);
  while (!rest.empty() && IsSpace(rest.front())) rest.remove_prefix(1);
  while (!rest.empty() && IsSpace(rest.back())) rest.remove_suffix(1);
  return rest;
}

}  // namespace

absl::StatusOr<BvhClip> ParseBvh(std::string_view text, std::string_view source_name, const BvhReadLimits& limits) {
  if (text.size() >= 3 && static_cast<unsigned char>(text[0]) == 0xEF && static_cast<unsigned char>(text[1]) == 0xBB &&
      static_cast<unsigned char>(text[2]) == 0xBF) {
    text.remove_prefix(3);  // UTF-8 byte order mark
  }
  Tokenizer tokens(text, source_name);
  BvhClip clip;
  {
    HierarchyParser hierarchy(tokens);
    MOCAP_ASSIGN_OR_RETURN(clip.skeleton, hierarchy.Parse());
  }
  MOCAP_RETURN_IF_ERROR(Expect(tokens, "MOTION"));

  tokens.SkipSpace();
  const int frames_line = tokens.line();
  std::string_view frames_header = tokens.RestOfLine();
  if (!frames_header.starts_with("Frames")) {
    return tokens.ErrorAtLine(frames_line, StrCat("expected 'Frames: N', found ", Quote(frames_header)));
  }
  std::string_view frames_value = AfterColon(frames_header);
  long long num_frames = -1;
  {
    auto [ptr, ec] = std::from_chars(frames_value.data(), frames_value.data() + frames_value.size(), num_frames);
    if (ec != std::errc() || ptr != frames_value.data() + frames_value.size()) {
      return tokens.ErrorAtLine(frames_line,
                                StrCat("expected a whole frame count after 'Frames:', found ", Quote(frames_value)));
    }
  }
  if (num_frames < 1 || num_frames > limits.max_frames) {
    return tokens.ErrorAtLine(frames_line, StrCat("frame count ", num_frames, " outside 1..", limits.max_frames));
  }

  tokens.SkipSpace();
  const int time_line = tokens.line();
  std::string_view time_header = tokens.RestOfLine();
  if (!time_header.starts_with("Frame Time") && !time_header.starts_with("Frame\tTime")) {
    return tokens.ErrorAtLine(time_line, StrCat("expected 'Frame Time: T', found ", Quote(time_header)));
  }
  std::string_view time_value = AfterColon(time_header);
  float frame_time = 0;
  {
    const char* end = time_value.data() + time_value.size();
    if (time_value.empty() || ParseFloat(time_value.data(), end, frame_time) != end) {
      return tokens.ErrorAtLine(time_line, StrCat("expected a number after 'Frame Time:', found ", Quote(time_value)));
    }
  }
  if (!(frame_time >= limits.min_frame_time && frame_time <= limits.max_frame_time)) {
    return tokens.ErrorAtLine(time_line, StrCat("frame time ", frame_time, " s is outside ", limits.min_frame_time,
                                                "..", limits.max_frame_time, " s"));
  }
  clip.frame_time = frame_time;

  const int num_channels = clip.skeleton.num_channels();
  // Checked before allocating: every value takes at least one byte, so a declared size the text
  // cannot hold is a truncated (or hostile) file, not a reason to allocate gigabytes. (Smaller
  // shortfalls are found by the reading below, with the line where the values end.)
  const std::size_t remaining = text.size() - tokens.pos();
  if (static_cast<double>(num_frames) * num_channels > static_cast<double>(remaining)) {
    return tokens.ErrorAtLine(
        frames_line, StrCat("'Frames: ", num_frames, "' with ", num_channels, " channels needs more values than the ",
                            remaining, " bytes after the header can hold (truncated file?)"));
  }
  clip.channels.resize(num_frames, num_channels);
  std::string_view data = text.substr(tokens.pos());
  int line = tokens.line();
  const char* cursor = data.data();
  const char* const data_end = data.data() + data.size();
  for (long long frame = 0; frame < num_frames; ++frame) {
    // Skip blank lines between frames (some exporters leave them).
    const char* line_end;
    while (true) {
      if (cursor >= data_end) {
        return tokens.ErrorAtLine(line, StrCat("truncated motion block: 'Frames: ", num_frames,
                                               "' but the file ends after ", frame, " frames"));
      }
      line_end = static_cast<const char*>(memchr(cursor, '\n', data_end - cursor));
      if (line_end == nullptr) line_end = data_end;
      const char* p = cursor;
      while (p < line_end && IsSpace(*p)) ++p;
      if (p != line_end) break;
      cursor = line_end + 1;
      ++line;
    }
    float* row = clip.channels.row(frame).data();
    int count = 0;
    const char* p = cursor;
    while (true) {
      while (p < line_end && IsSpace(*p)) ++p;
      if (p >= line_end) break;
      if (count >= num_channels) {
        return tokens.ErrorAtLine(
            line, StrCat("frame ", frame, " has more than the ", num_channels, " values the hierarchy declares"));
      }
      float value;
      const char* next = ParseFloat(p, line_end, value);
      if (next == nullptr || (next < line_end && !IsSpace(*next))) {
        const char* token_end = p;
        while (token_end < line_end && !IsSpace(*token_end)) ++token_end;
        return tokens.ErrorAtLine(line,
                                  StrCat("frame ", frame, " value ", count + 1, ": expected a finite number, found ",
                                         Quote(std::string_view(p, token_end - p))));
      }
      row[count++] = value;
      p = next;
    }
    if (count != num_channels) {
      return tokens.ErrorAtLine(
          line, StrCat("frame ", frame, " has ", count, " values; the hierarchy declares ", num_channels));
    }
    cursor = line_end < data_end ? line_end + 1 : data_end;
    ++line;
  }
  for (const char* p = cursor; p < data_end; ++p) {
    if (*p == '\n') ++line;
    if (!IsSpace(*p)) {
      return tokens.ErrorAtLine(
          line, StrCat("unexpected data after the ", num_frames, " declared frames (is 'Frames:' too small?)"));
    }
  }
  NormaliseRootPosition(clip);
  return clip;
}

absl::StatusOr<BvhClip> ReadBvhFile(const std::filesystem::path& path, const BvhReadLimits& limits) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return absl::NotFoundError(StrCat(path.string(), ": cannot open file"));
  std::string text;
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) return absl::InvalidArgumentError(StrCat(path.string(), ": not a readable file"));
  text.resize(static_cast<size_t>(size));
  in.seekg(0, std::ios::beg);
  in.read(text.data(), size);
  if (!in) return absl::DataLossError(StrCat(path.string(), ": read failed"));
  return ParseBvh(text, path.string(), limits);
}

}  // namespace mocap
