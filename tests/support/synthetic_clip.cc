#include "tests/support/synthetic_clip.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

namespace mocap::testing {
namespace {

using Eigen::AngleAxisd;
using Eigen::Quaterniond;
using Eigen::Vector3d;

constexpr double kDegree = M_PI / 180.0;
constexpr double kHipYaw = 4.0;        // degrees
constexpr double kArmLowering = 75.0;  // degrees from the T-pose
constexpr double kArmSwing = 18.0;     // degrees
constexpr double kHipJointDrop = 6.0;  // Hips -> hip joint, cm down
constexpr double kHipJointSide = 9.0;  // Hips -> hip joint, cm sideways
// Half the distance the foot travels relative to the hips during stance (stance = half a cycle).
constexpr double kHalfStep = kSyntheticWalkSpeed * kSyntheticGaitCycle / 4.0;

Quaterniond Rotation(int axis, double degrees) {
  return Quaterniond(AngleAxisd(degrees * kDegree, Vector3d::Unit(axis)));
}

struct RigJoint {
  std::string name;
  int parent = -1;
  Vector3d offset = Vector3d::Zero();    // cm, Y-up axes
  Vector3d end_site = Vector3d::Zero();  // used when the joint is a leaf
};

// Indices of the joints the walk animates; side 0 = left (+X), 1 = right (-X).
struct Body {
  std::vector<RigJoint> joints;
  int hips = -1, spine = -1, chest = -1, neck = -1;
  std::array<int, 2> upleg{}, leg{}, foot{}, arm{}, forearm{};
  std::vector<std::pair<int, int>> curling_fingers;  // (joint, side)
  std::vector<std::pair<int, int>> twists;           // (joint, twist axis in the joint's frame)

  int Add(std::string name, int parent, const Vector3d& offset, const Vector3d& end_site = Vector3d::Zero()) {
    joints.push_back(RigJoint{std::move(name), parent, offset, end_site});
    return static_cast<int>(joints.size()) - 1;
  }
};

Body BuildBody(const SyntheticRigOptions& options) {
  Body body;
  body.hips = body.Add("Hips", -1, {0, kSyntheticRestHipsHeight, 0});
  body.spine = body.Add("Spine", body.hips, {0, 10, 0});
  body.chest = body.Add("Chest", body.spine, {0, 15, 0});
  body.neck = body.Add("Neck", body.chest, {0, 22, 0});
  body.Add("Head", body.neck, {0, 9, 0}, {0, 18, 0});
  static constexpr const char* kFingers[] = {"Thumb", "Index", "Middle", "Ring", "Pinky"};
  for (int side = 0; side < 2; ++side) {
    const double s = side == 0 ? 1.0 : -1.0;
    const std::string prefix = side == 0 ? "Left" : "Right";
    const int shoulder = body.Add(prefix + "Shoulder", body.chest, {3 * s, 17, 0});
    const int arm = body.arm[side] = body.Add(prefix + "Arm", shoulder, {options.clavicle_length * s, 0, 0});
    const int forearm = body.forearm[side] = body.Add(prefix + "ForeArm", arm, {28 * s, 0, 0});
    const int hand = body.Add(prefix + "Hand", forearm, {25 * s, 0, 0}, {18 * s, 0, 0});
    if (options.fingers_and_toes) {
      static constexpr double kBase[5][3] = {{2.5, -1, 3}, {9, 0, 2.5}, {9.5, 0, 0.7}, {9, 0, -1}, {8, 0, -2.7}};
      for (int f = 0; f < 5; ++f) {
        const bool thumb = f == 0;
        const std::string name = prefix + "Hand" + kFingers[f];
        const int j1 = body.Add(name + "1", hand, {kBase[f][0] * s, kBase[f][1], kBase[f][2]});
        const int j2 = body.Add(name + "2", j1, thumb ? Vector3d(2.5 * s, 0, 2) : Vector3d((f == 4 ? 3 : 4) * s, 0, 0));
        const int j3 = body.Add(name + "3", j2, thumb ? Vector3d(2 * s, 0, 1.5) : Vector3d(2.5 * s, 0, 0),
                                thumb ? Vector3d(1.5 * s, 0, 1) : Vector3d(2 * s, 0, 0));
        if (!thumb) {
          for (int j : {j1, j2, j3}) body.curling_fingers.emplace_back(j, side);
        }
      }
    }
    if (options.twist_bones) {
      const int forearm_twist = body.Add(prefix + "ForeArmTwist", forearm, Vector3d::Zero());
      body.twists.emplace_back(forearm_twist, 0);
      body.Add(prefix + "ForeArmTwistMid", forearm_twist, {12.5 * s, 0, 0});
      body.Add(prefix + "ElbowShareBone", forearm, Vector3d::Zero());
      const int arm_twist = body.Add(prefix + "ArmTwist", arm, Vector3d::Zero());
      body.twists.emplace_back(arm_twist, 0);
      body.Add(prefix + "ArmTwistMid", arm_twist, {14 * s, 0, 0});
    }
  }
  const int pelvis = options.twist_bones ? body.Add("Pelvis", body.hips, Vector3d::Zero()) : body.hips;
  for (int side = 0; side < 2; ++side) {
    const double s = side == 0 ? 1.0 : -1.0;
    const std::string prefix = side == 0 ? "Left" : "Right";
    const int upleg = body.upleg[side] = body.Add(prefix + "UpLeg", pelvis, {kHipJointSide * s, -kHipJointDrop, 0});
    const int leg = body.leg[side] = body.Add(prefix + "Leg", upleg, {0, -kSyntheticThighLength, 0});
    const int foot = body.foot[side] = body.Add(prefix + "Foot", leg, {0, -kSyntheticShinLength, 0});
    const int toe_base =
        body.Add(prefix + "ToeBase", foot, {0, kSyntheticToeHeight - kSyntheticAnkleHeight, 13}, {0, 0, 6});
    if (options.fingers_and_toes) {
      for (int k = 0; k < 5; ++k) {
        body.Add(prefix + "Toe" + std::to_string(k + 1), toe_base, {s * (-3 + 1.5 * k), 0, 2.5 - 0.3 * k}, {0, 0, 2});
      }
    }
    if (options.twist_bones) {
      const int leg_twist = body.Add(prefix + "LegTwist", leg, Vector3d::Zero());
      body.twists.emplace_back(leg_twist, 1);
      body.Add(prefix + "LegTwistMid", leg_twist, {0, -kSyntheticShinLength / 2, 0});
      body.Add(prefix + "KneeShareBone", leg, Vector3d::Zero());
      const int upleg_twist = body.Add(prefix + "UpLegTwist", upleg, Vector3d::Zero());
      body.twists.emplace_back(upleg_twist, 1);
      body.Add(prefix + "UpLegTwistMid", upleg_twist, {0, -kSyntheticThighLength / 2, 0});
    }
  }
  return body;
}

// One leg at one instant: ankle position relative to the hip joint in the sagittal plane.
struct LegPose {
  double flexion = 0;  // degrees, thigh forward of vertical
  double knee = 0;     // degrees of bend
  double extent = 0;   // cm, hip joint above ankle
};

// Thigh angle `a` putting the ankle `z` cm in front of the hip joint with the knee bent `k`.
LegPose SolveLeg(double z, double knee) {
  const double l1 = kSyntheticThighLength, l2 = kSyntheticShinLength;
  auto horizontal = [&](double a) { return l1 * std::sin(a * kDegree) + l2 * std::sin((a - knee) * kDegree); };
  double lo = -80.0, hi = 80.0 + knee;
  for (int i = 0; i < 80; ++i) {
    const double mid = 0.5 * (lo + hi);
    (horizontal(mid) < z ? lo : hi) = mid;
  }
  LegPose pose;
  pose.flexion = 0.5 * (lo + hi);
  pose.knee = knee;
  pose.extent = l1 * std::cos(pose.flexion * kDegree) + l2 * std::cos((pose.flexion - knee) * kDegree);
  return pose;
}

double HipYaw(double t) { return -kHipYaw * std::cos(2 * M_PI * t / kSyntheticGaitCycle); }

// `side` 0 = left (heel strike at t = 0), 1 = right (half a cycle later).
LegPose LegAt(double t, int side) {
  double p = t / kSyntheticGaitCycle + (side == 0 ? 0.0 : 0.5);
  p -= std::floor(p);
  const double s = side == 0 ? 1.0 : -1.0;
  // The hip joint moves with the pelvis yaw; keep the planted ankle still in the world.
  const double yaw_shift = kHipJointSide * (s * std::sin(HipYaw(t) * kDegree) + std::sin(kHipYaw * kDegree));
  const double stance_end = -kHalfStep + 2 * kHipJointSide * std::sin(kHipYaw * kDegree);
  if (p < 0.5) {
    const double u = p / 0.5;
    return SolveLeg(kHalfStep * (1 - 2 * u) + yaw_shift, 5 + 10 * std::sin(M_PI * u));
  }
  const double u = (p - 0.5) / 0.5;
  // The knee bends most early in the swing (u = 1/4) and straightens before heel strike.
  return SolveLeg(stance_end + (kHalfStep - stance_end) * 0.5 * (1 - std::cos(M_PI * u)),
                  5 + 55 * std::sin(M_PI * std::sqrt(u)));
}

// Local rotations (Y-up axes) and the Hips world position (cm) at time t.
void PoseAt(const Body& body, double t, std::vector<Quaterniond>& local, Vector3d& hips) {
  std::fill(local.begin(), local.end(), Quaterniond::Identity());
  const double yaw = HipYaw(t);
  const LegPose legs[2] = {LegAt(t, 0), LegAt(t, 1)};
  hips = Vector3d(0, kSyntheticAnkleHeight + kHipJointDrop + std::max(legs[0].extent, legs[1].extent),
                  kSyntheticWalkSpeed * t);
  local[body.hips] = Rotation(1, yaw);
  local[body.spine] = Rotation(1, -yaw);
  local[body.chest] = Rotation(1, -0.5 * yaw);
  local[body.neck] = Rotation(1, 0.5 * yaw);
  for (int side = 0; side < 2; ++side) {
    const double s = side == 0 ? 1.0 : -1.0;
    const LegPose& leg = legs[side];
    // Flexion swings the thigh towards +Z: a negative angle about X. The thigh cancels the pelvis
    // yaw so that the leg stays in the walking plane; the ankle keeps the foot flat.
    local[body.upleg[side]] = Rotation(1, -yaw) * Rotation(0, -leg.flexion);
    local[body.leg[side]] = Rotation(0, leg.knee);
    local[body.foot[side]] = Rotation(0, leg.flexion - leg.knee);
    double p = t / kSyntheticGaitCycle + (side == 0 ? 0.0 : 0.5);
    p -= std::floor(p);
    const double swing = -kArmSwing * std::cos(2 * M_PI * p);  // forward when the leg is back
    local[body.arm[side]] = Rotation(0, -swing) * Rotation(2, -kArmLowering * s);
    const double elbow = 20 + 10 * std::max(0.0, swing) / kArmSwing;
    local[body.forearm[side]] = Rotation(1, -elbow * s);
  }
  for (const auto& [joint, side] : body.curling_fingers) {
    local[joint] = Rotation(2, side == 0 ? -15.0 : 15.0);
  }
  for (const auto& [joint, axis] : body.twists) {
    local[joint] = Rotation(axis, 3 * std::sin(2 * M_PI * t / kSyntheticGaitCycle));
  }
}

// The walk of PoseAt along options.path.
void WalkPoseAt(const Body& body, const SyntheticRigOptions& options, double t, std::vector<Quaterniond>& local,
                Vector3d& hips) {
  switch (options.path) {
    case SyntheticPath::kStraight:
      PoseAt(body, t, local, hips);
      return;
    case SyntheticPath::kBackwards:
      PoseAt(body, -t, local, hips);  // the same steps in reverse: facing +Z, travelling -Z
      return;
    case SyntheticPath::kSideways:
      PoseAt(body, t, local, hips);
      hips.z() = 0;                              // stepping in place ...
      hips.x() = 0.5 * kSyntheticWalkSpeed * t;  // ... while drifting to the left
      return;
    case SyntheticPath::kCircle: {
      PoseAt(body, t, local, hips);
      const double r = options.circle_radius;
      const double heading = kSyntheticWalkSpeed * t / r;  // radians about +Y
      local[body.hips] = Quaterniond(AngleAxisd(heading, Vector3d::UnitY())) * local[body.hips];
      hips = Vector3d(r - r * std::cos(heading), hips.y(), r * std::sin(heading));
      return;
    }
  }
}

// One standing frame (MakeStandingClip).
void StandingPose(const Body& body, double arm_lowering_degrees, std::vector<Quaterniond>& local, Vector3d& hips) {
  std::fill(local.begin(), local.end(), Quaterniond::Identity());
  for (int side = 0; side < 2; ++side) {
    local[body.arm[side]] = Rotation(2, -arm_lowering_degrees * (side == 0 ? 1.0 : -1.0));
  }
  hips = Vector3d(0, kSyntheticRestHipsHeight, 0);
}

// "Left*" <-> "Right*".
std::string OtherSidesName(const std::string& name) {
  if (name.rfind("Left", 0) == 0) return "Right" + name.substr(4);
  if (name.rfind("Right", 0) == 0) return "Left" + name.substr(5);
  return name;
}

// Intrinsic Euler angles in degrees: R = R_axes[0](e0) R_axes[1](e1) R_axes[2](e2), middle angle in
// [-90, 90].
Vector3d EulerDegrees(const Eigen::Matrix3d& m, const std::array<int, 3>& axes) {
  const int i = axes[0], j = axes[1], k = axes[2];
  const double sign = j == (i + 1) % 3 ? 1.0 : -1.0;
  Vector3d e;
  const double s = std::clamp(sign * m(i, k), -1.0, 1.0);
  e[1] = std::asin(s);
  if (std::abs(s) < 1.0 - 1e-12) {
    e[0] = std::atan2(-sign * m(j, k), m(k, k));
    e[2] = std::atan2(-sign * m(i, j), m(i, i));
  } else {
    e[0] = std::atan2(sign * m(k, j), m(j, j));
    e[2] = 0;
  }
  e /= kDegree;
  for (int r = 0; r < 3; ++r) {
    if (std::abs(e[r]) < 1e-9) e[r] = 0;  // no 1e-17 noise in the file
  }
  return e;
}

std::array<int, 3> ParseOrder(const std::string& order) {
  std::array<int, 3> axes{};
  bool ok = order.size() == 3;
  for (int i = 0; ok && i < 3; ++i) {
    const char c = order[i];
    axes[i] = c == 'X' ? 0 : c == 'Y' ? 1 : c == 'Z' ? 2 : -1;
    ok = axes[i] >= 0 && std::count(order.begin(), order.end(), c) == 1;
  }
  if (!ok) {
    std::fprintf(stderr, "MakeWalkingClip: rotation_order '%s' is not a permutation of XYZ\n", order.c_str());
    std::abort();
  }
  return axes;
}

// The clip of `frames` frames posed by `pose_at(body, t, local, hips)`.
template <typename PoseFunction>
BvhClip MakeClip(const SyntheticRigOptions& options, int frames, double frame_time, PoseFunction pose_at) {
  const std::array<int, 3> axes = ParseOrder(options.rotation_order);
  const Body body = BuildBody(options);
  const double scale = options.length_scale;
  // Z-up authoring: a vector v (Y-up) is stored as C v, C = +90 deg about X (exactly); a local
  // rotation R as C R C^-1; RL_BoneRoot's rotation is C^-1.
  Eigen::Matrix3d c = Eigen::Matrix3d::Identity();
  if (options.z_up) c << 1, 0, 0, 0, 0, -1, 0, 1, 0;

  const std::vector<ChannelType> positions = {ChannelType::kXposition, ChannelType::kYposition,
                                              ChannelType::kZposition};
  std::vector<ChannelType> rotations;
  for (int axis : axes) rotations.push_back(static_cast<ChannelType>(3 + axis));
  std::vector<ChannelType> six = positions;
  six.insert(six.end(), rotations.begin(), rotations.end());

  // Output joints: optional RL_BoneRoot and Root, then the body.
  std::vector<Joint> joints;
  int rl_root = -1, static_root = -1;
  if (options.z_up) {
    rl_root = static_cast<int>(joints.size());
    joints.push_back(Joint{.name = "RL_BoneRoot", .parent = -1, .channels = six});
  }
  if (options.extra_root) {
    static_root = static_cast<int>(joints.size());
    joints.push_back(Joint{.name = "Root", .parent = rl_root, .channels = six});
  }
  const int top = static_root >= 0 ? static_root : rl_root;
  const int first_body = static_cast<int>(joints.size());
  const bool hips_is_root = top < 0;
  std::vector<bool> has_child(body.joints.size(), false);
  for (const RigJoint& joint : body.joints) {
    if (joint.parent >= 0) has_child[joint.parent] = true;
  }
  for (size_t b = 0; b < body.joints.size(); ++b) {
    const RigJoint& rig = body.joints[b];
    Joint joint;
    joint.name = options.mirrored_names ? OtherSidesName(rig.name) : rig.name;
    joint.parent = rig.parent < 0 ? top : first_body + rig.parent;
    joint.offset = (scale * (c * rig.offset)).cast<float>();
    const bool is_hips = static_cast<int>(b) == body.hips;
    const bool six_channels = options.position_channels_everywhere || (is_hips && (hips_is_root || options.extra_root));
    joint.channels = six_channels ? six : rotations;
    if (!has_child[b]) joint.end_site = (scale * (c * rig.end_site)).cast<float>();
    joints.push_back(std::move(joint));
  }

  BvhClip clip;
  clip.skeleton = Skeleton(std::move(joints));
  clip.frame_time = frame_time;
  const Skeleton& skeleton = clip.skeleton;
  clip.channels.setZero(std::max(frames, 0), skeleton.num_channels());

  std::vector<Quaterniond> local(body.joints.size());
  for (int f = 0; f < frames; ++f) {
    Vector3d hips_world = Vector3d::Zero();
    pose_at(body, f * frame_time, local, hips_world);
    hips_world *= scale;
    for (int j = 0; j < skeleton.num_joints(); ++j) {
      const Joint& joint = skeleton.joint(j);
      const int body_index = j - first_body;
      const Vector3d offset = joint.offset.cast<double>();
      Vector3d translation = offset;  // the position channel values of non-root joints
      Vector3d angles = Vector3d::Zero();
      if (j == rl_root) {
        // Carries the travel unless Hips does (extra_root); rotation exactly -90 deg about X.
        translation = Vector3d::Zero();
        if (!options.extra_root) {
          translation = hips_world - c.transpose() * skeleton.joint(first_body + body.hips).offset.cast<double>();
        }
        for (int r = 0; r < 3; ++r) angles[r] = axes[r] == 0 ? -90.0 : 0.0;
      } else if (j == static_root) {
        translation = Vector3d::Zero();
      } else {
        if (body_index == body.hips) {
          if (hips_is_root) {
            translation = hips_world - offset;  // root: OFFSET + channels
          } else if (options.extra_root) {
            translation = c * hips_world;  // replaces the OFFSET
          }
        }
        angles = EulerDegrees(c * local[body_index].normalized().toRotationMatrix() * c.transpose(), axes);
      }
      int r = 0;
      for (size_t k = 0; k < joint.channels.size(); ++k) {
        const ChannelType type = joint.channels[k];
        const int column = skeleton.channel_start(j) + static_cast<int>(k);
        clip.channels(f, column) = static_cast<float>(IsRotation(type) ? angles[r++] : translation[ChannelAxis(type)]);
      }
    }
  }
  return clip;
}

}  // namespace

BvhClip MakeWalkingClip(const SyntheticRigOptions& options, int frames, double frame_time) {
  return MakeClip(options, frames, frame_time,
                  [&](const Body& body, double t, std::vector<Quaterniond>& local, Vector3d& hips) {
                    WalkPoseAt(body, options, t, local, hips);
                  });
}

BvhClip MakeStandingClip(const SyntheticRigOptions& options, double arm_lowering_degrees) {
  return MakeClip(options, 1, 1.0 / 30.0,
                  [&](const Body& body, double, std::vector<Quaterniond>& local, Vector3d& hips) {
                    StandingPose(body, arm_lowering_degrees, local, hips);
                  });
}

SyntheticRigOptions SyntheticRigFromBits(int bits, const std::string& rotation_order) {
  SyntheticRigOptions options;
  options.extra_root = (bits & 1) != 0;
  options.z_up = (bits & 2) != 0;
  options.fingers_and_toes = (bits & 4) != 0;
  options.twist_bones = (bits & 8) != 0;
  options.position_channels_everywhere = (bits & 16) != 0;
  options.rotation_order = rotation_order;
  return options;
}

}  // namespace mocap::testing
