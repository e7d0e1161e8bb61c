#include "motion/reconstruct/reconstruction_export.h"

#include <algorithm>

#include "motion/core/units.h"
#include "motion/skeleton/local_motion.h"

namespace mocap {
namespace {

bool HasPositionChannels(const Joint& joint) {
  return std::any_of(joint.channels.begin(), joint.channels.end(), [](ChannelType c) {
    return c == ChannelType::kXposition || c == ChannelType::kYposition || c == ChannelType::kZposition;
  });
}

// Joints above the pelvis (Bandai's joint_Root, an RL_BoneRoot) are bookkeeping nodes that the
// capture keeps still, with the pelvis carrying the motion in its position channels. The body
// model moves them instead (it places the root from the pelvis through fixed offsets), which in a
// viewer shows a root wandering metres away and under the floor. Where the pelvis has position
// channels, hold those joints at their rest transform (the rig's reference rotations and offsets,
// root at its OFFSET as in the capture) and give the pelvis its world motion relative to them.
// World positions of every body joint are unchanged. `motion` is in metres, Y up.
void HoldJointsAbovePelvis(const RigModel& rig, LocalMotion& motion) {
  const Skeleton& skeleton = rig.skeleton;
  const int pelvis = rig.topology.landmarks.pelvis;
  if (pelvis <= 0 || !HasPositionChannels(skeleton.joint(pelvis))) return;
  std::vector<int> chain;  // root first, pelvis last
  for (int j = pelvis; j >= 0; j = skeleton.parent(j)) chain.insert(chain.begin(), j);
  const Eigen::Vector3f root_offset =
      rig.to_y_up * (skeleton.joint(0).offset * static_cast<float>(MetresPerUnit(rig.unit)));
  for (int f = 0; f < motion.num_frames(); ++f) {
    Eigen::Quaternionf world_rotation = Eigen::Quaternionf::Identity(), held_rotation = world_rotation;
    Eigen::Vector3f world_position = Eigen::Vector3f::Zero(), held_position = world_position;
    for (int j : chain) {
      world_position += world_rotation * motion.translation(f, j);
      world_rotation = (world_rotation * motion.rotation(f, j)).normalized();
      if (j == pelvis) break;
      const Eigen::Vector3f translation = j == 0 ? root_offset : motion.translation(f, j);
      const Eigen::Quaternionf rotation = rig.reference_rotations[j];  // the root's includes the turn to Y up
      held_position += held_rotation * translation;
      held_rotation = (held_rotation * rotation).normalized();
      motion.SetTranslation(f, j, translation);
      motion.SetRotation(f, j, rotation);
    }
    const Eigen::Quaternionf to_held = held_rotation.conjugate();
    motion.SetRotation(f, pelvis, (to_held * world_rotation).normalized());
    motion.SetTranslation(f, pelvis, to_held * (world_position - held_position));
  }
}

}  // namespace

BvhClip ReconstructionToBvh(const ReconstructionDatabase& database, const std::vector<ReconstructedFrame>& frames) {
  const BodyModel& body = database.body();
  std::vector<BodyPose> poses;
  poses.reserve(frames.size());
  for (const ReconstructedFrame& frame : frames) poses.push_back(frame.pose);
  LocalMotion motion = body.ToLocalMotion(poses, database.frame_time());
  HoldJointsAbovePelvis(database.rig(), motion);
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
