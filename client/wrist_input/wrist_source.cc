#include "client/wrist_input/wrist_source.h"

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <optional>
#include <random>
#include <string>
#include <string_view>

#include "motion/bvh/bvh_reader.h"
#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/skeleton/forward_kinematics.h"

namespace mocap {
namespace {

constexpr std::array<std::string_view, 17> kCsvColumns = {
    "time",    "left_x",          "left_y",           "left_z",   "right_x", "right_y",
    "right_z", "left_confidence", "right_confidence", "left_qw",  "left_qx", "left_qy",
    "left_qz", "right_qw",        "right_qx",         "right_qy", "right_qz"};
constexpr size_t kPositionColumns = 7, kConfidenceColumns = 9;
constexpr std::string_view kCsvHeader =
    "time,left_x,left_y,left_z,right_x,right_y,right_z[,left_confidence,right_confidence"
    "[,left_qw,left_qx,left_qy,left_qz,right_qw,right_qx,right_qy,right_qz]]";

std::string_view Trim(std::string_view text) {
  const size_t begin = text.find_first_not_of(" \t");
  if (begin == std::string_view::npos) return {};
  const size_t end = text.find_last_not_of(" \t");
  return text.substr(begin, end - begin + 1);
}

std::vector<std::string_view> SplitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    fields.push_back(
        Trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) return fields;
    start = comma + 1;
  }
}

// A decimal number, "nan" or "inf" (any case, optional sign); nullopt for anything else.
std::optional<double> ParseNumber(std::string_view text) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty() || text.front() == '+') return std::nullopt;
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

}  // namespace

absl::StatusOr<std::vector<v1::WristSample>> WristsFromCsv(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) return absl::NotFoundError(StrCat(path.string(), ": cannot read the file"));
  return WristsFromCsv(in, path.string());
}

absl::StatusOr<std::vector<v1::WristSample>> WristsFromCsv(std::istream& in, const std::string& name) {
  std::vector<v1::WristSample> samples;
  size_t columns = 0;  // 0 until the header has been read
  std::string line;
  for (int line_number = 1; std::getline(in, line); ++line_number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string_view text = Trim(line);
    if (text.empty() || text.front() == '#') continue;
    const std::vector<std::string_view> fields = SplitFields(text);
    if (columns == 0) {
      const bool names_match = [&] {
        if (fields.size() > kCsvColumns.size()) return false;  // (a longer header read past the names)
        for (size_t i = 0; i < fields.size(); ++i) {
          if (fields[i] != kCsvColumns[i]) return false;
        }
        return true;
      }();
      if ((fields.size() != kPositionColumns && fields.size() != kConfidenceColumns &&
           fields.size() != kCsvColumns.size()) ||
          !names_match) {
        return absl::InvalidArgumentError(
            StrCat(name, ":", line_number, ": expected the header ", kCsvHeader, ", found \"", text, "\""));
      }
      columns = fields.size();
      continue;
    }
    if (fields.size() != columns) {
      return absl::InvalidArgumentError(
          StrCat(name, ":", line_number, ": expected ", columns, " fields as in the header, found ", fields.size()));
    }
    std::array<double, kCsvColumns.size()> values{};
    std::array<bool, kCsvColumns.size()> present{};
    for (size_t i = 0; i < columns; ++i) {
      if (i >= kPositionColumns && fields[i].empty()) continue;  // confidence or orientation left unset
      const std::optional<double> value = ParseNumber(fields[i]);
      if (!value) {
        return absl::InvalidArgumentError(
            StrCat(name, ":", line_number, ": ", kCsvColumns[i], " is not a number: \"", fields[i], "\""));
      }
      if (i >= kPositionColumns && i < kConfidenceColumns && std::isfinite(*value) && (*value < 0.0 || *value > 1.0)) {
        return absl::InvalidArgumentError(
            StrCat(name, ":", line_number, ": ", kCsvColumns[i], " must lie in 0..1, found ", fields[i]));
      }
      values[i] = *value;
      present[i] = true;
    }
    v1::WristSample& sample = samples.emplace_back();
    sample.set_time(values[0]);
    sample.mutable_left()->set_x(static_cast<float>(values[1]));
    sample.mutable_left()->set_y(static_cast<float>(values[2]));
    sample.mutable_left()->set_z(static_cast<float>(values[3]));
    sample.mutable_right()->set_x(static_cast<float>(values[4]));
    sample.mutable_right()->set_y(static_cast<float>(values[5]));
    sample.mutable_right()->set_z(static_cast<float>(values[6]));
    if (present[7]) sample.set_left_confidence(static_cast<float>(values[7]));
    if (present[8]) sample.set_right_confidence(static_cast<float>(values[8]));
    for (int side = 0; side < 2; ++side) {
      const size_t first = kConfidenceColumns + 4 * side;
      if (!present[first] && !present[first + 1] && !present[first + 2] && !present[first + 3]) continue;
      v1::Quaternion* q = side == 0 ? sample.mutable_left_orientation() : sample.mutable_right_orientation();
      q->set_w(static_cast<float>(values[first]));
      q->set_x(static_cast<float>(values[first + 1]));
      q->set_y(static_cast<float>(values[first + 2]));
      q->set_z(static_cast<float>(values[first + 3]));
    }
  }
  if (in.bad()) return absl::DataLossError(StrCat(name, ": read error"));
  if (columns == 0) return absl::InvalidArgumentError(StrCat(name, ": empty file, expected the header ", kCsvHeader));
  if (samples.empty()) return absl::InvalidArgumentError(StrCat(name, ": no samples after the header"));
  return samples;
}

absl::StatusOr<std::vector<v1::WristSample>> WristsFromBvh(const std::filesystem::path& path, double noise_cm,
                                                           unsigned seed) {
  if (!std::isfinite(noise_cm) || noise_cm < 0.0) {
    return absl::InvalidArgumentError(StrCat("noise must be a finite number of centimetres >= 0, got ", noise_cm));
  }
  MOCAP_ASSIGN_OR_RETURN(BvhClip clip, ReadBvhFile(path));
  const PreprocessOptions options{.frame_rate = clip.frame_rate()};
  absl::StatusOr<RigModel> rig = BuildRigModel(clip, options);
  if (!rig.ok()) return absl::Status(rig.status().code(), StrCat(path.string(), ": ", rig.status().message()));
  absl::StatusOr<PreparedClip> prepared = PrepareClip(clip, *rig, options);
  if (!prepared.ok()) {
    return absl::Status(prepared.status().code(), StrCat(path.string(), ": ", prepared.status().message()));
  }
  const GlobalPoses poses = ForwardKinematics(prepared->skeleton, prepared->motion);
  const BodyLandmarks& landmarks = rig->topology.landmarks;

  std::mt19937 random(seed);
  std::normal_distribution<float> noise(0.0f, static_cast<float>(noise_cm / 100.0));
  std::vector<v1::WristSample> samples;
  samples.reserve(poses.num_frames());
  for (int f = 0; f < poses.num_frames(); ++f) {
    Eigen::Vector3f left = poses.position(f, landmarks.left_wrist);
    Eigen::Vector3f right = poses.position(f, landmarks.right_wrist);
    if (noise_cm > 0) {
      for (int axis = 0; axis < 3; ++axis) {
        left[axis] += noise(random);
        right[axis] += noise(random);
      }
    }
    v1::WristSample& sample = samples.emplace_back();
    sample.set_time(f * prepared->motion.frame_time);
    sample.mutable_left()->set_x(left.x());
    sample.mutable_left()->set_y(left.y());
    sample.mutable_left()->set_z(left.z());
    sample.mutable_right()->set_x(right.x());
    sample.mutable_right()->set_y(right.y());
    sample.mutable_right()->set_z(right.z());
  }
  return samples;
}

std::array<double, 3> RecenterHorizontally(std::vector<v1::WristSample>* samples, int up_axis) {
  auto get = [](const v1::Vec3& v, int axis) { return axis == 0 ? v.x() : axis == 1 ? v.y() : v.z(); };
  std::array<double, 3> offset{0, 0, 0};
  for (const v1::WristSample& s : *samples) {
    bool finite = true;
    for (int axis = 0; axis < 3; ++axis)
      finite = finite && std::isfinite(get(s.left(), axis)) && std::isfinite(get(s.right(), axis));
    if (!finite) continue;
    for (int axis = 0; axis < 3; ++axis) {
      if (axis != up_axis) offset[axis] = 0.5 * (get(s.left(), axis) + get(s.right(), axis));
    }
    break;
  }
  for (v1::WristSample& s : *samples) {
    for (v1::Vec3* v : {s.mutable_left(), s.mutable_right()}) {
      v->set_x(v->x() - offset[0]);
      v->set_y(v->y() - offset[1]);
      v->set_z(v->z() - offset[2]);
    }
  }
  return offset;
}

}  // namespace mocap
