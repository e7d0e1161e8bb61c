// Body topology of an arbitrary humanoid rig without using joint names (docs/method.md B1), made
// robust for real rigs: zero-length helper joints, twist and "share" bones, hubs in hands, feet
// and face, an extra root above the hips, a rest pose that is not standing, a Z-up hierarchy.
// The seed's hub rule (joints with >= 3 children start groups) fails on such rigs; instead, in
// the order AnalyseBody runs them (one function each in body_topology_steps.h):
//  1. Bone lengths from the clip's own frames (position channels honoured); a joint whose
//     translation moves over the clip carries the motion and has no bone. Joints whose bone is
//     shorter than 2% of the body size (half the tree's diameter along the bones) are merged into
//     their parent; leaf chains that lie along a sibling bone in the clip's frames (twist bones)
//     are ignored. The remaining leaves are the candidate limb ends.
//  2. The five limb ends are picked by farthest-point sampling over those leaves with the tree
//     metric (path length along bones): hands, feet and head are the leaves farthest apart.
//  3. The head is the limb end with the shortest chain from where it branches off; the other four
//     pair up by deepest common ancestor. Pelvis = common ancestor of both pairs and the head.
//  4. World up = signed world axis nearest the mean pelvis -> head end direction over the frames.
//  5. The pair that branches off closer to the head are the arms (a star rig, where the tree
//     cannot tell: the pair whose ends are higher).
//  6. Wrist / ankle = distal end of the more distal of the two longest segments of the limb
//     chain, elbow / knee = distal end of the other one (where they meet, on a normal limb); a
//     segment runs between joints where the chain really bends (a split bone held straight does
//     not end one). The legs first; then the arms, whose upper long segment must start at a
//     shoulder lying wider apart from its mirror than the two hips do: a clavicle from the middle
//     of the chest is skipped even when it is longer than the forearm (the CMU 31-joint rig).
//  7. Sides, frame by frame (a clip's mean says nothing on a walk in a circle): in each sampled
//     frame the hip line (hip to hip) gives the facing up to its sign, forward = hip line x up,
//     and two anatomical cues of that same frame give the sign: knees bend forward (the knee's
//     horizontal offset from the hip-ankle line) and toes point forward from the ankle while the
//     foot is near its lowest (stance); when those are too weak (straight legs, no toe joints),
//     the pelvis' travel between sampled frames, each step against its own frame's facing. The
//     arms are sided against the same per-frame body: the left shoulder lies toward each frame's
//     left (left = up x forward). `forward` is the mean facing (the first frame's on a clip that
//     turns around).
//  8. Head landmark = the first branching joint on the head chain (or its end); groups = the
//     subtree of each limb's first joint, the rest is spine; leg length, pelvis height and floor
//     along up; unit from the leg length.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "absl/status/statusor.h"
#include "motion/core/units.h"
#include "motion/skeleton/local_motion.h"
#include "motion/skeleton/skeleton.h"

namespace mocap {

enum class BodyGroup : int { kSpine = 0, kHead, kLeftArm, kRightArm, kLeftLeg, kRightLeg };
inline constexpr int kNumBodyGroups = 6;
std::string_view BodyGroupName(BodyGroup group);  // "spine", "head", "left_arm", ...

struct BodyLandmarks {
  int pelvis = -1;
  int head = -1;
  int left_wrist = -1;
  int right_wrist = -1;
  int left_ankle = -1;
  int right_ankle = -1;
  // Where each limb bends (the joint between its two longest segments, step 6); -1 when unknown
  // (rigs stored before these were kept).
  int left_elbow = -1;
  int right_elbow = -1;
  int left_knee = -1;
  int right_knee = -1;
  // Where each limb's upper long bone starts (the proximal end of the segment ending at the elbow
  // / knee, step 6): past a clavicle or a hip offset; -1 when unknown (rigs stored before these
  // were kept).
  int left_shoulder = -1;
  int right_shoulder = -1;
  int left_hip = -1;
  int right_hip = -1;
};

// The body landmarks the service answers for (reconstruction confidence, landmark scoring), in
// this order: pelvis, head, then left and right of shoulders, elbows, wrists, hips, knees, ankles.
inline constexpr int kNumBodyLandmarks = 14;
inline constexpr std::array<const char*, kNumBodyLandmarks> kBodyLandmarkNames = {
    "pelvis",      "head",     "left_shoulder", "right_shoulder", "left_elbow", "right_elbow", "left_wrist",
    "right_wrist", "left_hip", "right_hip",     "left_knee",      "right_knee", "left_ankle",  "right_ankle"};
// The joints of `landmarks` in that order; -1 where the rig's analysis found none.
inline std::array<int, kNumBodyLandmarks> BodyLandmarkJoints(const BodyLandmarks& l) {
  return {l.pelvis,      l.head,     l.left_shoulder, l.right_shoulder, l.left_elbow, l.right_elbow, l.left_wrist,
          l.right_wrist, l.left_hip, l.right_hip,     l.left_knee,      l.right_knee, l.left_ankle,  l.right_ankle};
}

struct BodyTopology {
  std::vector<BodyGroup> group_of_joint;  // one per joint
  // Per group: the group's top joint (spine: the skeleton root) and its limb-end leaf.
  std::array<int, kNumBodyGroups> group_top{};
  std::array<int, kNumBodyGroups> group_end{};
  BodyLandmarks landmarks;
  // World axes in the clip's coordinates (unit vectors). up_axis is 0/1/2 for X/Y/Z and
  // up_sign +1/-1; up_alignment is the cosine between the measured body axis and that axis.
  int up_axis = 1;
  int up_sign = 1;
  float up_alignment = 0.0f;
  // Ground-plane facing direction: the mean over the clip's sampled frames, or the first frame's
  // when the clip turns so much that the mean is short (a walk in a circle).
  Eigen::Vector3f forward = Eigen::Vector3f::UnitZ();
  // Up axis of the zero-rotation pose, which often differs (Z-up hierarchies).
  int rest_up_axis = 1;
  int rest_up_sign = 1;
  // Sizes in the file's length unit.
  float leg_length = 0.0f;              // hip joint -> ankle along bones, mean of both legs
  float standing_pelvis_height = 0.0f;  // median over frames of pelvis height above the lowest leg joint
  float floor_height = 0.0f;            // lowest leg joint height over the clip, along up
  LengthUnit unit = LengthUnit::kCentimetre;
  bool unit_detected = true;  // false when given by the caller

  Eigen::Vector3f up() const {
    Eigen::Vector3f v = Eigen::Vector3f::Zero();
    v[up_axis] = static_cast<float>(up_sign);
    return v;
  }
  int group_size(BodyGroup group) const;
};

struct BodyTopologyOptions {
  std::optional<LengthUnit> unit;  // override unit detection
};

// Analyses `skeleton` using the clip's local motion (any number of frames; with one frame of the
// rest pose, geometry-dependent answers come from the rest pose). FailedPrecondition when the rig
// is not a recognisable humanoid (fewer than five limb ends, no way to tell left from right).
absl::StatusOr<BodyTopology> AnalyseBody(const Skeleton& skeleton, const LocalMotion& motion,
                                         const BodyTopologyOptions& options = {});

}  // namespace mocap
