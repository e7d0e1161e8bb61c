#include "motion/skeleton/skeleton.h"

#include <algorithm>
#include <unordered_set>

#include "motion/core/str_cat.h"

namespace mocap {

std::string_view ChannelName(ChannelType type) {
  switch (type) {
    case ChannelType::kXposition:
      return "Xposition";
    case ChannelType::kYposition:
      return "Yposition";
    case ChannelType::kZposition:
      return "Zposition";
    case ChannelType::kXrotation:
      return "Xrotation";
    case ChannelType::kYrotation:
      return "Yrotation";
    case ChannelType::kZrotation:
      return "Zrotation";
  }
  return "?";
}

bool IsRotation(ChannelType type) {
  return type == ChannelType::kXrotation || type == ChannelType::kYrotation || type == ChannelType::kZrotation;
}

int ChannelAxis(ChannelType type) { return static_cast<int>(type) % 3; }

Skeleton::Skeleton(std::vector<Joint> joints) : joints_(std::move(joints)) {
  channel_starts_.reserve(joints_.size());
  for (const Joint& joint : joints_) {
    channel_starts_.push_back(num_channels_);
    num_channels_ += static_cast<int>(joint.channels.size());
  }
}

absl::Status Skeleton::Validate() const {
  if (joints_.empty()) return absl::InvalidArgumentError("skeleton has no joints");
  if (num_joints() > kMaxJoints) {
    return absl::InvalidArgumentError(
        StrCat("skeleton has ", num_joints(), " joints; at most ", kMaxJoints, " supported"));
  }
  std::unordered_set<std::string_view> names;
  for (int i = 0; i < num_joints(); ++i) {
    const Joint& joint = joints_[i];
    // Names are echoed in errors, logs and replies: no white space or control characters, and
    // short enough for any of them (issue #24: a 3 MiB name overflowed the reply's metadata).
    if (joint.name.size() > kMaxJointNameBytes) {
      return absl::InvalidArgumentError(
          StrCat("joint ", i, " has a name of ", joint.name.size(), " bytes (at most ", kMaxJointNameBytes, ")"));
    }
    if (joint.name.empty() || std::any_of(joint.name.begin(), joint.name.end(),
                                          [](char c) { return static_cast<unsigned char>(c) <= ' ' || c == '\x7f'; })) {
      std::string shown;
      for (const char c : joint.name) shown += static_cast<unsigned char>(c) < ' ' || c == '\x7f' ? '?' : c;
      return absl::InvalidArgumentError(
          StrCat("joint ", i, " has an invalid name '", shown, "' (white space or control characters)"));
    }
    if (!names.insert(joint.name).second) {
      return absl::InvalidArgumentError(StrCat("duplicate joint name '", joint.name, "'"));
    }
    if ((i == 0) != (joint.parent == -1) || joint.parent < -1 || joint.parent >= i) {
      return absl::InvalidArgumentError(StrCat("joint '", joint.name, "' has invalid parent index ", joint.parent));
    }
    if (!joint.offset.allFinite()) {
      return absl::InvalidArgumentError(StrCat("joint '", joint.name, "' has a non-finite offset"));
    }
    unsigned seen = 0;
    for (ChannelType channel : joint.channels) {
      const unsigned bit = 1u << static_cast<unsigned>(channel);
      if (seen & bit) {
        return absl::InvalidArgumentError(StrCat("joint '", joint.name, "' repeats channel ", ChannelName(channel)));
      }
      seen |= bit;
    }
  }
  return absl::OkStatus();
}

std::vector<int> Skeleton::Children(int index) const {
  std::vector<int> children;
  for (int i = index + 1; i < num_joints(); ++i) {
    if (joints_[i].parent == index) children.push_back(i);
  }
  return children;
}

int Skeleton::Find(std::string_view name) const {
  for (int i = 0; i < num_joints(); ++i) {
    if (joints_[i].name == name) return i;
  }
  return -1;
}

bool Skeleton::SameRigAs(const Skeleton& other) const {
  if (num_joints() != other.num_joints()) return false;
  for (int i = 0; i < num_joints(); ++i) {
    if (joints_[i].name != other.joints_[i].name || joints_[i].parent != other.joints_[i].parent) {
      return false;
    }
  }
  return true;
}

}  // namespace mocap
