// libFuzzer target: a `--query-pose` JSON file (mocap similar, mocapd similar) through the
// parser and, when it parses, the named pose's body points (METHOD.md B3–B4), as a search does.
#include <cstddef>
#include <cstdint>

#include <nlohmann/json.hpp>

#include "cli_util/similar_json.h"
#include "motion/similarity/named_pose.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nlohmann::json json = nlohmann::json::parse(data, data + size, nullptr, /*allow_exceptions=*/false);
  if (json.is_discarded()) return 0;
  absl::StatusOr<mocap::v1::NamedPose> parsed = mocap::NamedPoseFromJson(json);
  if (!parsed.ok()) return 0;
  // The proto as the server receives it, in the engine's terms.
  mocap::NamedPose pose;
  pose.up = parsed->up();
  for (const mocap::v1::NamedJoint& joint : parsed->joints()) {
    pose.joints.push_back({joint.name(), joint.parent(),
                           Eigen::Vector3f(joint.position().x(), joint.position().y(), joint.position().z())});
  }
  const mocap::v1::NamedLandmarks& l = parsed->landmarks();
  pose.pelvis = l.pelvis();
  pose.head = l.head();
  pose.left_wrist = l.left_wrist();
  pose.right_wrist = l.right_wrist();
  pose.left_ankle = l.left_ankle();
  pose.right_ankle = l.right_ankle();
  (void)mocap::NamedPosePoints(pose, {});
  return 0;
}
