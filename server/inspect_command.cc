#include "server/inspect_command.h"

#include <sstream>

#include "motion/bvh/bvh_reader.h"
#include "motion/core/status_macros.h"
#include "motion/skeleton/body_topology.h"
#include "motion/skeleton/local_motion.h"

namespace mocap {
namespace {

std::string AxisName(int axis, int sign) {
  return std::string(sign > 0 ? "+" : "-") + static_cast<char>('X' + axis);
}

}  // namespace

absl::StatusOr<nlohmann::json> InspectBvhFile(const std::string& path, const InspectOptions& options) {
  MOCAP_ASSIGN_OR_RETURN(BvhClip clip, ReadBvhFile(path));
  const LocalMotion motion = MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time);
  absl::StatusOr<BodyTopology> analysed = AnalyseBody(clip.skeleton, motion, BodyTopologyOptions{.unit = options.unit});
  if (!analysed.ok()) {
    return absl::Status(analysed.status().code(), path + ": " + std::string(analysed.status().message()));
  }
  const BodyTopology& topology = *analysed;
  const Skeleton& skeleton = clip.skeleton;
  const double metres = MetresPerUnit(topology.unit);
  nlohmann::json report;
  report["file"] = path;
  report["joints"] = skeleton.num_joints();
  report["channels"] = skeleton.num_channels();
  report["frames"] = clip.num_frames();
  report["frame_rate"] = clip.frame_rate();
  report["duration_s"] = (clip.num_frames() - 1) * clip.frame_time;
  report["root"] = skeleton.joint(0).name;
  report["up_axis"] = AxisName(topology.up_axis, topology.up_sign);
  report["up_alignment"] = topology.up_alignment;
  report["rest_pose_up_axis"] = AxisName(topology.rest_up_axis, topology.rest_up_sign);
  report["forward"] = {topology.forward.x(), topology.forward.y(), topology.forward.z()};
  report["units"] = {{"unit", std::string(UnitName(topology.unit))},
                     {"detected", topology.unit_detected}};
  report["body"] = {{"leg_length_m", topology.leg_length * metres},
                    {"standing_pelvis_height_m", topology.standing_pelvis_height * metres},
                    {"floor_height_m", topology.floor_height * metres}};
  const BodyLandmarks& l = topology.landmarks;
  auto name = [&](int joint) { return skeleton.joint(joint).name; };
  report["landmarks"] = {{"pelvis", name(l.pelvis)},          {"head", name(l.head)},
                         {"left_wrist", name(l.left_wrist)},  {"right_wrist", name(l.right_wrist)},
                         {"left_ankle", name(l.left_ankle)},  {"right_ankle", name(l.right_ankle)}};
  nlohmann::json groups = nlohmann::json::object();
  for (int g = 0; g < kNumBodyGroups; ++g) groups[std::string(BodyGroupName(static_cast<BodyGroup>(g)))] = nlohmann::json::array();
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    groups[std::string(BodyGroupName(topology.group_of_joint[j]))].push_back(name(j));
  }
  report["groups"] = groups;
  return report;
}

std::string FormatInspection(const nlohmann::json& r) {
  std::ostringstream out;
  out << r["file"].get<std::string>() << "\n"
      << "  joints " << r["joints"] << ", channels " << r["channels"] << ", root " << r["root"].get<std::string>() << "\n"
      << "  frames " << r["frames"] << " at " << r["frame_rate"].get<double>() << " fps ("
      << r["duration_s"].get<double>() << " s)\n"
      << "  up axis " << r["up_axis"].get<std::string>() << " (alignment " << r["up_alignment"].get<double>()
      << "; rest pose " << r["rest_pose_up_axis"].get<std::string>() << ")\n"
      << "  units " << r["units"]["unit"].get<std::string>() << (r["units"]["detected"].get<bool>() ? " (detected)" : " (given)")
      << ", leg length " << r["body"]["leg_length_m"].get<double>() << " m, standing pelvis height "
      << r["body"]["standing_pelvis_height_m"].get<double>() << " m\n"
      << "  landmarks:";
  for (const auto& [key, value] : r["landmarks"].items()) out << " " << key << "=" << value.get<std::string>();
  out << "\n  groups:\n";
  for (const auto& [key, value] : r["groups"].items()) {
    out << "    " << key << " (" << value.size() << "):";
    for (const auto& joint : value) out << " " << joint.get<std::string>();
    out << "\n";
  }
  return out.str();
}

}  // namespace mocap
