// Each step of AnalyseBody alone (motion/skeleton/body_topology_steps.h): hand-built trees and
// poses where the answer is easy to work out, and the synthetic walking rig where its joint names
// are the answer key. body_topology_test.cc checks the steps together.
#include "motion/skeleton/body_topology_steps.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "motion/bvh/bvh_clip.h"
#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/local_motion.h"
#include "tests/support/rig_variants.h"
#include "tests/support/synthetic_clip.h"

namespace mocap::body_topology {
namespace {

std::string NameOf(const Skeleton& skeleton, int index) {
  return index >= 0 && index < skeleton.num_joints() ? skeleton.joint(index).name : "<" + std::to_string(index) + ">";
}

std::vector<std::string> NamesOf(const Skeleton& skeleton, const std::vector<int>& indices) {
  std::vector<std::string> names;
  for (int index : indices) names.push_back(NameOf(skeleton, index));
  return names;
}

std::vector<std::string> Sorted(std::vector<std::string> names) {
  std::sort(names.begin(), names.end());
  return names;
}

// World positions given per frame (one row of joint positions per frame).
GlobalPoses PosesOf(const std::vector<std::vector<Eigen::Vector3f>>& frames) {
  GlobalPoses poses;
  const int rows = static_cast<int>(frames.size());
  const int joints = static_cast<int>(frames[0].size());
  for (Eigen::ArrayXXf* array : {&poses.px, &poses.py, &poses.pz, &poses.qw, &poses.qx, &poses.qy, &poses.qz}) {
    array->setZero(rows, joints);
  }
  poses.qw.setOnes();
  for (int f = 0; f < rows; ++f) {
    for (int j = 0; j < joints; ++j) {
      poses.px(f, j) = frames[f][j].x();
      poses.py(f, j) = frames[f][j].y();
      poses.pz(f, j) = frames[f][j].z();
    }
  }
  return poses;
}

// Bone lengths of a rig from its OFFSETs (0 for the root).
Eigen::VectorXf OffsetLengths(const Skeleton& skeleton) {
  Eigen::VectorXf bone(skeleton.num_joints());
  for (int j = 0; j < skeleton.num_joints(); ++j) bone[j] = j == 0 ? 0.0f : skeleton.joint(j).offset.norm();
  return bone;
}

// The synthetic walking clip with the first steps' results, as AnalyseBody computes them.
struct WalkingClip {
  explicit WalkingClip(const testing::SyntheticRigOptions& options = {}, int frame_count = 40)
      : WalkingClip(testing::MakeWalkingClip(options, frame_count)) {}
  explicit WalkingClip(BvhClip clip)
      : bvh(std::move(clip)),
        skeleton(bvh.skeleton),
        motion(MotionFromChannels(skeleton, bvh.channels, bvh.frame_time)),
        poses(ForwardKinematics(skeleton, motion)),
        frames(SampleFrames(motion.num_frames())),
        bone(StaticBoneLengths(motion)),
        metric(skeleton, bone),
        body_size(BodySize(metric)),
        tree(MergeShortBones(skeleton, bone, body_size)) {}
  WalkingClip(const WalkingClip&) = delete;
  WalkingClip& operator=(const WalkingClip&) = delete;

  int operator[](const std::string& name) const {
    const int index = skeleton.Find(name);
    EXPECT_GE(index, 0) << "no joint " << name;
    return index;
  }
  HeadAndPairs Body() const {
    return FindHeadAndPairs(
        PickLimbEnds(LimbEndCandidates(tree, FindOverlayChains(skeleton, tree, poses, frames)), metric), metric);
  }

  const BvhClip bvh;
  const Skeleton& skeleton;
  const LocalMotion motion;
  const GlobalPoses poses;
  const std::vector<int> frames;
  const Eigen::VectorXf bone;
  const TreeMetric metric;
  const float body_size;
  const MergedTree tree;
};

// ---------------------------------------------------------------------------------------------
// Helpers shared by the steps.

TEST(BodyStepTreeMetricTest, DistancesAndWalks) {
  // Root -> A (10) -> B (20); Root -> C (5) -> D (7).
  const Skeleton skeleton({Joint{.name = "Root", .parent = -1}, Joint{.name = "A", .parent = 0, .offset = {10, 0, 0}},
                           Joint{.name = "B", .parent = 1, .offset = {20, 0, 0}},
                           Joint{.name = "C", .parent = 0, .offset = {0, 5, 0}},
                           Joint{.name = "D", .parent = 3, .offset = {0, 7, 0}}});
  const Eigen::VectorXf bone = OffsetLengths(skeleton);
  const TreeMetric metric(skeleton, bone);
  EXPECT_EQ(metric.num_joints(), 5);
  EXPECT_FLOAT_EQ(metric.path_length(2), 30.0f);
  EXPECT_FLOAT_EQ(metric.path_length(4), 12.0f);
  EXPECT_EQ(metric.Lca(2, 4), 0);
  EXPECT_EQ(metric.Lca(1, 2), 1);
  EXPECT_EQ(metric.Lca(2, 2), 2);
  EXPECT_FLOAT_EQ(metric.Distance(2, 4), 42.0f);
  EXPECT_FLOAT_EQ(metric.Distance(1, 2), 20.0f);
  EXPECT_EQ(metric.ChildToward(0, 2), 1);
  EXPECT_EQ(metric.ChildToward(0, 4), 3);
  EXPECT_EQ(metric.Path(0, 2), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(metric.Path(3, 4), (std::vector<int>{3, 4}));
}

TEST(BodyStepSampleFramesTest, AllFramesOfAShortClipEvenlySpreadOfALongOne) {
  EXPECT_EQ(SampleFrames(1), (std::vector<int>{0}));
  EXPECT_EQ(SampleFrames(4), (std::vector<int>{0, 1, 2, 3}));
  const std::vector<int> sample = SampleFrames(3 * kMaxFramesSampled);
  ASSERT_EQ(static_cast<int>(sample.size()), kMaxFramesSampled);
  EXPECT_EQ(sample[0], 0);
  EXPECT_EQ(sample[1], 3);
  EXPECT_EQ(sample.back(), 3 * kMaxFramesSampled - 3);
}

// ---------------------------------------------------------------------------------------------
// Step 1: the tree of real bones.

TEST(BodyStepStaticBoneLengthsTest, JointsWhoseTranslationMovesHaveNoBone) {
  // Root, Hips carrying the travel in its translation, a static Spine above it.
  LocalMotion motion;
  motion.Resize(3, 3);
  motion.qw.setOnes();
  motion.qx.setZero();
  motion.qy.setZero();
  motion.qz.setZero();
  for (int f = 0; f < 3; ++f) {
    motion.SetTranslation(f, 0, Eigen::Vector3f(5.0f * f, 0, 0));
    motion.SetTranslation(f, 1, Eigen::Vector3f(0, 90, 10.0f * f));
    // A rounding-size wobble is not motion.
    motion.SetTranslation(f, 2, Eigen::Vector3f(0, 30.0f + 1e-4f * f, 0));
  }
  const Eigen::VectorXf bone = StaticBoneLengths(motion);
  ASSERT_EQ(bone.size(), 3);
  EXPECT_EQ(bone[0], 0.0f);
  EXPECT_EQ(bone[1], 0.0f);
  EXPECT_NEAR(bone[2], 30.0f, 1e-3f);
}

TEST(BodyStepStaticBoneLengthsTest, SyntheticRigWithAnExtraRoot) {
  testing::SyntheticRigOptions options;
  options.extra_root = true;
  const WalkingClip clip(options);
  EXPECT_EQ(clip.bone[clip["Root"]], 0.0f);
  EXPECT_EQ(clip.bone[clip["Hips"]], 0.0f);  // carries the walk
  EXPECT_NEAR(clip.bone[clip["Spine"]], 10.0f, 1e-4f);
  EXPECT_NEAR(clip.bone[clip["LeftLeg"]], testing::kSyntheticThighLength, 1e-4f);
}

TEST(BodyStepBodySizeTest, HalfTheLongestLeafToLeafPathNotTheStemAboveIt) {
  // Root -> Stem (30) -> A (50) and Stem -> B (80): 110 from the root to B, 130 from A to B.
  const Skeleton skeleton(
      {Joint{.name = "Root", .parent = -1}, Joint{.name = "Stem", .parent = 0, .offset = {0, 30, 0}},
       Joint{.name = "A", .parent = 1, .offset = {50, 0, 0}}, Joint{.name = "B", .parent = 1, .offset = {-80, 0, 0}}});
  const Eigen::VectorXf bone = OffsetLengths(skeleton);
  EXPECT_FLOAT_EQ(BodySize(TreeMetric(skeleton, bone)), 65.0f);
  const Eigen::VectorXf no_bones = Eigen::VectorXf::Zero(4);
  EXPECT_EQ(BodySize(TreeMetric(skeleton, no_bones)), 0.0f);
}

TEST(BodyStepMergeShortBonesTest, ShortBonesMergeIntoTheirParent) {
  // Root -> Zero (0) -> Long (50) -> Tiny (0.5) -> Tip (30); threshold 2% of 40 = 0.8.
  const Skeleton skeleton({Joint{.name = "Root", .parent = -1}, Joint{.name = "Zero", .parent = 0},
                           Joint{.name = "Long", .parent = 1, .offset = {0, 50, 0}},
                           Joint{.name = "Tiny", .parent = 2, .offset = {0, 0.5f, 0}},
                           Joint{.name = "Tip", .parent = 3, .offset = {0, 30, 0}}});
  const MergedTree tree = MergeShortBones(skeleton, OffsetLengths(skeleton), 40.0f);
  EXPECT_EQ(tree.representative, (std::vector<int>{0, 0, 2, 2, 4}));
  EXPECT_EQ(tree.children[0], (std::vector<int>{2}));
  EXPECT_TRUE(tree.children[1].empty());
  EXPECT_EQ(tree.children[2], (std::vector<int>{4}));
  EXPECT_TRUE(tree.children[3].empty());
  EXPECT_TRUE(tree.children[4].empty());
}

TEST(BodyStepMergeShortBonesTest, HelperJointsOfTheSyntheticTwistRig) {
  testing::SyntheticRigOptions options;
  options.twist_bones = true;
  const WalkingClip clip(options);
  auto representative = [&](const std::string& name) {
    return NameOf(clip.skeleton, clip.tree.representative[clip[name]]);
  };
  EXPECT_EQ(representative("Pelvis"), "Hips");
  EXPECT_EQ(representative("LeftKneeShareBone"), "LeftLeg");
  EXPECT_EQ(representative("LeftUpLegTwist"), "LeftUpLeg");
  EXPECT_EQ(representative("LeftUpLegTwistMid"), "LeftUpLegTwistMid");
  EXPECT_EQ(representative("LeftFoot"), "LeftFoot");
  // The thighs hang off the zero-length Pelvis: in the merged tree, off Hips.
  EXPECT_EQ(Sorted(NamesOf(clip.skeleton, clip.tree.children[clip["Hips"]])),
            Sorted({"Spine", "LeftUpLeg", "RightUpLeg"}));
  EXPECT_EQ(Sorted(NamesOf(clip.skeleton, clip.tree.children[clip["LeftUpLeg"]])),
            Sorted({"LeftLeg", "LeftUpLegTwistMid"}));
}

TEST(BodyStepFindOverlayChainsTest, TwistChainsOfTheSyntheticRigAndNothingElse) {
  testing::SyntheticRigOptions options;
  options.twist_bones = true;
  const WalkingClip clip(options);
  const std::vector<bool> overlay = FindOverlayChains(clip.skeleton, clip.tree, clip.poses, clip.frames);
  std::vector<int> marked;
  for (int j = 0; j < clip.skeleton.num_joints(); ++j) {
    if (overlay[j]) marked.push_back(j);
  }
  EXPECT_EQ(Sorted(NamesOf(clip.skeleton, marked)),
            Sorted({"LeftArmTwistMid", "LeftForeArmTwistMid", "RightArmTwistMid", "RightForeArmTwistMid",
                    "LeftUpLegTwistMid", "LeftLegTwistMid", "RightUpLegTwistMid", "RightLegTwistMid"}));
}

// Root with two identical bones down and one up; `extra` adds a leaf half-way along the first.
Skeleton HubWithDuplicates(bool extra) {
  std::vector<Joint> joints = {Joint{.name = "Root", .parent = -1, .offset = {0, 100, 0}},
                               Joint{.name = "Down", .parent = 0, .offset = {0, -40, 0}},
                               Joint{.name = "DownCopy", .parent = 0, .offset = {0, -40, 0}},
                               Joint{.name = "Up", .parent = 0, .offset = {0, 40, 0}}};
  if (extra) joints.push_back(Joint{.name = "HalfDown", .parent = 0, .offset = {0.5f, -20, 0}});
  return Skeleton(std::move(joints));
}

TEST(BodyStepFindOverlayChainsTest, OfTwoDuplicatesTheFirstIsTheOverlay) {
  const Skeleton skeleton = HubWithDuplicates(false);
  const Eigen::VectorXf bone = OffsetLengths(skeleton);
  const MergedTree tree = MergeShortBones(skeleton, bone, 40.0f);
  const GlobalPoses poses = ForwardKinematics(skeleton, RestMotion(skeleton));
  EXPECT_EQ(FindOverlayChains(skeleton, tree, poses, {0}), (std::vector<bool>{false, true, false, false}));
}

TEST(BodyStepFindOverlayChainsTest, AChainOverlaysOnlyABoneItLiesWithin) {
  // HalfDown lies within the kept copy of Down (0.5 away from it): an overlay. Neither Down nor
  // its copy counts as overlaying HalfDown: they reach beyond its end.
  const Skeleton skeleton = HubWithDuplicates(true);
  const Eigen::VectorXf bone = OffsetLengths(skeleton);
  const MergedTree tree = MergeShortBones(skeleton, bone, 40.0f);
  const GlobalPoses poses = ForwardKinematics(skeleton, RestMotion(skeleton));
  const std::vector<bool> overlay = FindOverlayChains(skeleton, tree, poses, {0});
  EXPECT_FALSE(overlay[skeleton.Find("Up")]);
  EXPECT_TRUE(overlay[skeleton.Find("HalfDown")]);
  EXPECT_NE(overlay[skeleton.Find("Down")], overlay[skeleton.Find("DownCopy")]);
}

TEST(BodyStepLimbEndCandidatesTest, KeptLeavesThatAreNotOverlays) {
  // Root -> 1 -> 2 (leaf), Root -> 3 (leaf, overlay), Root -> 4 (merged into Root) -> 5 (leaf).
  MergedTree tree;
  tree.representative = {0, 1, 2, 3, 0, 5};
  tree.children = {{1, 3, 5}, {2}, {}, {}, {}, {}};
  EXPECT_EQ(LimbEndCandidates(tree, {false, false, false, true, false, false}), (std::vector<int>{2, 5}));
  EXPECT_EQ(LimbEndCandidates(tree, std::vector<bool>(6, false)), (std::vector<int>{2, 3, 5}));
}

// ---------------------------------------------------------------------------------------------
// Step 2: the five limb ends.

TEST(BodyStepPickLimbEndsTest, FarthestPointOrderLeavesOutTheShortestLeaf) {
  // Six single-bone limbs off the root: lengths 10, 50, 40, 30, 20, 5.
  std::vector<Joint> joints = {Joint{.name = "Root", .parent = -1}};
  for (float length : {10.0f, 50.0f, 40.0f, 30.0f, 20.0f, 5.0f}) {
    joints.push_back(
        Joint{.name = "L" + std::to_string(static_cast<int>(length)), .parent = 0, .offset = {length, 0, 0}});
  }
  const Skeleton skeleton(std::move(joints));
  const Eigen::VectorXf bone = OffsetLengths(skeleton);
  const TreeMetric metric(skeleton, bone);
  // First the farthest from the root, then each time the leaf farthest from those picked.
  EXPECT_EQ(PickLimbEnds({1, 2, 3, 4, 5, 6}, metric), (std::array<int, 5>{2, 3, 4, 5, 1}));
}

TEST(BodyStepPickLimbEndsTest, HandsFeetAndHeadOfTheSyntheticRigWithFingersAndToes) {
  testing::SyntheticRigOptions options;
  options.fingers_and_toes = true;
  const WalkingClip clip(options);
  const std::vector<int> candidates =
      LimbEndCandidates(clip.tree, FindOverlayChains(clip.skeleton, clip.tree, clip.poses, clip.frames));
  const std::array<int, 5> ends = PickLimbEnds(candidates, clip.metric);
  std::vector<std::string> groups;
  for (int end : ends) {
    const std::string name = NameOf(clip.skeleton, end);
    if (name == "Head")
      groups.push_back("head");
    else if (name.starts_with("LeftHand"))
      groups.push_back("left hand");
    else if (name.starts_with("RightHand"))
      groups.push_back("right hand");
    else if (name.starts_with("LeftToe"))
      groups.push_back("left foot");
    else if (name.starts_with("RightToe"))
      groups.push_back("right foot");
    else
      groups.push_back(name);
  }
  EXPECT_EQ(Sorted(groups), Sorted({"head", "left hand", "right hand", "left foot", "right foot"}));
}

TEST(BodyStepExtraLimbTest, ACreaturesSixthLimbButNotAPersonsFingersAndToes) {
  // Seven equal limbs of two bones off the root (an eight-legged creature's body, less one leg).
  std::vector<Joint> joints = {Joint{.name = "Body", .parent = -1}};
  for (int limb = 0; limb < 7; ++limb) {
    const float angle = static_cast<float>(limb) * 0.9f;
    const Eigen::Vector3f out(std::cos(angle), 0.0f, std::sin(angle));
    joints.push_back(Joint{.name = "Upper" + std::to_string(limb), .parent = 0, .offset = 40.0f * out});
    joints.push_back(Joint{.name = "Lower" + std::to_string(limb),
                           .parent = static_cast<int>(joints.size()) - 1,
                           .offset = Eigen::Vector3f(0, -40, 0)});
  }
  const Skeleton creature(std::move(joints));
  const TreeMetric metric(creature, OffsetLengths(creature));
  const std::vector<int> leaves = {2, 4, 6, 8, 10, 12, 14};
  const std::optional<int> extra = ExtraLimb(leaves, PickLimbEnds(leaves, metric), metric);
  ASSERT_TRUE(extra.has_value());
  EXPECT_TRUE(NameOf(creature, *extra).starts_with("Lower"));

  testing::SyntheticRigOptions options;
  options.fingers_and_toes = true;
  const WalkingClip person(options);
  const std::vector<int> candidates =
      LimbEndCandidates(person.tree, FindOverlayChains(person.skeleton, person.tree, person.poses, person.frames));
  ASSERT_GT(candidates.size(), 5u);  // fingers and toes are leaves too
  EXPECT_FALSE(ExtraLimb(candidates, PickLimbEnds(candidates, person.metric), person.metric).has_value());
}

// ---------------------------------------------------------------------------------------------
// Step 3: head, pairs, pelvis.

TEST(BodyStepFindHeadAndPairsTest, SyntheticRig) {
  const WalkingClip clip;
  const std::array<int, 5> ends = {clip["LeftHand"], clip["RightToeBase"], clip["Head"], clip["RightHand"],
                                   clip["LeftToeBase"]};
  const HeadAndPairs body = FindHeadAndPairs(ends, clip.metric);
  EXPECT_EQ(NameOf(clip.skeleton, body.head.end), "Head");
  EXPECT_EQ(NameOf(clip.skeleton, body.head.top), "Neck");
  EXPECT_EQ(NameOf(clip.skeleton, body.head.branch), "Chest");
  EXPECT_EQ(NameOf(clip.skeleton, body.pelvis), "Hips");
  // Pairs in the order of their first end in `ends`.
  EXPECT_EQ(NamesOf(clip.skeleton, {body.first_pair[0].end, body.first_pair[1].end}),
            (std::vector<std::string>{"LeftHand", "RightHand"}));
  EXPECT_EQ(NamesOf(clip.skeleton, {body.second_pair[0].end, body.second_pair[1].end}),
            (std::vector<std::string>{"RightToeBase", "LeftToeBase"}));
  EXPECT_EQ(NameOf(clip.skeleton, body.first_pair[0].top), "LeftShoulder");
  EXPECT_EQ(NameOf(clip.skeleton, body.first_pair[0].branch), "Chest");
  EXPECT_EQ(NameOf(clip.skeleton, body.second_pair[1].top), "LeftUpLeg");
  EXPECT_EQ(NameOf(clip.skeleton, body.second_pair[1].branch), "Hips");
}

TEST(BodyStepFindHeadAndPairsTest, HeadIsTheShortestChainNotTheEndNearestTheRoot) {
  // Root -> Trunk (60) -> Neck (5) -> Head (5); Trunk -> two arms of 2 x 30; Root -> two legs
  // of 2 x 20. The feet end nearest the root (40, the head 70), but the head's chain from where
  // it branches off (Trunk) is the shortest (10).
  std::vector<Joint> joints = {
      Joint{.name = "Root", .parent = -1}, Joint{.name = "Trunk", .parent = 0, .offset = {0, 60, 0}},
      Joint{.name = "Neck", .parent = 1, .offset = {0, 5, 0}}, Joint{.name = "Head", .parent = 2, .offset = {0, 5, 0}}};
  auto add_limb = [&](const std::string& name, int parent, const Eigen::Vector3f& bone) {
    joints.push_back(Joint{.name = name + "1", .parent = parent, .offset = bone});
    joints.push_back(Joint{.name = name + "2", .parent = static_cast<int>(joints.size()) - 1, .offset = bone});
    return static_cast<int>(joints.size()) - 1;
  };
  const int left_hand = add_limb("LeftArm", 1, {30, 0, 0});
  const int right_hand = add_limb("RightArm", 1, {-30, 0, 0});
  const int left_foot = add_limb("LeftLeg", 0, {0, -20, 0});
  const int right_foot = add_limb("RightLeg", 0, {0, -20, 0});
  const Skeleton skeleton(std::move(joints));
  const Eigen::VectorXf bone = OffsetLengths(skeleton);
  const TreeMetric metric(skeleton, bone);
  const HeadAndPairs body = FindHeadAndPairs({left_foot, 3, left_hand, right_foot, right_hand}, metric);
  EXPECT_EQ(body.head.end, 3);
  EXPECT_EQ(body.head.top, 2);
  EXPECT_EQ(body.head.branch, 1);
  EXPECT_EQ(body.first_pair[0].end, left_foot);
  EXPECT_EQ(body.first_pair[1].end, right_foot);
  EXPECT_EQ(body.second_pair[0].end, left_hand);
  EXPECT_EQ(body.second_pair[1].end, right_hand);
  EXPECT_EQ(body.pelvis, 0);
}

// ---------------------------------------------------------------------------------------------
// Step 4: up.

TEST(BodyStepNearestAxisTest, SignedAxisAndAlignment) {
  const UpAxis up = NearestAxis(Eigen::Vector3f(0.1f, -0.9f, 0.2f));
  EXPECT_EQ(up.axis, 1);
  EXPECT_EQ(up.sign, -1);
  EXPECT_FLOAT_EQ(up.alignment, 0.9f / Eigen::Vector3f(0.1f, -0.9f, 0.2f).norm());
  const UpAxis z = NearestAxis(Eigen::Vector3f(0.0f, 0.0f, 3.0f));
  EXPECT_EQ(z.axis, 2);
  EXPECT_EQ(z.sign, 1);
  EXPECT_FLOAT_EQ(z.alignment, 1.0f);
  EXPECT_EQ(NearestAxis(Eigen::Vector3f::Zero()).alignment, 0.0f);
}

TEST(BodyStepMeasureUpTest, ClipUpAndRestUpOfAZUpHierarchy) {
  testing::SyntheticRigOptions options;
  options.z_up = true;
  const WalkingClip clip(options);
  const UpAxis up = MeasureUp(clip.poses, clip.frames, clip["Hips"], clip["Head"]);
  EXPECT_EQ(up.axis, 1);
  EXPECT_EQ(up.sign, 1);
  EXPECT_GT(up.alignment, 0.95f);
  const UpAxis rest = RestUp(clip.skeleton, clip["Hips"], clip["Head"]);
  EXPECT_EQ(rest.axis, 2);
  EXPECT_EQ(rest.sign, 1);
}

TEST(BodyStepMeasureUpTest, MeanDirectionOverTheSampledFramesOnly) {
  // Pelvis at the origin, head end along -X in frame 0 and along +Y in frames 1 and 2.
  const GlobalPoses poses = PosesOf({{Eigen::Vector3f::Zero(), Eigen::Vector3f(-50, 0, 0)},
                                     {Eigen::Vector3f::Zero(), Eigen::Vector3f(0, 50, 0)},
                                     {Eigen::Vector3f::Zero(), Eigen::Vector3f(0, 50, 0)}});
  EXPECT_EQ(MeasureUp(poses, {0, 1, 2}, 0, 1).axis, 1);
  const UpAxis first = MeasureUp(poses, {0}, 0, 1);
  EXPECT_EQ(first.axis, 0);
  EXPECT_EQ(first.sign, -1);
}

// ---------------------------------------------------------------------------------------------
// Step 5: arms and legs.

TEST(BodyStepSplitArmsAndLegsTest, ArmsBranchOffCloserToTheHead) {
  const WalkingClip clip;
  HeadAndPairs body = clip.Body();
  for (int swap = 0; swap < 2; ++swap) {
    if (swap) std::swap(body.first_pair, body.second_pair);
    const ArmsAndLegs limbs = SplitArmsAndLegs(body, clip.metric, clip.poses, clip.frames, Eigen::Vector3f::UnitY());
    EXPECT_EQ(Sorted(NamesOf(clip.skeleton, {limbs.arms[0].end, limbs.arms[1].end})),
              Sorted({"LeftHand", "RightHand"}));
    EXPECT_EQ(Sorted(NamesOf(clip.skeleton, {limbs.legs[0].end, limbs.legs[1].end})),
              Sorted({"LeftToeBase", "RightToeBase"}));
  }
}

TEST(BodyStepSplitArmsAndLegsTest, OnAStarRigTheHigherPairAreTheArms) {
  // Every limb branches off the root: the tree cannot tell, the heights do.
  const Skeleton skeleton({Joint{.name = "Root", .parent = -1, .offset = {0, 100, 0}},
                           Joint{.name = "Head", .parent = 0, .offset = {0, 20, 0}},
                           Joint{.name = "LegA", .parent = 0, .offset = {10, -90, 0}},
                           Joint{.name = "LegB", .parent = 0, .offset = {-10, -90, 0}},
                           Joint{.name = "ArmA", .parent = 0, .offset = {60, 10, 0}},
                           Joint{.name = "ArmB", .parent = 0, .offset = {-60, 10, 0}}});
  const Eigen::VectorXf bone = OffsetLengths(skeleton);
  const TreeMetric metric(skeleton, bone);
  const GlobalPoses poses = ForwardKinematics(skeleton, RestMotion(skeleton));
  auto limb = [](int end) { return Limb{.branch = 0, .top = end, .end = end}; };
  HeadAndPairs body{.head = limb(1), .first_pair = {limb(2), limb(3)}, .second_pair = {limb(4), limb(5)}, .pelvis = 0};
  ArmsAndLegs limbs = SplitArmsAndLegs(body, metric, poses, {0}, Eigen::Vector3f::UnitY());
  EXPECT_EQ(limbs.arms[0].end, 4);
  EXPECT_EQ(limbs.legs[0].end, 2);
  // Upside down, the legs are higher.
  limbs = SplitArmsAndLegs(body, metric, poses, {0}, -Eigen::Vector3f::UnitY());
  EXPECT_EQ(limbs.arms[0].end, 2);
  EXPECT_EQ(limbs.legs[0].end, 4);
}

// ---------------------------------------------------------------------------------------------
// Step 6: where each limb bends and ends.

TEST(BodyStepFindLimbJointsTest, WristElbowAnkleKneeOfTheSyntheticRig) {
  const WalkingClip clip;
  auto limb = [&](const std::string& top, const std::string& end) {
    return Limb{.branch = clip.skeleton.parent(clip[top]), .top = clip[top], .end = clip[end]};
  };
  absl::StatusOr<LimbJoints> arm =
      FindLimbJoints(clip.skeleton, clip.metric, clip.bone, limb("LeftShoulder", "LeftHand"), clip.poses, clip.frames);
  ASSERT_TRUE(arm.ok()) << arm.status();
  EXPECT_EQ(NameOf(clip.skeleton, arm->end), "LeftHand");
  EXPECT_EQ(NameOf(clip.skeleton, arm->middle), "LeftForeArm");
  EXPECT_EQ(NameOf(clip.skeleton, arm->start), "LeftArm");  // past the clavicle
  absl::StatusOr<LimbJoints> leg = FindLimbJoints(clip.skeleton, clip.metric, clip.bone,
                                                  limb("RightUpLeg", "RightToeBase"), clip.poses, clip.frames);
  ASSERT_TRUE(leg.ok()) << leg.status();
  EXPECT_EQ(NameOf(clip.skeleton, leg->end), "RightFoot");
  EXPECT_EQ(NameOf(clip.skeleton, leg->middle), "RightLeg");
  EXPECT_EQ(NameOf(clip.skeleton, leg->start), "RightUpLeg");
}

// The synthetic clip with its left thigh split in two (a joint that never bends).
BvhClip WithSplitThigh(int frame_count) {
  BvhClip clip = testing::MakeWalkingClip({}, frame_count);
  EXPECT_TRUE(testing::SplitBone(clip, clip.skeleton.Find("LeftLeg"), "LeftThighMid").ok());
  return clip;
}

TEST(BodyStepFindLimbJointsTest, ASplitBoneDoesNotEndASegmentGivenEnoughFrames) {
  const WalkingClip clip(WithSplitThigh(40));
  const Limb leg{.branch = clip["Hips"], .top = clip["LeftUpLeg"], .end = clip["LeftToeBase"]};
  absl::StatusOr<LimbJoints> joints =
      FindLimbJoints(clip.skeleton, clip.metric, clip.bone, leg, clip.poses, clip.frames);
  ASSERT_TRUE(joints.ok()) << joints.status();
  EXPECT_EQ(NameOf(clip.skeleton, joints->end), "LeftFoot");
  EXPECT_EQ(NameOf(clip.skeleton, joints->middle), "LeftLeg");
  EXPECT_EQ(NameOf(clip.skeleton, joints->start), "LeftUpLeg");  // not the split joint
}

TEST(BodyStepFindLimbJointsTest, WithFewerThanTenFramesEveryJointEndsASegment) {
  // Segments 21.5 (half thigh), 21.5, 42 (shin), 13.8 (foot): the longest two are the shin and the
  // first half thigh.
  const WalkingClip clip(WithSplitThigh(9));
  ASSERT_LT(clip.frames.size(), 10u);
  const Limb leg{.branch = clip["Hips"], .top = clip["LeftUpLeg"], .end = clip["LeftToeBase"]};
  absl::StatusOr<LimbJoints> joints =
      FindLimbJoints(clip.skeleton, clip.metric, clip.bone, leg, clip.poses, clip.frames);
  ASSERT_TRUE(joints.ok()) << joints.status();
  EXPECT_EQ(NameOf(clip.skeleton, joints->end), "LeftFoot");
  EXPECT_EQ(NameOf(clip.skeleton, joints->middle), "LeftThighMid");
  EXPECT_EQ(NameOf(clip.skeleton, joints->start), "LeftUpLeg");
}

// The synthetic clip with the left elbow held straight in every frame (a short clip of an arm
// hanging straight: seen in bandai-namco-1's dataset-1_walk-back_normal_001).
BvhClip WithStraightLeftElbow() {
  BvhClip clip = testing::MakeWalkingClip({}, 40);
  const int elbow = clip.skeleton.Find("LeftForeArm");
  const std::vector<ChannelType>& channels = clip.skeleton.joint(elbow).channels;
  for (size_t k = 0; k < channels.size(); ++k) {
    if (IsRotation(channels[k])) clip.channels.col(clip.skeleton.channel_start(elbow) + static_cast<int>(k)).setZero();
  }
  return clip;
}

TEST(BodyStepFindLimbJointsTest, AnElbowHeldStraightStillBendsOnTheOtherArm) {
  const WalkingClip clip(WithStraightLeftElbow());
  const Limb left{.branch = clip["Chest"], .top = clip["LeftShoulder"], .end = clip["LeftHand"]};
  const Limb right{.branch = clip["Chest"], .top = clip["RightShoulder"], .end = clip["RightHand"]};
  // Alone, the straight elbow looks like a split bone: the clavicle becomes the upper segment.
  absl::StatusOr<LimbJoints> alone =
      FindLimbJoints(clip.skeleton, clip.metric, clip.bone, left, clip.poses, clip.frames);
  ASSERT_TRUE(alone.ok()) << alone.status();
  EXPECT_EQ(NameOf(clip.skeleton, alone->middle), "LeftArm");
  // Beside its mirror, it is the elbow.
  absl::StatusOr<LimbJoints> paired =
      FindLimbJoints(clip.skeleton, clip.metric, clip.bone, left, clip.poses, clip.frames, &right);
  ASSERT_TRUE(paired.ok()) << paired.status();
  EXPECT_EQ(NameOf(clip.skeleton, paired->end), "LeftHand");
  EXPECT_EQ(NameOf(clip.skeleton, paired->middle), "LeftForeArm");
  EXPECT_EQ(NameOf(clip.skeleton, paired->start), "LeftArm");
}

TEST(BodyStepFindLimbJointsTest, AClavicleLongerThanTheForearmIsSkippedWhenItStartsInsideTheShoulders) {
  testing::SyntheticRigOptions options;
  options.clavicle_length = 27.0;  // forearm 25, upper arm 28 (the CMU rig's proportions)
  const WalkingClip clip(options);
  const Limb left{.branch = clip["Chest"], .top = clip["LeftShoulder"], .end = clip["LeftHand"]};
  const Limb right{.branch = clip["Chest"], .top = clip["RightShoulder"], .end = clip["RightHand"]};
  // By length alone: clavicle and upper arm.
  absl::StatusOr<LimbJoints> joints =
      FindLimbJoints(clip.skeleton, clip.metric, clip.bone, left, clip.poses, clip.frames, &right);
  ASSERT_TRUE(joints.ok()) << joints.status();
  EXPECT_EQ(NameOf(clip.skeleton, joints->end), "LeftForeArm");
  // The clavicles start 6 apart, the shoulders 60: wider than the hips (18) only the shoulders.
  const float hips = MeanDistance(clip.poses, clip.frames, clip["LeftUpLeg"], clip["RightUpLeg"]);
  EXPECT_NEAR(hips, 18.0f, 0.5f);
  joints = FindLimbJoints(clip.skeleton, clip.metric, clip.bone, left, clip.poses, clip.frames, &right, hips);
  ASSERT_TRUE(joints.ok()) << joints.status();
  EXPECT_EQ(NameOf(clip.skeleton, joints->end), "LeftHand");
  EXPECT_EQ(NameOf(clip.skeleton, joints->middle), "LeftForeArm");
  EXPECT_EQ(NameOf(clip.skeleton, joints->start), "LeftArm");
  // Shoulders no wider than the hips (a separation no joint reaches): the clavicle is still
  // skipped, never the upper arm, the arm's longest bone.
  joints = FindLimbJoints(clip.skeleton, clip.metric, clip.bone, left, clip.poses, clip.frames, &right, 1000.0f);
  ASSERT_TRUE(joints.ok()) << joints.status();
  EXPECT_EQ(NameOf(clip.skeleton, joints->end), "LeftHand");
  EXPECT_EQ(NameOf(clip.skeleton, joints->start), "LeftArm");
  // Without the mirror, no separation to measure: length alone.
  joints = FindLimbJoints(clip.skeleton, clip.metric, clip.bone, left, clip.poses, clip.frames, nullptr, hips);
  ASSERT_TRUE(joints.ok()) << joints.status();
  EXPECT_EQ(NameOf(clip.skeleton, joints->end), "LeftForeArm");
}

TEST(BodyStepFindLimbJointsTest, ALimbNeedsTwoBonesThatBend) {
  const WalkingClip clip;
  const Limb one_bone{.branch = clip["Neck"], .top = clip["Head"], .end = clip["Head"]};
  absl::StatusOr<LimbJoints> joints =
      FindLimbJoints(clip.skeleton, clip.metric, clip.bone, one_bone, clip.poses, clip.frames);
  ASSERT_FALSE(joints.ok());
  EXPECT_EQ(joints.status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(joints.status().message().find("'Head' has fewer than two bones"), std::string_view::npos)
      << joints.status();

  // The arm held straight out (the rest T-pose) in every frame of a long clip: one segment.
  const Limb straight{.branch = clip["Chest"], .top = clip["LeftShoulder"], .end = clip["LeftHand"]};
  const GlobalPoses rest = ForwardKinematics(clip.skeleton, RestMotion(clip.skeleton));
  joints = FindLimbJoints(clip.skeleton, clip.metric, clip.bone, straight, rest, std::vector<int>(12, 0));
  ASSERT_FALSE(joints.ok());
  EXPECT_NE(joints.status().message().find("does not bend"), std::string_view::npos) << joints.status();
}

// ---------------------------------------------------------------------------------------------
// Step 7: facing, left and right.

// Hand-built legs: 0 Hips; 1 LeftUpLeg, 2 LeftLeg (knee), 3 LeftFoot (ankle), 4 LeftToe; 5..8 the
// same on the right.
Skeleton TwoLegs() {
  std::vector<Joint> joints = {Joint{.name = "Hips", .parent = -1, .offset = {0, 90, 0}}};
  for (const std::string side : {"Left", "Right"}) {
    const float x = side == "Left" ? 10.0f : -10.0f;
    const int top = static_cast<int>(joints.size());
    joints.push_back(Joint{.name = side + "UpLeg", .parent = 0, .offset = {x, 0, 0}});
    joints.push_back(Joint{.name = side + "Leg", .parent = top, .offset = {0, -43, 0}});
    joints.push_back(Joint{.name = side + "Foot", .parent = top + 1, .offset = {0, -42, 0}});
    joints.push_back(Joint{.name = side + "Toe", .parent = top + 2, .offset = {0, -4.5f, 13}});
  }
  return Skeleton(std::move(joints));
}

const std::array<Limb, 2> kLegs = {Limb{.branch = 0, .top = 1, .end = 4}, Limb{.branch = 0, .top = 5, .end = 8}};
const std::array<LimbJoints, 2> kLegJoints = {LimbJoints{.end = 3, .middle = 2, .start = 1},
                                              LimbJoints{.end = 7, .middle = 6, .start = 5}};

// Positions of TwoLegs' joints: hips at `pelvis`, knees `knee_forward` ahead (+Z) of the
// hip-ankle line, toes at `toe` from the ankle; the whole body turned by `yaw` degrees about +Y
// (the left hip, at +X unturned, stays on the body's left).
std::vector<Eigen::Vector3f> LegPose(const Eigen::Vector3f& pelvis, float knee_forward, const Eigen::Vector3f& toe,
                                     float yaw = 0.0f) {
  const Eigen::Matrix3f turn =
      Eigen::AngleAxisf(yaw * static_cast<float>(M_PI) / 180, Eigen::Vector3f::UnitY()).toRotationMatrix();
  std::vector<Eigen::Vector3f> pose = {pelvis};
  for (float x : {10.0f, -10.0f}) {
    const Eigen::Vector3f hip(x, 0, 0);
    const Eigen::Vector3f ankle = hip + Eigen::Vector3f(0, -85, 0);
    for (const Eigen::Vector3f& p :
         {hip, Eigen::Vector3f(hip + Eigen::Vector3f(0, -43, knee_forward)), ankle, Eigen::Vector3f(ankle + toe)}) {
      pose.push_back(pelvis + turn * p);
    }
  }
  return pose;
}

Eigen::Vector3f Sum(const std::vector<Eigen::Vector3f>& vectors) {
  Eigen::Vector3f sum = Eigen::Vector3f::Zero();
  for (const Eigen::Vector3f& v : vectors) sum += v;
  return sum;
}

TEST(BodyStepFacingTest, KneeCueIsTheKneesHorizontalOffsetFromTheHipAnkleLinePerFrame) {
  const GlobalPoses poses = PosesOf({LegPose({0, 90, 0}, 5, {0, -4.5f, 13}), LegPose({0, 90, 0}, 2, {0, -4.5f, 13})});
  std::vector<Eigen::Vector3f> per_frame = {Eigen::Vector3f(1, 0, 0), Eigen::Vector3f::Zero()};
  AddKneeBendCue(kLegs, kLegJoints, poses, {0, 1}, Eigen::Vector3f::UnitY(), &per_frame);
  EXPECT_TRUE(per_frame[0].isApprox(Eigen::Vector3f(1, 0, 2 * 5.0f), 1e-5f)) << per_frame[0].transpose();  // added to
  EXPECT_TRUE(per_frame[1].isApprox(Eigen::Vector3f(0, 0, 2 * 2.0f), 1e-5f)) << per_frame[1].transpose();
  // Only the part across `up` counts: with Z up, the knees' offset along Z adds nothing.
  std::vector<Eigen::Vector3f> across_z(2, Eigen::Vector3f::Zero());
  AddKneeBendCue(kLegs, kLegJoints, poses, {0, 1}, Eigen::Vector3f::UnitZ(), &across_z);
  EXPECT_NEAR(Sum(across_z).norm(), 0.0f, 1e-4f) << Sum(across_z).transpose();
}

TEST(BodyStepFacingTest, ToeCueCountsOnlyFramesWithTheToeNearItsLowest) {
  const Skeleton skeleton = TwoLegs();
  const Eigen::VectorXf bone = OffsetLengths(skeleton);
  const TreeMetric metric(skeleton, bone);
  // Frame 0: toes forward on the ground; frame 1: the feet kicked back, toes 20 up and behind.
  const GlobalPoses poses = PosesOf({LegPose({0, 90, 0}, 0, {0, -4.5f, 13}), LegPose({0, 90, 0}, 0, {0, 20, -10})});
  std::vector<Eigen::Vector3f> per_frame(2, Eigen::Vector3f::Zero());
  const float foot_length =
      AddToeCue(kLegs, kLegJoints, metric, poses, {0, 1}, Eigen::Vector3f::UnitY(), 100.0f, &per_frame);
  EXPECT_TRUE(per_frame[0].isApprox(Eigen::Vector3f(0, 0, 26), 1e-5f)) << per_frame[0].transpose();
  EXPECT_EQ(per_frame[1], Eigen::Vector3f::Zero());
  EXPECT_NEAR(foot_length, Eigen::Vector2f(20, -10).norm(), 1e-4f);

  // Legs whose ankle is their end have no toe: no cue, no foot.
  const std::array<LimbJoints, 2> ankles_at_ends = {LimbJoints{.end = 4, .middle = 2},
                                                    LimbJoints{.end = 8, .middle = 6}};
  per_frame.assign(2, Eigen::Vector3f::Zero());
  EXPECT_EQ(AddToeCue(kLegs, ankles_at_ends, metric, poses, {0, 1}, Eigen::Vector3f::UnitY(), 100.0f, &per_frame),
            0.0f);
  EXPECT_EQ(Sum(per_frame), Eigen::Vector3f::Zero());
}

TEST(BodyStepFacingTest, PairLinesRunFromTheSecondStartToTheFirstElseBetweenTheMiddles) {
  const GlobalPoses poses =
      PosesOf({LegPose({0, 90, 0}, 3, {0, -4.5f, 13}), LegPose({0, 90, 0}, 3, {0, -4.5f, 13}, 90)});
  const std::vector<Eigen::Vector3f> lines = PairLines(kLegJoints, poses, {0, 1}, Eigen::Vector3f::UnitY());
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_TRUE(lines[0].isApprox(Eigen::Vector3f(20, 0, 0), 1e-4f)) << lines[0].transpose();
  // Turned 90 degrees about +Y, the left hip (+X) lies at -Z.
  EXPECT_TRUE(lines[1].isApprox(Eigen::Vector3f(0, 0, -20), 1e-4f)) << lines[1].transpose();
  // Both starts on one joint (a rig whose limbs start at the pelvis): the middles.
  const std::array<LimbJoints, 2> shared_start = {LimbJoints{.end = 3, .middle = 2, .start = 0},
                                                  LimbJoints{.end = 7, .middle = 6, .start = 0}};
  const std::vector<Eigen::Vector3f> middles = PairLines(shared_start, poses, {0, 1}, Eigen::Vector3f::UnitY());
  ASSERT_EQ(middles.size(), 2u);
  EXPECT_TRUE(middles[0].isApprox(lines[0], 1e-4f)) << middles[0].transpose();
  EXPECT_TRUE(middles[1].isApprox(lines[1], 1e-4f)) << middles[1].transpose();
}

// Sides of TwoLegs (first leg = the joints built at +X, the body's left) with no arms: the legs
// stand in for them.
absl::StatusOr<Sides> LegSides(const std::array<Limb, 2>& legs, const std::array<LimbJoints, 2>& joints,
                               const GlobalPoses& poses, const std::vector<int>& frames) {
  const Skeleton skeleton = TwoLegs();
  const Eigen::VectorXf bone = OffsetLengths(skeleton);
  const TreeMetric metric(skeleton, bone);
  return FindSides(ArmsAndLegs{.arms = legs, .legs = legs}, joints, joints, 0, metric, poses, frames,
                   Eigen::Vector3f::UnitY(), 100.0f);
}

TEST(BodyStepSidesTest, KneesAndToesSideTheLegsInEveryFrameOfATurningClip) {
  // The body turns a full circle over the frames (its mean facing is nothing), walking backwards
  // relative to its facing: the knees and toes still say where its front is in every frame.
  std::vector<std::vector<Eigen::Vector3f>> frames;
  std::vector<int> indices;
  for (int k = 0; k < 12; ++k) {
    const float yaw = 30.0f * k;
    const float radians = yaw * static_cast<float>(M_PI) / 180;
    const Eigen::Vector3f facing(std::sin(radians), 0, std::cos(radians));
    frames.push_back(LegPose(Eigen::Vector3f(0, 90, 0) - 5.0f * k * facing, 4, {0, -4.5f, 13}, yaw));
    indices.push_back(k);
  }
  const GlobalPoses poses = PosesOf(frames);
  absl::StatusOr<Sides> sides = LegSides(kLegs, kLegJoints, poses, indices);
  ASSERT_TRUE(sides.ok()) << sides.status();
  EXPECT_TRUE(sides->first_leg_is_left);
  EXPECT_TRUE(sides->first_arm_is_left);
  // The mean facing of a full turn is nothing: the first frame's.
  EXPECT_TRUE(sides->forward.isApprox(Eigen::Vector3f::UnitZ(), 1e-4f)) << sides->forward.transpose();
  // The same limbs listed the other way round.
  sides = LegSides({kLegs[1], kLegs[0]}, {kLegJoints[1], kLegJoints[0]}, poses, indices);
  ASSERT_TRUE(sides.ok()) << sides.status();
  EXPECT_FALSE(sides->first_leg_is_left);
  EXPECT_FALSE(sides->first_arm_is_left);
}

TEST(BodyStepSidesTest, WithoutKneeBendOrToesEachStepOfTheTravelCountsAgainstItsOwnFacing) {
  // Legs ending at the ankle, straight; the body walks a quarter turn: +Z, then +X.
  const std::array<Limb, 2> legs = {Limb{.branch = 0, .top = 1, .end = 3}, Limb{.branch = 0, .top = 5, .end = 7}};
  const GlobalPoses travelling =
      PosesOf({LegPose({0, 90, 0}, 0, {0, -4.5f, 13}), LegPose({0, 90, 30}, 0, {0, -4.5f, 13}, 45),
               LegPose({30, 95, 30}, 0, {0, -4.5f, 13}, 90)});
  absl::StatusOr<Sides> sides = LegSides(legs, kLegJoints, travelling, {0, 1, 2});
  ASSERT_TRUE(sides.ok()) << sides.status();
  EXPECT_TRUE(sides->first_leg_is_left);
  EXPECT_TRUE(sides->forward.isApprox(Eigen::Vector3f(1, 0, 1).normalized(), 1e-4f)) << sides->forward.transpose();

  // Travelling 4 (under 5% of the body size of 100): cannot tell.
  const GlobalPoses standing =
      PosesOf({LegPose({0, 90, 0}, 0, {0, -4.5f, 13}), LegPose({0, 90, 4}, 0, {0, -4.5f, 13})});
  sides = LegSides(legs, kLegJoints, standing, {0, 1});
  ASSERT_FALSE(sides.ok());
  EXPECT_EQ(sides.status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(sides.status().message().find("left from right"), std::string_view::npos) << sides.status();
}

TEST(BodyStepFacingTest, HorizontalDropsTheUpComponent) {
  EXPECT_EQ(Horizontal(Eigen::Vector3f(1, 2, 3), Eigen::Vector3f::UnitY()), Eigen::Vector3f(1, 0, 3));
  EXPECT_EQ(Horizontal(Eigen::Vector3f(1, 2, 3), -Eigen::Vector3f::UnitZ()), Eigen::Vector3f(1, 2, 0));
}

TEST(BodyStepSidesTest, SyntheticRigFacesPlusZWithItsLeftAtPlusX) {
  const WalkingClip clip;
  auto limb = [&](const std::string& top, const std::string& end) {
    return Limb{.branch = clip.skeleton.parent(clip[top]), .top = clip[top], .end = clip[end]};
  };
  auto joints = [&](const std::string& start, const std::string& middle, const std::string& end) {
    return LimbJoints{.end = clip[end], .middle = clip[middle], .start = clip[start]};
  };
  const ArmsAndLegs limbs{.arms = {limb("RightShoulder", "RightHand"), limb("LeftShoulder", "LeftHand")},
                          .legs = {limb("LeftUpLeg", "LeftToeBase"), limb("RightUpLeg", "RightToeBase")}};
  absl::StatusOr<Sides> sides =
      FindSides(limbs, {joints("RightArm", "RightForeArm", "RightHand"), joints("LeftArm", "LeftForeArm", "LeftHand")},
                {joints("LeftUpLeg", "LeftLeg", "LeftFoot"), joints("RightUpLeg", "RightLeg", "RightFoot")},
                clip["Hips"], clip.metric, clip.poses, clip.frames, Eigen::Vector3f::UnitY(), clip.body_size);
  ASSERT_TRUE(sides.ok()) << sides.status();
  EXPECT_TRUE(sides->first_leg_is_left);
  EXPECT_FALSE(sides->first_arm_is_left);
  EXPECT_GT(sides->forward.z(), 0.95f) << sides->forward.transpose();
}

// ---------------------------------------------------------------------------------------------
// Step 8: head landmark, groups, sizes.

TEST(BodyStepHeadLandmarkTest, FirstBranchingJointOfTheHeadChainElseItsEnd) {
  // Neck -> Head -> {Jaw, Crown}, Crown -> CrownEnd -> two zero-length eyes (merged into CrownEnd).
  const Skeleton skeleton(
      {Joint{.name = "Chest", .parent = -1}, Joint{.name = "Neck", .parent = 0, .offset = {0, 20, 0}},
       Joint{.name = "Head", .parent = 1, .offset = {0, 8, 0}}, Joint{.name = "Jaw", .parent = 2, .offset = {0, -2, 8}},
       Joint{.name = "Crown", .parent = 2, .offset = {0, 15, 0}},
       Joint{.name = "CrownEnd", .parent = 4, .offset = {0, 5, 0}}, Joint{.name = "LeftEye", .parent = 5},
       Joint{.name = "RightEye", .parent = 5}});
  const Eigen::VectorXf bone = OffsetLengths(skeleton);
  const TreeMetric metric(skeleton, bone);
  const MergedTree tree = MergeShortBones(skeleton, bone, 30.0f);
  EXPECT_EQ(HeadLandmark(Limb{.branch = 0, .top = 1, .end = 5}, metric, tree), 2);
  // Below the face hub: CrownEnd's children are merged, it does not branch: the end.
  EXPECT_EQ(HeadLandmark(Limb{.branch = 2, .top = 4, .end = 5}, metric, tree), 5);
}

TEST(BodyStepAssignGroupsTest, SubtreeOfEachLimbsTopTheRestIsSpine) {
  const WalkingClip clip;
  auto limb = [&](const std::string& top, const std::string& end) {
    return Limb{.branch = clip.skeleton.parent(clip[top]), .top = clip[top], .end = clip[end]};
  };
  BodyTopology topology;
  AssignGroups(clip.skeleton,
               SidedLimbs{.head = limb("Neck", "Head"),
                          .left_arm = limb("LeftShoulder", "LeftHand"),
                          .right_arm = limb("RightShoulder", "RightHand"),
                          .left_leg = limb("LeftUpLeg", "LeftToeBase"),
                          .right_leg = limb("RightUpLeg", "RightToeBase")},
               clip["Hips"], &topology);
  ASSERT_EQ(static_cast<int>(topology.group_of_joint.size()), clip.skeleton.num_joints());
  auto group = [&](const std::string& name) { return std::string(BodyGroupName(topology.group_of_joint[clip[name]])); };
  EXPECT_EQ(group("Hips"), "spine");
  EXPECT_EQ(group("Chest"), "spine");
  EXPECT_EQ(group("Neck"), "head");
  EXPECT_EQ(group("Head"), "head");
  EXPECT_EQ(group("LeftShoulder"), "left_arm");
  EXPECT_EQ(group("LeftForeArm"), "left_arm");
  EXPECT_EQ(group("RightHand"), "right_arm");
  EXPECT_EQ(group("LeftFoot"), "left_leg");
  EXPECT_EQ(group("RightUpLeg"), "right_leg");
  EXPECT_EQ(group("RightToeBase"), "right_leg");
  EXPECT_EQ(topology.group_size(BodyGroup::kSpine), 3);
  EXPECT_EQ(topology.group_top[static_cast<int>(BodyGroup::kSpine)], 0);
  EXPECT_EQ(NameOf(clip.skeleton, topology.group_end[static_cast<int>(BodyGroup::kSpine)]), "Hips");
  EXPECT_EQ(NameOf(clip.skeleton, topology.group_top[static_cast<int>(BodyGroup::kRightArm)]), "RightShoulder");
  EXPECT_EQ(NameOf(clip.skeleton, topology.group_end[static_cast<int>(BodyGroup::kRightArm)]), "RightHand");
  EXPECT_EQ(NameOf(clip.skeleton, topology.group_end[static_cast<int>(BodyGroup::kLeftLeg)]), "LeftToeBase");
}

TEST(BodyStepLegLengthTest, MeanOfTheBonesBelowTheHipJointDownToTheAnkle) {
  const Skeleton skeleton = TwoLegs();
  Eigen::VectorXf bone = OffsetLengths(skeleton);
  bone[skeleton.Find("RightLeg")] = 45.0f;  // thigh 45 on the right, 43 on the left
  const TreeMetric metric(skeleton, bone);
  // The hip offset (UpLeg's bone) and the toe do not count.
  EXPECT_FLOAT_EQ(LegLength(kLegs, kLegJoints, metric, bone), (43.0f + 42.0f + 45.0f + 42.0f) / 2);
}

TEST(BodyStepMeasureHeightsTest, PelvisAboveTheLowestLegJointAndTheFloorOverAllFrames) {
  // Joints: 0 a static root far below, 1 pelvis, 2 and 3 leg joints (groups given below).
  const std::vector<BodyGroup> groups = {BodyGroup::kSpine, BodyGroup::kSpine, BodyGroup::kLeftLeg,
                                         BodyGroup::kRightLeg};
  auto frame = [](float pelvis, float left, float right) {
    return std::vector<Eigen::Vector3f>{{0, -50, 0}, {0, pelvis, 0}, {0, left, 0}, {0, right, 0}};
  };
  const GlobalPoses poses = PosesOf({frame(95, 5, 10), frame(90, 2, 20), frame(100, 30, 4)});
  const Heights heights = MeasureHeights(groups, 1, poses, Eigen::Vector3f::UnitY());
  EXPECT_FLOAT_EQ(heights.floor, 2.0f);
  EXPECT_FLOAT_EQ(heights.standing_pelvis, 90.0f);  // median of 90, 88, 96
  // Along -Y the heights are negated.
  const Heights down = MeasureHeights(groups, 1, poses, -Eigen::Vector3f::UnitY());
  EXPECT_FLOAT_EQ(down.floor, -30.0f);
}

}  // namespace
}  // namespace mocap::body_topology
