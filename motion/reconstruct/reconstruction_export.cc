#include "motion/reconstruct/reconstruction_export.h"

#include "motion/core/units.h"
#include "motion/skeleton/local_motion.h"

namespace mocap {

BvhClip ReconstructionToBvh(const ReconstructionDatabase& database, const std::vector<ReconstructedFrame>& frames) {
  const BodyModel& body = database.body();
  std::vector<BodyPose> poses;
  poses.reserve(frames.size());
  for (const ReconstructedFrame& frame : frames) poses.push_back(frame.pose);
  LocalMotion motion = body.ToLocalMotion(poses, database.frame_time());
  // Back to the file's world: undo the Y-up rotation and the conversion to metres.
  RotateWorld(motion, database.rig().to_y_up.conjugate());
  ScaleTranslations(motion, static_cast<float>(1.0 / MetresPerUnit(database.rig().unit)));
  BvhClip clip;
  clip.skeleton = database.rig().skeleton;  // the rig's hierarchy, offsets and channels as imported
  clip.frame_time = database.frame_time();
  // Joints without position channels take their translation from the OFFSET: use the body's.
  std::vector<Joint> joints = clip.skeleton.joints();
  for (int j = 1; j < static_cast<int>(joints.size()); ++j) joints[j].offset = motion.translation(0, j);
  clip.skeleton = Skeleton(std::move(joints));
  clip.channels = ChannelsFromMotion(clip.skeleton, motion);
  return clip;
}

}  // namespace mocap
