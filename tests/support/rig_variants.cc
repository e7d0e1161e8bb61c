#include "tests/support/rig_variants.h"

#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include "motion/skeleton/local_motion.h"

namespace mocap::testing {

void MoveOnGround(BvhClip& clip, float yaw_degrees, const Eigen::Vector3f& ground_translation) {
  LocalMotion motion = MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time);
  RotateWorld(motion, Eigen::Quaternionf(
                          Eigen::AngleAxisf(yaw_degrees * static_cast<float>(M_PI / 180.0), Eigen::Vector3f::UnitY())));
  for (int f = 0; f < motion.num_frames(); ++f) {
    motion.SetTranslation(f, 0, motion.translation(f, 0) + ground_translation);
  }
  clip.channels = ChannelsFromMotion(clip.skeleton, motion);
}

void RenameJoints(BvhClip& clip) {
  std::vector<Joint> joints = clip.skeleton.joints();
  for (size_t j = 0; j < joints.size(); ++j) joints[j].name = "j" + std::to_string(j);
  clip.skeleton = Skeleton(std::move(joints));
}

absl::Status SplitBone(BvhClip& clip, int child, const std::string& new_name) {
  const Skeleton& old = clip.skeleton;
  if (child <= 0 || child >= old.num_joints()) return absl::InvalidArgumentError("cannot split above the root");
  const int parent = old.parent(child);
  if (old.joint(child).channels.size() != 3 && old.joint(child).channels.size() != 6) {
    return absl::InvalidArgumentError("the joint has no rotation channels");
  }
  auto shifted = [&](int index) { return index >= child ? index + 1 : index; };

  std::vector<Joint> joints;
  std::vector<int> source;  // old joint index per new joint, -1 for the inserted one
  for (int j = 0; j < old.num_joints(); ++j) {
    if (j == child) {
      Joint middle;
      middle.name = new_name;
      middle.parent = parent;
      middle.offset = 0.5f * old.joint(child).offset;
      for (ChannelType type : old.joint(child).channels) {
        if (IsRotation(type)) middle.channels.push_back(type);
      }
      joints.push_back(std::move(middle));
      source.push_back(-1);
    }
    Joint joint = old.joint(j);
    if (j == child) {
      joint.parent = child;  // the inserted joint's index
      joint.offset *= 0.5f;
    } else if (joint.parent >= 0) {
      joint.parent = shifted(joint.parent);
    }
    joints.push_back(std::move(joint));
    source.push_back(j);
  }
  Skeleton skeleton(std::move(joints));
  if (absl::Status status = skeleton.Validate(); !status.ok()) return status;
  ChannelMatrix channels = ChannelMatrix::Zero(clip.num_frames(), skeleton.num_channels());
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    if (source[j] < 0) continue;  // zero rotation
    const int count = static_cast<int>(skeleton.joint(j).channels.size());
    channels.middleCols(skeleton.channel_start(j), count) =
        clip.channels.middleCols(old.channel_start(source[j]), count);
  }
  // A child with position channels (e.g. Bandai's) carries its offset in them: halve those too.
  const Joint& moved = skeleton.joint(child + 1);
  for (size_t k = 0; k < moved.channels.size(); ++k) {
    if (!IsRotation(moved.channels[k])) channels.col(skeleton.channel_start(child + 1) + static_cast<int>(k)) *= 0.5f;
  }
  clip.skeleton = std::move(skeleton);
  clip.channels = std::move(channels);
  return absl::OkStatus();
}

void ChangeRotationOrder(BvhClip& clip, const std::string& order) {
  const LocalMotion motion = MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time);
  std::vector<Joint> joints = clip.skeleton.joints();
  for (Joint& joint : joints) {
    std::vector<ChannelType> positions, rotations;
    for (ChannelType type : joint.channels) (IsRotation(type) ? rotations : positions).push_back(type);
    if (rotations.empty()) continue;
    joint.channels = positions;
    for (char axis : order) {
      joint.channels.push_back(axis == 'X'   ? ChannelType::kXrotation
                               : axis == 'Y' ? ChannelType::kYrotation
                                             : ChannelType::kZrotation);
    }
  }
  clip.skeleton = Skeleton(std::move(joints));
  clip.channels = ChannelsFromMotion(clip.skeleton, motion);
}

namespace {

// Multiplies joint `j`'s offset, end site and position channels by `factor`.
void ScaleJoint(BvhClip& clip, std::vector<Joint>& joints, int j, float factor) {
  joints[j].offset *= factor;
  if (joints[j].end_site) *joints[j].end_site *= factor;
  for (size_t k = 0; k < joints[j].channels.size(); ++k) {
    if (!IsRotation(joints[j].channels[k]))
      clip.channels.col(clip.skeleton.channel_start(j) + static_cast<int>(k)) *= factor;
  }
}

}  // namespace

void ScaleLengths(BvhClip& clip, float factor) {
  std::vector<Joint> joints = clip.skeleton.joints();
  for (int j = 0; j < clip.skeleton.num_joints(); ++j) ScaleJoint(clip, joints, j, factor);
  clip.skeleton = Skeleton(std::move(joints));
}

Proportions RandomProportions(std::mt19937& random, float low, float high) {
  std::uniform_real_distribution<float> log_factor(std::log(low), std::log(high));
  Proportions p;
  for (float* factor : {&p.legs, &p.arms, &p.spine, &p.head}) *factor = std::exp(log_factor(random));
  return p;
}

void ScaleProportions(BvhClip& clip, const BodyTopology& topology, const Proportions& proportions) {
  std::vector<bool> carries_body(clip.skeleton.num_joints(), false);  // the pelvis and its ancestors
  for (int j = topology.landmarks.pelvis; j >= 0; j = clip.skeleton.parent(j)) carries_body[j] = true;
  std::vector<Joint> joints = clip.skeleton.joints();
  for (int j = 0; j < clip.skeleton.num_joints(); ++j) {
    float factor = proportions.spine;
    switch (topology.group_of_joint[j]) {
      case BodyGroup::kLeftLeg:
      case BodyGroup::kRightLeg:
        factor = proportions.legs;
        break;
      case BodyGroup::kLeftArm:
      case BodyGroup::kRightArm:
        factor = proportions.arms;
        break;
      case BodyGroup::kHead:
        factor = proportions.head;
        break;
      case BodyGroup::kSpine:
        factor = proportions.spine;
        break;
    }
    if (carries_body[j]) factor = proportions.legs;
    ScaleJoint(clip, joints, j, factor);
  }
  clip.skeleton = Skeleton(std::move(joints));
}

void ScaleEveryBone(BvhClip& clip, const BodyTopology& topology, std::mt19937& random, float low, float high) {
  std::uniform_real_distribution<float> log_factor(std::log(low), std::log(high));
  const int n = clip.skeleton.num_joints();
  std::vector<float> factor(n);
  for (float& f : factor) f = std::exp(log_factor(random));
  // The pelvis and its ancestors carry the travel and the height, which follow the legs.
  float leg_log_sum = 0.0f;
  int leg_bones = 0;
  for (int j = 0; j < n; ++j) {
    const BodyGroup group = topology.group_of_joint[j];
    if (group == BodyGroup::kLeftLeg || group == BodyGroup::kRightLeg) {
      leg_log_sum += std::log(factor[j]);
      ++leg_bones;
    }
  }
  const float legs = leg_bones > 0 ? std::exp(leg_log_sum / leg_bones) : 1.0f;
  for (int j = topology.landmarks.pelvis; j >= 0; j = clip.skeleton.parent(j)) factor[j] = legs;
  std::vector<Joint> joints = clip.skeleton.joints();
  for (int j = 0; j < n; ++j) ScaleJoint(clip, joints, j, factor[j]);
  clip.skeleton = Skeleton(std::move(joints));
}

absl::Status Rerig(BvhClip& clip, int split_joint, float yaw_degrees, const Eigen::Vector3f& ground_translation) {
  MoveOnGround(clip, yaw_degrees, ground_translation);
  if (absl::Status status = SplitBone(clip, split_joint, "InsertedJoint"); !status.ok()) return status;
  ChangeRotationOrder(clip, "XYZ");
  ScaleLengths(clip, 1.0f / 2.54f);
  RenameJoints(clip);
  return absl::OkStatus();
}

}  // namespace mocap::testing
