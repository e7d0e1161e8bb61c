#include "motion/retarget/retarget_clip.h"

#include <vector>

#include "motion/core/status_macros.h"
#include "motion/retarget/retarget_export.h"
#include "motion/retarget/retargeter.h"
#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/local_motion.h"

namespace mocap {

absl::StatusOr<BvhClip> RetargetClipOntoRig(const BvhClip& clip, const RigModel& rig,
                                            std::optional<LengthUnit> clip_unit) {
  MOCAP_ASSIGN_OR_RETURN(RetargetRig source, TargetRigFromClip(clip, clip_unit));
  // The database's body in metres (as the reconstruction animates it), written back in its file's
  // unit and axes.
  std::vector<Joint> joints = rig.skeleton.joints();
  const float metres = static_cast<float>(MetresPerUnit(rig.unit));
  for (Joint& joint : joints) {
    joint.offset *= metres;
    if (joint.end_site) *joint.end_site *= metres;
  }
  MOCAP_ASSIGN_OR_RETURN(RetargetRig target, SourceRigOf(rig, Skeleton(std::move(joints))));
  MOCAP_ASSIGN_OR_RETURN(Retargeter retargeter, Retargeter::Create(std::move(source), std::move(target)));

  // The clip's world transforms in metres, Y up: what the retargeter reads.
  LocalMotion motion = MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time);
  ScaleTranslations(motion, static_cast<float>(MetresPerUnit(retargeter.source().unit)));
  RotateWorld(motion, retargeter.source().to_y_up);
  const GlobalPoses world = ForwardKinematics(clip.skeleton, motion);
  const int num_joints = clip.skeleton.num_joints();
  std::vector<Eigen::Quaternionf> rotations(num_joints);
  std::vector<Eigen::Vector3f> positions(num_joints);
  std::vector<BodyPose> poses(clip.num_frames());
  for (int f = 0; f < clip.num_frames(); ++f) {
    for (int j = 0; j < num_joints; ++j) {
      rotations[j] = world.rotation(f, j);
      positions[j] = world.position(f, j);
    }
    retargeter.Retarget(rotations, positions, &poses[f]);
  }
  return RetargetedToBvh(retargeter.target(), poses, clip.frame_time);
}

}  // namespace mocap
