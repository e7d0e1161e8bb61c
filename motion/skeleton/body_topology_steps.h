// The steps of AnalyseBody (body_topology.h), one function each, in the order AnalyseBody calls
// them. Internal to the skeleton analysis; declared here so that tests can check each step alone.
//
// Conventions: `poses` are the clip's world poses (ForwardKinematics), `frames` the frames that
// per-clip statistics sample (SampleFrames); joint indices are the skeleton's.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "motion/skeleton/body_topology.h"
#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/local_motion.h"
#include "motion/skeleton/skeleton.h"

namespace mocap::body_topology {

// Bones shorter than this fraction of the body size are helper joints (zero-length "pelvis",
// twist roots, share bones): merged into their parent for the branching analysis.
inline constexpr float kCollapseFraction = 0.02f;
// A leaf chain whose joints stay within this fraction of a sibling bone's length from that bone
// (in the clip's frames) is a twist/share overlay, not a limb.
inline constexpr float kOverlayDistanceFraction = 0.1f;
// Per-clip statistics look at this many frames at most, spread evenly over the clip.
inline constexpr int kMaxFramesSampled = 240;

// Distances along the bones of a skeleton (the tree metric) and walks in its hierarchy.
class TreeMetric {
 public:
  // `bone[j]`: length of the bone ending at joint j (bone[0] is ignored).
  TreeMetric(const Skeleton& skeleton, const Eigen::VectorXf& bone);

  int num_joints() const { return static_cast<int>(path_length_.size()); }
  // Deepest common ancestor of `a` and `b` (a joint is its own ancestor).
  int Lca(int a, int b) const;
  // Path length along the bones between `a` and `b`.
  float Distance(int a, int b) const { return path_length_[a] + path_length_[b] - 2 * path_length_[Lca(a, b)]; }
  // Path length from the root.
  float path_length(int j) const { return path_length_[j]; }
  // The child of `ancestor` on the path down to `descendant` (a strict descendant).
  int ChildToward(int ancestor, int descendant) const;
  // Joints from `top` down to `end`, inclusive.
  std::vector<int> Path(int top, int end) const;

 private:
  const Skeleton& skeleton_;
  std::vector<float> path_length_;
  std::vector<int> depth_;
};

// Up to kMaxFramesSampled frame indices spread evenly over `frames` frames, starting at 0.
std::vector<int> SampleFrames(int frames);

// ---------------------------------------------------------------------------------------------
// Step 1: the tree of real bones.

// Length of each joint's bone, averaged over the clip's frames. 0 for the root and for joints
// whose translation moves over the clip: such a joint carries the motion (as Bandai's Hips under
// a static joint_Root) and has no bone.
Eigen::VectorXf StaticBoneLengths(const LocalMotion& motion);

// Half the tree's diameter along the bones (found by a double sweep): a long static stem above
// the hips (an extra root node) does not make the body larger. 0 when there are no bones.
float BodySize(const TreeMetric& metric);

// The hierarchy with short bones merged into their parents.
struct MergedTree {
  std::vector<int> representative;         // per joint: the kept joint it is merged into (itself if kept)
  std::vector<std::vector<int>> children;  // per kept joint: its kept children
};
// Merges every joint whose bone is shorter than kCollapseFraction * body_size into its parent
// (the root is always kept).
MergedTree MergeShortBones(const Skeleton& skeleton, const Eigen::VectorXf& bone, float body_size);

// Marks the joints of leaf chains of `tree` that lie along a sibling bone over the sampled frames
// (twist and share bones): per chain joint, the mean distance to the sibling bone stays under
// kOverlayDistanceFraction of its length and the joint never projects beyond its ends. Of two
// chains overlaying each other (duplicates), the first is marked and the other kept as the limb.
std::vector<bool> FindOverlayChains(const Skeleton& skeleton, const MergedTree& tree, const GlobalPoses& poses,
                                    const std::vector<int>& frames);

// The leaves of `tree` that are not overlays (the root never counts), in joint order.
std::vector<int> LimbEndCandidates(const MergedTree& tree, const std::vector<bool>& overlay);

// ---------------------------------------------------------------------------------------------
// Step 2: the five limb ends.

// Farthest-point sampling with the tree metric: first the leaf farthest from the root along the
// bones, then repeatedly the leaf farthest from those already picked (ties: the earlier leaf).
// Needs at least five candidates.
std::array<int, 5> PickLimbEnds(const std::vector<int>& candidates, const TreeMetric& metric);

// ---------------------------------------------------------------------------------------------
// Step 3: head, limb pairs and pelvis.

// A limb as a chain hanging off the rest of the body.
struct Limb {
  int branch = -1;  // where it branches off: the deepest common ancestor with any other limb end
  int top = -1;     // its first joint: the child of `branch` toward `end`
  int end = -1;     // its end (a leaf)
};

struct HeadAndPairs {
  Limb head;
  // The four other limbs paired so that each pair's common ancestor is as deep as possible.
  std::array<Limb, 2> first_pair;
  std::array<Limb, 2> second_pair;
  int pelvis = -1;  // common ancestor of both pairs and the head
};
// The head is the limb end with the shortest chain from where it branches off (ties: the earlier
// end in `ends`).
HeadAndPairs FindHeadAndPairs(const std::array<int, 5>& ends, const TreeMetric& metric);

// ---------------------------------------------------------------------------------------------
// Step 4: up.

struct UpAxis {
  int axis = 1;            // 0, 1, 2: X, Y, Z
  int sign = 1;            // +1 or -1
  float alignment = 0.0f;  // cosine between the measured direction and the axis
};
// The signed world axis nearest `direction`.
UpAxis NearestAxis(const Eigen::Vector3f& direction);
// World up: the axis nearest the mean unit direction pelvis -> head end over the sampled frames.
UpAxis MeasureUp(const GlobalPoses& poses, const std::vector<int>& frames, int pelvis, int head_end);
// The same in the zero-rotation pose (often another axis: Z-up hierarchies).
UpAxis RestUp(const Skeleton& skeleton, int pelvis, int head_end);

// ---------------------------------------------------------------------------------------------
// Step 5: arms and legs.

struct ArmsAndLegs {
  std::array<Limb, 2> arms;
  std::array<Limb, 2> legs;
};
// The arms are the pair that branches off closer to the head (deeper common ancestor with the
// head end). When the tree cannot tell (a star rig), the arms are the pair whose ends are higher
// along `up`, summed over the sampled frames.
ArmsAndLegs SplitArmsAndLegs(const HeadAndPairs& body, const TreeMetric& metric, const GlobalPoses& poses,
                             const std::vector<int>& frames, const Eigen::Vector3f& up);

// ---------------------------------------------------------------------------------------------
// Step 6: where each limb bends and ends.

struct LimbJoints {
  int end = -1;     // wrist / ankle: the distal end of the more distal of the two longest segments
  int middle = -1;  // elbow / knee: the distal end of the more proximal of those two segments
  int start = -1;   // shoulder / hip: the proximal end of the more proximal of those two segments
};
// Splits the chain limb.top .. limb.end into segments at the joints where it really bends: a
// joint with one child that keeps its two bones within 2 degrees of straight in every sampled
// frame (a split bone, a roll joint) does not end a segment; with fewer than 10 sampled frames
// every joint ends one. `mirror`, the other limb of the pair: when its chain has as many joints,
// a joint must stay straight on both sides not to end a segment (an elbow held straight through
// a short clip still bends on the other arm). FailedPrecondition when the chain has fewer than
// two bones or segments.
absl::StatusOr<LimbJoints> FindLimbJoints(const Skeleton& skeleton, const TreeMetric& metric,
                                          const Eigen::VectorXf& bone, const Limb& limb, const GlobalPoses& poses,
                                          const std::vector<int>& frames, const Limb* mirror = nullptr);

// ---------------------------------------------------------------------------------------------
// Step 7: facing, left and right.

// `v` without its component along `up` (unit).
Eigen::Vector3f Horizontal(const Eigen::Vector3f& v, const Eigen::Vector3f& up);

// Knees bend forward: adds to `sum`, per leg and sampled frame, the horizontal part of the knee's
// offset from its projection on the hip-ankle line (unnormalised: strongly bent frames weigh more).
void AddKneeBendCue(const std::array<Limb, 2>& legs, const std::array<LimbJoints, 2>& leg_joints,
                    const GlobalPoses& poses, const std::vector<int>& frames, const Eigen::Vector3f& up,
                    Eigen::Vector3f* sum);
// Toes point forward in stance: adds to `sum` the horizontal ankle -> toe vector of each leg with a
// joint below the ankle, in the sampled frames where the toe is within 5% of `body_size` of its
// lowest height (a foot kicked back in a run points its toes backwards). Returns the longest
// ankle -> toe distance seen (0 without toes).
float AddToeCue(const std::array<Limb, 2>& legs, const std::array<LimbJoints, 2>& leg_joints, const TreeMetric& metric,
                const GlobalPoses& poses, const std::vector<int>& frames, const Eigen::Vector3f& up, float body_size,
                Eigen::Vector3f* sum);
// Forward (unit, horizontal): the knee and toe cues summed; when their sum is too short to trust
// (under 10% of the longer of the foot length and 5% of `body_size`), the pelvis' horizontal travel
// from the first to the last frame. FailedPrecondition when that is under 5% of `body_size` too.
absl::StatusOr<Eigen::Vector3f> MeasureForward(const ArmsAndLegs& limbs, const std::array<LimbJoints, 2>& leg_joints,
                                               int pelvis, const TreeMetric& metric, const GlobalPoses& poses,
                                               const std::vector<int>& frames, const Eigen::Vector3f& up,
                                               float body_size);

// How far the limb's top joint lies toward `left` of its branch joint, summed over the sampled frames.
float LateralOffset(const Limb& limb, const Eigen::Vector3f& left, const GlobalPoses& poses,
                    const std::vector<int>& frames);
// True when the first of the pair lies more to the left (see LateralOffset) than the second.
bool FirstIsLeft(const std::array<Limb, 2>& pair, const Eigen::Vector3f& left, const GlobalPoses& poses,
                 const std::vector<int>& frames);

// ---------------------------------------------------------------------------------------------
// Step 8: head landmark, groups, sizes.

// The first joint on the head chain (from its top) where the merged tree branches (the face and
// the rest of the skull), else the chain's end.
int HeadLandmark(const Limb& head, const TreeMetric& metric, const MergedTree& tree);

// The body's limbs, sided.
struct SidedLimbs {
  Limb head;
  Limb left_arm, right_arm, left_leg, right_leg;
};
// Sets group_of_joint, group_top and group_end of `topology`: each limb's group is the subtree of
// its top joint (top: the limb's first joint, end: its end); every other joint is spine, whose top
// is the skeleton root and whose end is `pelvis`.
void AssignGroups(const Skeleton& skeleton, const SidedLimbs& limbs, int pelvis, BodyTopology* topology);

// Mean over both legs of the bone lengths from the hip joint (the leg's top) down to the ankle.
float LegLength(const std::array<Limb, 2>& legs, const std::array<LimbJoints, 2>& leg_joints, const TreeMetric& metric,
                const Eigen::VectorXf& bone);

struct Heights {
  float standing_pelvis = 0.0f;  // median over all frames of the pelvis height above the lowest leg joint
  float floor = 0.0f;            // lowest leg joint height over the clip
};
// Heights along `up` over every frame of the clip. Only the leg groups' joints count as the floor:
// a static node above the hips (Bandai's joint_Root at the origin) must not.
Heights MeasureHeights(const std::vector<BodyGroup>& group_of_joint, int pelvis, const GlobalPoses& poses,
                       const Eigen::Vector3f& up);

}  // namespace mocap::body_topology
