// Skeleton: the joint hierarchy of a rig as flat arrays (parents before children, BVH order).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "absl/status/status.h"

namespace mocap {

enum class ChannelType : std::uint8_t { kXposition, kYposition, kZposition, kXrotation, kYrotation, kZrotation };
std::string_view ChannelName(ChannelType type);  // "Xposition", ...
bool IsRotation(ChannelType type);
int ChannelAxis(ChannelType type);  // 0, 1 or 2

// One joint. `offset` is in the file's length unit, in the parent's frame.
struct Joint {
  std::string name;
  int parent = -1;  // index into Skeleton::joints, -1 for the root
  Eigen::Vector3f offset = Eigen::Vector3f::Zero();
  std::vector<ChannelType> channels;  // in file order; 0, 3 or 6 of them (any order)
  // BVH "End Site" offset when the joint has one.
  std::optional<Eigen::Vector3f> end_site;
};

// Invariants (checked by Validate): exactly one root at index 0, every parent index smaller than
// the child's, unique non-empty names without white space, at most kMaxJoints joints, channels
// without repeats.
inline constexpr size_t kMaxJointNameBytes = 256;

class Skeleton {
 public:
  static constexpr int kMaxJoints = 1024;

  Skeleton() = default;
  explicit Skeleton(std::vector<Joint> joints);

  absl::Status Validate() const;

  int num_joints() const { return static_cast<int>(joints_.size()); }
  const Joint& joint(int index) const { return joints_[index]; }
  const std::vector<Joint>& joints() const { return joints_; }
  int parent(int index) const { return joints_[index].parent; }
  // Total channel count per frame, and where joint `index`'s first channel sits in a frame row.
  int num_channels() const { return num_channels_; }
  int channel_start(int index) const { return channel_starts_[index]; }
  std::vector<int> Children(int index) const;
  // Index of the joint called `name`, or -1.
  int Find(std::string_view name) const;

  // True when both describe the same rig: same joint names in the same hierarchy. Offsets and
  // channel orders may differ (other performers, other exporters).
  bool SameRigAs(const Skeleton& other) const;

 private:
  std::vector<Joint> joints_;
  std::vector<int> channel_starts_;
  int num_channels_ = 0;
};

}  // namespace mocap
