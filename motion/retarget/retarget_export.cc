#include "motion/retarget/retarget_export.h"

#include "motion/preprocess/clip_preprocessor.h"
#include "motion/reconstruct/reconstruction_export.h"
#include "motion/skeleton/local_motion.h"

namespace mocap {

BvhClip RetargetedToBvh(const RetargetRig& target, const std::vector<BodyPose>& poses, double frame_time) {
  const Skeleton& skeleton = target.skeleton;
  const int joints = skeleton.num_joints();
  LocalMotion motion;
  motion.frame_time = frame_time;
  motion.Resize(static_cast<int>(poses.size()), joints);
  for (int f = 0; f < static_cast<int>(poses.size()); ++f) {
    for (int j = 0; j < joints; ++j) {
      motion.SetRotation(f, j, poses[f].rotations[j]);
      motion.SetTranslation(f, j, j == 0 ? poses[f].root_position : skeleton.joint(j).offset);
    }
  }
  // The rest pose is the file's: joints above the pelvis hold it, the root's turned to Y up.
  std::vector<Eigen::Quaternionf> held(joints, Eigen::Quaternionf::Identity());
  held[0] = target.to_y_up;
  HoldJointsAbovePelvis(skeleton, target.topology.landmarks.pelvis, held, target.to_y_up * skeleton.joint(0).offset,
                        motion);
  // Back to the file's world: undo the Y-up rotation and the conversion to metres.
  return ToFileConventions(skeleton, std::move(motion), target.to_y_up, target.unit);
}

}  // namespace mocap
