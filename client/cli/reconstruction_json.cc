#include "client/cli/reconstruction_json.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>

#include "client/cli/cli_common.h"

namespace mocap::cli {
namespace {

// The frames field of the top-level object as Json() prints it empty: one space of indent per
// level, so this text is the top level's alone.
constexpr std::string_view kEmptyFrames = "\n \"frames\": []";
// A frame's rotations field the same way, at the frame's top level.
constexpr std::string_view kEmptyRotations = "\n \"rotations\": []";

// One frame's text as an element of the top-level array: every line two levels deeper.
void AppendIndentedElement(std::string_view text, std::string& out) {
  while (!text.empty() && text.back() == '\n') text.remove_suffix(1);
  size_t begin = 0;
  while (begin <= text.size()) {
    const size_t end = std::min(text.find('\n', begin), text.size());
    out += begin == 0 ? "  " : "\n  ";
    out += text.substr(begin, end - begin);
    begin = end + 1;
  }
}

// A frame's rotations as Json() prints them in the frame's text: fields in their proto order, one
// per line, the frame's fields one space in.
void AppendRotations(const google::protobuf::RepeatedPtrField<v1::Quaternion>& rotations, std::string& out) {
  out += "\n \"rotations\": [";
  for (int i = 0; i < rotations.size(); ++i) {
    const v1::Quaternion& q = rotations.Get(i);
    out += i == 0 ? "\n  {\n   \"w\": " : ",\n  {\n   \"w\": ";
    AppendJsonFloat(q.w(), out);
    out += ",\n   \"x\": ";
    AppendJsonFloat(q.x(), out);
    out += ",\n   \"y\": ";
    AppendJsonFloat(q.y(), out);
    out += ",\n   \"z\": ";
    AppendJsonFloat(q.z(), out);
    out += "\n  }";
  }
  out += rotations.empty() ? "]" : "\n ]";
}

// The frame's text, its rotations written apart from the printer.
absl::Status AppendFrame(v1::Frame& frame, std::string& text, std::string& out) {
  google::protobuf::RepeatedPtrField<v1::Quaternion> rotations;
  rotations.Swap(frame.mutable_rotations());
  const std::string head = Json(frame);
  frame.mutable_rotations()->Swap(&rotations);
  const size_t at = head.find(kEmptyRotations);
  if (at == std::string::npos) return absl::InternalError("no rotations field in a frame's JSON");
  text.assign(head, 0, at);
  AppendRotations(frame.rotations(), text);
  text.append(head, at + kEmptyRotations.size());
  AppendIndentedElement(text, out);
  return absl::OkStatus();
}

}  // namespace

void AppendJsonFloat(float value, std::string& out) {
  if (std::isnan(value)) {
    out += "\"NaN\"";
    return;
  }
  if (std::isinf(value)) {
    out += value > 0 ? "\"Infinity\"" : "\"-Infinity\"";
    return;
  }
  // %.*g's digits, as std::to_chars gives them for a precision (the float's exact value rounded).
  // protobuf reads them back with strtof, which calls a subnormal result a range error.
  char buffer[32];
  auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::general, 6);
  float read_back = 0;
  const auto [_, read_ec] = std::from_chars(buffer, end, read_back);
  if (ec != std::errc() || read_ec != std::errc() || read_back != value || std::fpclassify(read_back) == FP_SUBNORMAL) {
    end = std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::general, 9).ptr;
  }
  out.append(buffer, end);
}

absl::Status WriteReconstructionJson(const std::filesystem::path& path, const v1::ReconstructTrajectoryResponse& answer,
                                     std::vector<v1::Frame>& frames) {
  if (answer.frames_size() > 0) return absl::InvalidArgumentError("the answer's frames are written apart");
  const std::string rest = Json(answer);
  const size_t at = rest.find(kEmptyFrames);
  if (at == std::string::npos) return absl::InternalError("no top-level frames field in the answer's JSON");
  std::ofstream out(path, std::ios::binary);
  out << std::string_view(rest).substr(0, at) << "\n \"frames\": [";
  std::string text, element;  // reused: a frame on a large rig is tens of kilobytes
  for (size_t i = 0; i < frames.size(); ++i) {
    element.assign(i == 0 ? "\n" : ",\n");
    if (absl::Status s = AppendFrame(frames[i], text, element); !s.ok()) return s;
    out << element;
  }
  out << (frames.empty() ? "]" : "\n ]") << std::string_view(rest).substr(at + kEmptyFrames.size());
  if (!out) return absl::DataLossError("cannot write " + path.string());
  return absl::OkStatus();
}

}  // namespace mocap::cli
