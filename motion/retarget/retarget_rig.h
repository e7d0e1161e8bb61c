// A rig as the retargeting sees it (issue #12): its hierarchy in metres, the body analysis of
// docs/method.md B1 (AnalyseBody: groups, landmarks, elbows and knees; no joint names), and what the
// analysis implies for mapping one body onto another:
//  - chains (similarity's MakeBodyChains: spine pelvis -> chest, head neck -> head, arms from the
//    clavicle to the wrist, legs from the hip to the ankle), each cut into sections at anchors
//    both bodies have: the shoulder (hip), the elbow (knee) and the wrist (ankle);
//  - the rest pose (every rotation zero, as the file defines it: a T-pose, an A-pose or the
//    "every bone along one axis" pose of the shared rigs) and its body frame (up: pelvis ->
//    chest; left: right hip -> left hip), against which bone directions are aligned.
// Both the database's rig (the source) and the caller's rig (the target) are RetargetRigs.
//
// Thread safety: immutable after creation; share freely.
#pragma once

#include <array>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "absl/status/statusor.h"
#include "motion/bvh/bvh_clip.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/similarity/body_points.h"
#include "motion/skeleton/body_topology.h"

namespace mocap {

// Where a limb chain is cut: indices into its BodyChains joint list (top = 0, end = size - 1).
// Sections [0, root], [root, middle], [middle, end]: clavicle, upper arm, forearm (hip offset,
// thigh, shin).
struct LimbAnchors {
  int root = 0;    // shoulder / hip joint: the upper segment's start
  int middle = 1;  // elbow / knee
};

struct RetargetRig {
  Skeleton skeleton;      // offsets in metres, in the file's own axes (rest pose as the file has it)
  BodyTopology topology;  // landmarks and groups of `skeleton`
  BodyChains chains;
  std::array<LimbAnchors, kNumBodyGroups> anchors{};  // meaningful for the four limbs
  std::vector<Eigen::Vector3f> rest_positions;        // zero-rotation pose, metres
  // Body frame of the rest pose, as a rotation whose columns are (left, up, forward).
  Eigen::Matrix3f rest_body_frame = Eigen::Matrix3f::Identity();
  // Lengths along the rest bones, metres: hip -> knee -> ankle (mean of both legs) and per arm
  // shoulder -> elbow -> wrist.
  float leg_length = 0.0f;
  std::array<float, 2> arm_length{};  // left, right
  // Rest pose to world Y up: the rotation the importer applies (RigModel::to_y_up), and the
  // file's unit, so that results can be written back in the file's own axes and unit.
  Eigen::Quaternionf to_y_up = Eigen::Quaternionf::Identity();
  LengthUnit unit = LengthUnit::kMetre;
};

// `skeleton` in metres with its analysis. FailedPrecondition when a limb has no elbow/knee
// landmark, a chain is missing, or the rest pose has no usable body frame (hips on top of each
// other, a spine of zero length).
absl::StatusOr<RetargetRig> MakeRetargetRig(const Skeleton& skeleton_in_metres, const BodyTopology& topology);

// The database's rig: the body the reconstruction animates (metres, Y up). Rigs stored before
// elbows and knees were kept are analysed again on their reference pose for them.
absl::StatusOr<RetargetRig> SourceRigOf(const RigModel& rig, const Skeleton& body_skeleton);

// Limits on a caller's rig (checked before the analysis).
inline constexpr int kMaxTargetJoints = Skeleton::kMaxJoints;
inline constexpr int kMaxTargetFrames = 2000;  // frames of a target BVH used by the analysis

// A caller's rig from BVH text. The hierarchy defines the rig (joint order, names, offsets,
// channels); frames, when the text has a MOTION section, help the analysis (up axis, left and
// right) but are not needed for a rig whose zero-rotation pose is a standing one; at most
// kMaxTargetFrames are used. `unit`: the file's length unit when known (else detected from the
// body's size). InvalidArgument for text that is not BVH; FailedPrecondition, with the analysis'
// reason, for a rig that is not a recognisable humanoid.
absl::StatusOr<RetargetRig> TargetRigFromBvh(std::string_view text, std::optional<LengthUnit> unit = std::nullopt);
// The same from a clip already read (its frames, at most kMaxTargetFrames, help the analysis).
absl::StatusOr<RetargetRig> TargetRigFromClip(const BvhClip& clip, std::optional<LengthUnit> unit = std::nullopt);
// A caller's rig given as joints (parents before children, offsets in the rig's unit and axes);
// the analysis sees only the zero-rotation pose, which must be a standing one (T- or A-pose).
absl::StatusOr<RetargetRig> TargetRigFromSkeleton(const Skeleton& skeleton,
                                                  std::optional<LengthUnit> unit = std::nullopt);

}  // namespace mocap
