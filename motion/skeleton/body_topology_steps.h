// The steps of AnalyseBody (body_topology.h), one function each, in the order AnalyseBody calls
// them. Internal to the skeleton analysis; declared here so that tests can check each step alone.
//
// Conventions: `poses` are the clip's world poses (ForwardKinematics), `frames` the frames that
// per-clip statistics sample (SampleFrames); joint indices are the skeleton's.
#pragma once

#include <array>
#include <optional>
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
  const Skeleton& skeleton() const { return skeleton_; }

 private:
  const Skeleton& skeleton_;
  std::vector<float> path_length_;
  std::vector<int> depth_;
};

// Up to kMaxFramesSampled frame indices spread evenly over `frames` frames, starting at 0.
std::vector<int> SampleFrames(int frames);

// Mean distance between joints `a` and `b` over the sampled frames.
float MeanDistance(const GlobalPoses& poses, const std::vector<int>& frames, int a, int b);

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

// A sixth limb: the candidate (not one of `ends`) on the longest branch off the body the five ends
// span, when that branch is at least kExtraLimbFraction of the shortest arm or leg (each end's own
// branch off the other four; the head's, the shortest, aside). A person's other leaves (fingers,
// toes, face, breast and twist bones) branch off briefly; a creature's third leg or second pair
// of arms is as long as a limb (issue #24: an eight-legged rig was taken for a human). nullopt
// when there is none.
inline constexpr float kExtraLimbFraction = 0.5f;
std::optional<int> ExtraLimb(const std::vector<int>& candidates, const std::array<int, 5>& ends,
                             const TreeMetric& metric);

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
// a short clip still bends on the other arm).
// `min_start_separation` (same unit as the poses; 0: no such rule), with a mirror of as many
// joints: the upper long segment cannot start at a joint that lies, on average over the sampled
// frames, nearer than this to its mirror joint. A clavicle starts near the middle of the chest and
// may be longer than the forearm (the CMU rig); the upper arm starts at the shoulder, and the two
// shoulders lie wider apart than the two hips (AnalyseBody passes the hips' separation for the
// arms). The leading segments that start nearer are skipped when at least two segments remain,
// each only while it is shorter than a segment after it (a clavicle is never the limb's longest
// bone: the upper arm of a body whose shoulders are no wider than its hips stays).
// FailedPrecondition when the chain has fewer than two bones or segments.
absl::StatusOr<LimbJoints> FindLimbJoints(const Skeleton& skeleton, const TreeMetric& metric,
                                          const Eigen::VectorXf& bone, const Limb& limb, const GlobalPoses& poses,
                                          const std::vector<int>& frames, const Limb* mirror = nullptr,
                                          float min_start_separation = 0.0f);

// ---------------------------------------------------------------------------------------------
// Step 7: facing, left and right, frame by frame.
//
// Every cue is read in its own frame against that frame's own body: a clip that turns (a walk in
// a circle) has no mean facing direction, and a clip's mean says nothing about which limb is on
// which side. Per sampled frame, the hip line (left hip minus right hip, if the first leg is the
// left one) gives the facing up to its sign, forward = hip line x up (docs/method.md B1 step 1: sides
// from the cross product with the up vector, here per frame); the anatomical cues of that same
// frame (knees bend forward, toes point forward in stance) give the sign. The arms are then sided
// against the same per-frame body: the left shoulder lies toward that frame's left.

// `v` without its component along `up` (unit).
Eigen::Vector3f Horizontal(const Eigen::Vector3f& v, const Eigen::Vector3f& up);

// Knees bend forward: adds to `per_frame[i]`, for frames[i] and each leg, the horizontal part of
// the knee's offset from its projection on the hip-ankle line (unnormalised: strongly bent frames
// weigh more; the hip is the leg's `start`, else its first joint). `per_frame` has one vector per
// sampled frame.
void AddKneeBendCue(const std::array<Limb, 2>& legs, const std::array<LimbJoints, 2>& leg_joints,
                    const GlobalPoses& poses, const std::vector<int>& frames, const Eigen::Vector3f& up,
                    std::vector<Eigen::Vector3f>* per_frame);
// Toes point forward in stance: adds to `per_frame[i]` the horizontal ankle -> toe vector of each
// leg, in the sampled frames where the toe is within 5% of `body_size` of its lowest height over
// the sampled frames (a foot kicked back in a run points its toes backwards). The toe is the joint
// below the ankle, else the ankle's End Site when the leg ends at the ankle (a foot drawn only by
// its End Site); legs with neither add nothing. Returns the longest ankle -> toe distance seen (0
// without toes).
float AddToeCue(const std::array<Limb, 2>& legs, const std::array<LimbJoints, 2>& leg_joints, const TreeMetric& metric,
                const GlobalPoses& poses, const std::vector<int>& frames, const Eigen::Vector3f& up, float body_size,
                std::vector<Eigen::Vector3f>* per_frame);

// Per sampled frame, the horizontal vector from the second limb of a pair to the first: between
// their `start` joints (hips, shoulders), or their `middle` joints when the rig puts both starts at
// the same place over the sampled frames.
std::vector<Eigen::Vector3f> PairLines(const std::array<LimbJoints, 2>& joints, const GlobalPoses& poses,
                                       const std::vector<int>& frames, const Eigen::Vector3f& up);

struct Sides {
  bool first_leg_is_left = true;
  bool first_arm_is_left = true;
  // Mean facing over the sampled frames (unit, horizontal); the first frame's when the clip turns
  // so much that the mean is shorter than half a unit.
  Eigen::Vector3f forward = Eigen::Vector3f::UnitZ();
};
// Sides both pairs (see the comment above this step). The knee and toe cues decide the legs; when
// they are too weak (their projections on the per-frame facings sum under 10% of the longer of the
// foot length and 5% of `body_size`: straight legs and no toe joints), the pelvis' horizontal
// travel between consecutive sampled frames, each step against its own frame's facing (a walk is
// taken to go forward). FailedPrecondition when that sums under 5% of `body_size` too.
// The arms: the first arm is left when its shoulder lies toward the left of the per-frame body
// (summed over the sampled frames).
absl::StatusOr<Sides> FindSides(const ArmsAndLegs& limbs, const std::array<LimbJoints, 2>& arm_joints,
                                const std::array<LimbJoints, 2>& leg_joints, int pelvis, const TreeMetric& metric,
                                const GlobalPoses& poses, const std::vector<int>& frames, const Eigen::Vector3f& up,
                                float body_size);

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
