#include "client/cli/reconstruction_bvh.h"

#include "motion/bvh/bvh_writer.h"
#include "motion/reconstruct/reconstruction_export.h"
#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/local_motion.h"

namespace mocap::cli {
namespace {

Eigen::Vector3f FromProto(const v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }

// `scale`: every bone times it (Frame.body_scale).
Skeleton SkeletonFromProto(const v1::Skeleton& skeleton, float scale) {
  using C = ChannelType;
  std::vector<Joint> joints;
  for (const v1::Joint& joint : skeleton.joints()) {
    Joint out;
    out.name = joint.name();
    out.parent = joint.parent();
    out.offset = scale * FromProto(joint.offset());
    out.channels = {C::kZrotation, C::kXrotation, C::kYrotation};
    if (out.parent < 0) out.channels.insert(out.channels.begin(), {C::kXposition, C::kYposition, C::kZposition});
    if (joint.has_end_site()) out.end_site = scale * FromProto(joint.end_site());
    joints.push_back(std::move(out));
  }
  // BVH readers expect every leaf to end in an End Site.
  std::vector<bool> has_child(joints.size(), false);
  for (const Joint& joint : joints) {
    if (joint.parent >= 0) has_child[joint.parent] = true;
  }
  for (size_t j = 0; j < joints.size(); ++j) {
    if (!has_child[j] && !joints[j].end_site) joints[j].end_site = Eigen::Vector3f::Zero();
  }
  return Skeleton(std::move(joints));
}

}  // namespace

absl::StatusOr<std::string> ReconstructionBvh(const v1::SessionStarted& started, const std::vector<v1::Frame>& frames) {
  // A stream that learned the performer's size (Frame.body_scale) grew its bones on the way; a
  // BVH has one skeleton: the size reached at the end.
  const float final_scale = frames.empty() ? 1.0f : BodyScale(frames.back());
  BvhClip clip;
  clip.skeleton = SkeletonFromProto(started.skeleton(), final_scale);
  if (absl::Status valid = clip.skeleton.Validate(); !valid.ok()) return valid;
  clip.frame_time = started.frame_rate() > 0 ? 1.0 / started.frame_rate() : 1.0 / 30.0;
  const int joints = clip.skeleton.num_joints();
  // Joints above the pelvis (Bandai's joint_Root, an RL_BoneRoot) are placed by the frames through
  // the rig's offsets, and the pelvis OFFSET is where the database's first clip started: written
  // as they come, the root wanders metres from the body and under the floor. The pelvis gets
  // position channels and carries the motion; the root stays at the origin.
  const int pelvis = started.skeleton().has_landmarks() ? started.skeleton().landmarks().pelvis() : 0;
  const bool hold_root = pelvis > 0 && pelvis < joints;
  if (hold_root) clip.skeleton = WithPelvisPositionChannels(clip.skeleton, pelvis);
  LocalMotion motion;
  motion.frame_time = clip.frame_time;
  motion.Resize(static_cast<int>(frames.size()), joints);
  for (int f = 0; f < static_cast<int>(frames.size()); ++f) {
    const v1::Frame& frame = frames[f];
    if (frame.rotations_size() != joints) {
      return absl::InvalidArgumentError("frame " + std::to_string(frame.index()) + " has " +
                                        std::to_string(frame.rotations_size()) + " rotations for " +
                                        std::to_string(joints) + " joints");
    }
    for (int j = 0; j < joints; ++j) {
      const v1::Quaternion& q = frame.rotations(j);
      motion.SetRotation(f, j, Eigen::Quaternionf(q.w(), q.x(), q.y(), q.z()).normalized());
      motion.SetTranslation(f, j, j == 0 ? FromProto(frame.root_position()) : clip.skeleton.joint(j).offset);
    }
  }
  // Frames made before the body reached that size keep their pelvis over the same ground point at
  // its height in the final body's proportion, so the feet stay on the floor.
  bool resized = false;
  for (const v1::Frame& frame : frames) resized = resized || BodyScale(frame) != final_scale;
  if (resized) {
    const int placed = pelvis < joints ? pelvis : 0;
    const GlobalPoses poses = ForwardKinematics(clip.skeleton, motion);
    for (int f = 0; f < static_cast<int>(frames.size()); ++f) {
      Eigen::Vector3f wanted = FromProto(frames[f].pelvis_position());
      wanted.y() *= final_scale / BodyScale(frames[f]);
      motion.SetTranslation(f, 0, motion.translation(f, 0) + wanted - poses.position(f, placed));
    }
  }
  if (hold_root && motion.num_frames() > 0) {
    // The joints above the pelvis keep the first frame's rotations (the root's turns the rig to
    // Y up), the root at the origin: on the floor, static; every joint's world position unchanged.
    std::vector<Eigen::Quaternionf> held(joints, Eigen::Quaternionf::Identity());
    for (int j = 0; j < joints; ++j) held[j] = motion.rotation(0, j);
    HoldJointsAbovePelvis(clip.skeleton, pelvis, held, Eigen::Vector3f::Zero(), motion);
  }
  clip.channels = ChannelsFromMotion(clip.skeleton, motion);
  return FormatBvh(clip);
}

}  // namespace mocap::cli
