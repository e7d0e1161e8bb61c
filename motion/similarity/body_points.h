// Rig-independent body point clouds (docs/method.md B3–B4): for every body group, points along the
// group's main chain, relative to the pelvis and divided by the body scale, so that skeletons of
// different size, joint count and joint names give comparable clouds.
#pragma once

#include <array>
#include <optional>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "absl/status/statusor.h"
#include "motion/skeleton/body_topology.h"
#include "motion/skeleton/forward_kinematics.h"

namespace mocap {

// How each group's chain becomes a fixed number of points (docs/method.md B4).
enum class PointSampling {
  // Points at equal fractions of the chain's length: rigs with extra twist or split joints
  // still give the same body points. The default: as good as dropping on real cross-rig queries
  // (cmu-cc against bandai-namco-2, precision@10) and robust to split bones where dropping is not.
  kResampleChains,
  // The seed's rule: the chain's joints, dropping those nearest the end effector beyond the
  // count (a rig with more joints in a chain compares different body points).
  kDropNearestEndEffector,
};

// How the points are scaled, i.e. what of a body's build is factored out (issue #11).
enum class ChainScaling {
  // Posture on a canonical body: each limb's two long bones (shoulder -> elbow -> wrist,
  // hip -> knee -> ankle) as their directions at canonical lengths, hung from shoulders and hips
  // placed at canonical widths along the body's own shoulder and hip lines; spine and head as
  // their own shapes divided by their own lengths (kCanonicalBody). Bone lengths within a limb,
  // clavicles, hip offsets and where a rig puts its chest and neck joints no longer count: only
  // joint directions do. The default.
  kBoneDirections,
  // Each chain is divided by its own length and put back together at fixed proportions
  // (kCanonicalChainLengths): legs and spine from the pelvis, arms and head from the spine's end.
  // Bodies with longer legs, shorter arms or a longer spine than another's give the same points
  // for the same joint rotations, but proportions within a chain (clavicle, upper arm, forearm)
  // and where each rig puts its joints still count.
  kPerChain,
  // The seed's rule: every point relative to the pelvis, divided by the mean leg length (only
  // the body's overall size is factored out).
  kBodyScale,
};

// "bone-directions", "per-chain", "body-scale" (the names `mocapd similar --scaling` and the
// PoseSearch request take).
std::string_view ChainScalingName(ChainScaling scaling);
std::optional<ChainScaling> ParseChainScaling(std::string_view name);
// "resample", "drop" (`mocapd similar --sampling`).
std::string_view PointSamplingName(PointSampling sampling);
std::optional<PointSampling> ParsePointSampling(std::string_view name);

// Chain lengths of the canonical body kPerChain assembles, in leg lengths, by BodyGroup
// (spine pelvis -> chest, head neck -> head joint, arms shoulder -> wrist, legs hip -> ankle):
// the proportions both shared rigs measure, rounded (spine 0.29–0.31,
// head 0.08, arms 0.65–0.66), so that each group keeps its natural share of the distance.
inline constexpr float kCanonicalChainLengths[kNumBodyGroups] = {0.3f, 0.08f, 0.65f, 0.65f, 1.0f, 1.0f};

// The canonical body kBoneDirections poses, in leg lengths: an adult's proportions, rounded
// (both shared rigs measure upper arm 0.26–0.30, forearm 0.26–0.28, thigh ≈ shin ≈ 0.5).
struct CanonicalBody {
  static constexpr float kSpine = 0.3f;          // pelvis -> chest, along the spine's own shape
  static constexpr float kNeck = 0.1f;           // chest -> neck, along the spine's direction
  static constexpr float kHead = 0.08f;          // neck -> head joint, along the head's own shape
  static constexpr float kHalfShoulders = 0.2f;  // chest -> each shoulder, along the shoulder line
  static constexpr float kUpperArm = 0.3f;       // shoulder -> elbow
  static constexpr float kForearm = 0.3f;        // elbow -> wrist
  static constexpr float kHalfHips = 0.1f;       // pelvis -> each hip, along the hip line
  static constexpr float kThigh = 0.5f;          // hip -> knee
  static constexpr float kShin = 0.5f;           // knee -> ankle
};

struct BodyPointOptions {
  int points_per_group = 5;
  PointSampling sampling = PointSampling::kResampleChains;
  ChainScaling scaling = ChainScaling::kBoneDirections;
};

// The chains of a rig: per group, joint indices from the group's start to its end landmark
// (spine: pelvis -> the joint the arms branch off; head: neck -> head; arms: shoulder -> wrist;
// legs: hip joint -> ankle). The body scale (docs/method.md B2) is measured on each pose as the mean
// length of the two leg chains, which no rotation changes (the zero-rotation pose of real rigs
// is not a standing pose), so any length unit works.
struct BodyChains {
  std::array<std::vector<int>, kNumBodyGroups> joints;
  int pelvis = 0;
  // Per limb group, the index in `joints` of the elbow / knee landmark; -1 when the landmarks do
  // not name it (a pose sent as named joints): then the length rule of LimbBendByLength finds it.
  std::array<int, kNumBodyGroups> bend{-1, -1, -1, -1, -1, -1};
  // Per limb group, the index in `joints` of the shoulder / hip landmark (above `bend`); -1 when
  // unknown: then UpperSegmentStart's length rule finds it.
  std::array<int, kNumBodyGroups> root{-1, -1, -1, -1, -1, -1};
};
BodyChains MakeBodyChains(const Skeleton& skeleton, const BodyTopology& topology);

// Chains from landmarks a caller names (a pose sent as joint positions, no analysis): arms run
// from below the wrists' common ancestor to each wrist, legs from below the ankles' common
// ancestor to each ankle, the head from below its common ancestor with the wrists, the spine from
// the pelvis to the wrists' common ancestor. Elbows, knees, shoulders and hips are optional (-1:
// found by length, see BodyChains); a shoulder (hip) needs its elbow (knee). InvalidArgument when
// the landmarks do not form such a body (e.g. a wrist that is an ancestor of the other, an elbow
// outside its arm).
absl::StatusOr<BodyChains> ChainsFromLandmarks(const Skeleton& skeleton, const BodyLandmarks& landmarks);

// Body scale of one pose (docs/method.md B2): the mean length of the two leg chains; 1 when zero.
float BodyScale(const GlobalPoses& poses, int frame, const BodyChains& chains);

// Points of one pose: kNumBodyGroups x points_per_group, Y up, relative to the pelvis, in body
// scales (leg lengths), scaled as options.scaling says. `out` must hold kNumBodyGroups *
// points_per_group points.
void BodyPointsOfFrame(const GlobalPoses& poses, int frame, const BodyChains& chains, const BodyPointOptions& options,
                       Eigen::Vector3f* out);

// Points of every frame: frames x (kNumBodyGroups * points_per_group * 3) floats, row-major.
using BodyPointMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
BodyPointMatrix BodyPointsOfClip(const GlobalPoses& poses, const BodyChains& chains, const BodyPointOptions& options);

}  // namespace mocap
