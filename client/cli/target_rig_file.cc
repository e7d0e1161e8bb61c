#include "client/cli/target_rig_file.h"

#include <fstream>
#include <sstream>

#include "motion/bvh/bvh_writer.h"
#include "motion/reconstruct/reconstruction_export.h"
#include "motion/retarget/retarget_export.h"

namespace mocap::cli {

absl::StatusOr<std::string> TargetRigText(const std::string& path, size_t max_bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return absl::NotFoundError("cannot read " + path);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  const size_t motion = text.find("MOTION");
  if (motion == std::string::npos)
    return text.size() <= max_bytes ? absl::StatusOr<std::string>(text)
                                    : absl::InvalidArgumentError(path + ": hierarchy too large");
  // Keep "Frame Time" and as many whole frame lines as fit.
  std::istringstream lines(text.substr(motion));
  std::string line, frame_time, frames;
  int kept = 0;
  const size_t budget = max_bytes > motion + 200 ? max_bytes - motion - 200 : 0;
  while (std::getline(lines, line)) {
    if (line.rfind("Frame Time", 0) == 0) {
      frame_time = line;
    } else if (!frame_time.empty() && line.find_first_not_of(" \t\r") != std::string::npos) {
      if (kept >= 2000 || frames.size() + line.size() + 1 > budget) break;
      frames += line + "\n";
      ++kept;
    }
  }
  if (frame_time.empty()) return absl::InvalidArgumentError(path + ": MOTION section without a Frame Time line");
  return text.substr(0, motion) + "MOTION\nFrames: " + std::to_string(kept) + "\n" + frame_time + "\n" + frames;
}

absl::StatusOr<std::string> RetargetedBvhText(const std::string& target_rig_text, const v1::SessionStarted& started,
                                              const std::vector<v1::Frame>& frames) {
  absl::StatusOr<RetargetRig> rig = TargetRigFromBvh(target_rig_text);
  if (!rig.ok()) return rig.status();
  const int joints = rig->skeleton.num_joints();
  if (started.skeleton().joints_size() != joints) {
    return absl::InvalidArgumentError("the session's skeleton has " + std::to_string(started.skeleton().joints_size()) +
                                      " joints, the target rig " + std::to_string(joints));
  }
  std::vector<BodyPose> poses(frames.size());
  for (size_t f = 0; f < frames.size(); ++f) {
    if (frames[f].rotations_size() != joints) {
      return absl::InvalidArgumentError("frame " + std::to_string(frames[f].index()) + " has " +
                                        std::to_string(frames[f].rotations_size()) + " rotations for " +
                                        std::to_string(joints) + " joints");
    }
    const v1::Vec3& root = frames[f].root_position();
    poses[f].root_position = Eigen::Vector3f(root.x(), root.y(), root.z());
    for (const v1::Quaternion& q : frames[f].rotations()) {
      poses[f].rotations.push_back(Eigen::Quaternionf(q.w(), q.x(), q.y(), q.z()).normalized());
    }
  }
  const double frame_time = started.frame_rate() > 0 ? 1.0 / started.frame_rate() : 1.0 / 30.0;
  // A pelvis under other joints without position channels of its own (cmu-cc's CC_Base_Hip under
  // RL_BoneRoot) gets them: it carries the motion and the root stays at rest at its OFFSET, where
  // it would otherwise wander with the body (RetargetedToBvh, HoldJointsAbovePelvis).
  rig->skeleton = WithPelvisPositionChannels(rig->skeleton, rig->topology.landmarks.pelvis);
  return FormatBvh(RetargetedToBvh(*rig, poses, frame_time));
}

}  // namespace mocap::cli
