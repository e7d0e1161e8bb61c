#include "motion/reconstruct/reconstruction_export.h"

#include <algorithm>

#include "motion/core/units.h"
#include "motion/skeleton/local_motion.h"

namespace mocap {
namespace {

// All three: a joint with only some of them keeps the rest of its translation from its OFFSET (and
// Blender reads a missing one as 0), so it could not carry a translation that moves freely.
bool HasAllPositionChannels(const Joint& joint) {
  bool axes[3] = {false, false, false};
  for (ChannelType c : joint.channels) {
    if (!IsRotation(c)) axes[ChannelAxis(c)] = true;
  }
  return axes[0] && axes[1] && axes[2];
}

}  // namespace

Skeleton WithPelvisPositionChannels(const Skeleton& skeleton, int pelvis) {
  if (pelvis <= 0 || pelvis >= skeleton.num_joints() || HasAllPositionChannels(skeleton.joint(pelvis))) return skeleton;
  std::vector<Joint> joints = skeleton.joints();
  std::vector<ChannelType>& channels = joints[pelvis].channels;
  channels.erase(std::remove_if(channels.begin(), channels.end(), [](ChannelType c) { return !IsRotation(c); }),
                 channels.end());
  channels.insert(channels.begin(), {ChannelType::kXposition, ChannelType::kYposition, ChannelType::kZposition});
  return Skeleton(std::move(joints));
}

void HoldJointsAbovePelvis(const Skeleton& skeleton, int pelvis, const std::vector<Eigen::Quaternionf>& held_rotations,
                           const Eigen::Vector3f& root_offset, LocalMotion& motion) {
  if (pelvis <= 0 || pelvis >= skeleton.num_joints() || !HasAllPositionChannels(skeleton.joint(pelvis))) return;
  std::vector<int> chain;  // root first, pelvis last
  for (int j = pelvis; j >= 0; j = skeleton.parent(j)) chain.insert(chain.begin(), j);
  for (int f = 0; f < motion.num_frames(); ++f) {
    Eigen::Quaternionf world_rotation = Eigen::Quaternionf::Identity(), held_rotation = world_rotation;
    Eigen::Vector3f world_position = Eigen::Vector3f::Zero(), held_position = world_position;
    for (int j : chain) {
      world_position += world_rotation * motion.translation(f, j);
      world_rotation = (world_rotation * motion.rotation(f, j)).normalized();
      if (j == pelvis) break;
      const Eigen::Vector3f translation = j == 0 ? root_offset : motion.translation(f, j);
      const Eigen::Quaternionf rotation = held_rotations[j];
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

BvhClip ReconstructionToBvh(const ReconstructionDatabase& database, const std::vector<ReconstructedFrame>& frames) {
  const BodyModel& body = database.body();
  std::vector<BodyPose> poses;
  poses.reserve(frames.size());
  for (const ReconstructedFrame& frame : frames) poses.push_back(frame.pose);
  LocalMotion motion = body.ToLocalMotion(poses, database.frame_time());
  const RigModel& rig = database.rig();
  // The rig's hierarchy, offsets and channels as imported, with position channels on a pelvis
  // below other joints that has none (cmu-cc's CC_Base_Hip), so that it carries the motion.
  const Skeleton skeleton = WithPelvisPositionChannels(rig.skeleton, rig.topology.landmarks.pelvis);
  // The rig's reference rotations (the root's includes the turn to Y up), the root at its OFFSET.
  HoldJointsAbovePelvis(skeleton, rig.topology.landmarks.pelvis, rig.reference_rotations,
                        rig.to_y_up * (rig.skeleton.joint(0).offset * static_cast<float>(MetresPerUnit(rig.unit))),
                        motion);
  // Back to the file's world: undo the Y-up rotation and the conversion to metres.
  RotateWorld(motion, database.rig().to_y_up.conjugate());
  ScaleTranslations(motion, static_cast<float>(1.0 / MetresPerUnit(database.rig().unit)));
  BvhClip clip;
  clip.skeleton = skeleton;
  clip.frame_time = database.frame_time();
  // Joints without position channels take their translation from the OFFSET: use the body's.
  std::vector<Joint> joints = clip.skeleton.joints();
  for (int j = 1; j < static_cast<int>(joints.size()); ++j) joints[j].offset = motion.translation(0, j);
  clip.skeleton = Skeleton(std::move(joints));
  clip.channels = ChannelsFromMotion(clip.skeleton, motion);
  return clip;
}

}  // namespace mocap
