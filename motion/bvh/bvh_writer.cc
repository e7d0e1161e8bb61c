#include "motion/bvh/bvh_writer.h"

#include <charconv>
#include <fstream>
#include <system_error>

#include "motion/bvh/root_convention.h"
#include "motion/core/str_cat.h"

namespace mocap {
namespace {

void AppendFloat(std::string& out, double value) {
  char buffer[32];
  auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, end);
}
void AppendFloat(std::string& out, float value) {
  char buffer[32];
  if (value == 0.0f) value = 0.0f;  // no "-0"
  auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, end);
}

void AppendVector(std::string& out, const Eigen::Vector3f& v) {
  for (int axis = 0; axis < 3; ++axis) {
    out += ' ';
    AppendFloat(out, v[axis]);
  }
}

void AppendJoint(std::string& out, const Skeleton& skeleton, int index, int depth) {
  const Joint& joint = skeleton.joint(index);
  const std::string indent(depth, '\t');
  out += indent;
  out += index == 0 ? "ROOT " : "JOINT ";
  out += joint.name;
  out += '\n';
  out += indent + "{\n";
  out += indent + "\tOFFSET";
  AppendVector(out, joint.offset);
  out += '\n';
  if (!joint.channels.empty() || index == 0) {
    out += indent + "\tCHANNELS " + std::to_string(joint.channels.size());
    for (ChannelType channel : joint.channels) (out += " ") += ChannelName(channel);
    out += '\n';
  }
  for (int child : skeleton.Children(index)) AppendJoint(out, skeleton, child, depth + 1);
  if (joint.end_site) {
    out += indent + "\tEnd Site\n" + indent + "\t{\n" + indent + "\t\tOFFSET";
    AppendVector(out, *joint.end_site);
    out += '\n' + indent + "\t}\n";
  }
  out += indent + "}\n";
}

}  // namespace

std::string FormatBvh(const BvhClip& clip) {
  // Files that every reader places alike (root_convention.h).
  if (!ReadersAgreeOn(clip)) {
    BvhClip agreed = clip;
    MakeReadersAgree(agreed);
    return FormatBvh(agreed);
  }
  std::string out = "HIERARCHY\n";
  if (clip.skeleton.num_joints() > 0) AppendJoint(out, clip.skeleton, 0, 0);
  out += StrCat("MOTION\nFrames: ", clip.num_frames(), "\nFrame Time: ");
  AppendFloat(out, clip.frame_time);
  out += '\n';
  // Values follow the hierarchy as written (depth first), whatever the skeleton's own order.
  std::vector<int> columns;
  std::vector<int> stack = {0};
  while (!stack.empty() && clip.skeleton.num_joints() > 0) {
    const int joint = stack.back();
    stack.pop_back();
    const int start = clip.skeleton.channel_start(joint);
    for (size_t c = 0; c < clip.skeleton.joint(joint).channels.size(); ++c)
      columns.push_back(start + static_cast<int>(c));
    const std::vector<int> children = clip.skeleton.Children(joint);
    stack.insert(stack.end(), children.rbegin(), children.rend());
  }
  out.reserve(out.size() + static_cast<size_t>(clip.channels.size()) * 12);
  for (int frame = 0; frame < clip.num_frames(); ++frame) {
    for (size_t i = 0; i < columns.size(); ++i) {
      if (i > 0) out += ' ';
      AppendFloat(out, clip.channels(frame, columns[i]));
    }
    out += '\n';
  }
  return out;
}

absl::Status WriteBvhFile(const BvhClip& clip, const std::filesystem::path& path) {
  const std::filesystem::path temporary = path.string() + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) return absl::PermissionDeniedError(StrCat(path.string(), ": cannot create file"));
    const std::string text = FormatBvh(clip);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    if (!out) return absl::DataLossError(StrCat(path.string(), ": write failed"));
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) return absl::InternalError(StrCat(path.string(), ": ", error.message()));
  return absl::OkStatus();
}

}  // namespace mocap
