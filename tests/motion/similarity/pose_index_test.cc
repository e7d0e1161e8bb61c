// PoseIndex on synthetic walks: the invariance tests of issue #5 (the same clip on another rig,
// moved, scaled, renamed, with joints added or removed retrieves its own frames first), the
// window option, and the argument checks.
#include "motion/similarity/pose_index.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <ostream>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/local_motion.h"
#include "tests/support/clip_points.h"
#include "tests/support/rig_variants.h"
#include "tests/support/rotation_checks.h"
#include "tests/support/synthetic_clip.h"

namespace mocap {
namespace {

using testing::kDegree;
using testing::PointsOf;
using testing::QueryPoints;

using testing::MakeWalkingClip;
using testing::SyntheticRigOptions;

constexpr int kFrames = 90;  // three gait cycles at 30 fps

// ---------------------------------------------------------------------------------------------
// Clip edits. All work on any of the synthetic rigs (they only use joint names the generator
// gives every rig, before any renaming).

// The synthetic walk repeats exactly every gait cycle (30 frames), so a frame's pose also occurs
// 30 and 60 frames later. To give every frame one right answer, the left upper arm is raised
// steadily over the clip (about the world's forward axis, `degrees` in all): the same world
// motion on every rig.
void RaiseLeftArmOverTime(BvhClip& clip, float degrees = 45.0f) {
  const int arm = clip.skeleton.Find("LeftArm");
  ASSERT_GE(arm, 0);
  const int parent = clip.skeleton.parent(arm);
  LocalMotion motion = MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time);
  const GlobalPoses poses = ForwardKinematics(clip.skeleton, motion);
  const int n = motion.num_frames();
  for (int f = 0; f < n; ++f) {
    const float angle = degrees * kDegree * static_cast<float>(f) / static_cast<float>(std::max(1, n - 1));
    const Eigen::Quaternionf raise(Eigen::AngleAxisf(angle, Eigen::Vector3f::UnitZ()));  // world Y up, +Z forward
    const Eigen::Quaternionf parent_world = poses.rotation(f, parent);
    motion.SetRotation(f, arm,
                       (parent_world.conjugate() * raise * parent_world * motion.rotation(f, arm)).normalized());
  }
  clip.channels = ChannelsFromMotion(clip.skeleton, motion);
}

using testing::MoveOnGround;
using testing::RenameJoints;

// Splits the bone ending at the joint named `child_name` (tests/support/rig_variants.h).
void SplitBone(BvhClip& clip, const std::string& child_name, const std::string& new_name) {
  const int child = clip.skeleton.Find(child_name);
  ASSERT_GT(child, 0);
  const absl::Status status = testing::SplitBone(clip, child, new_name);
  ASSERT_TRUE(status.ok()) << status;
}

// The root keeps its first frame's ground position: the same poses, walking on the spot.
void FreezeRootTravel(BvhClip& clip) {
  const Joint& root = clip.skeleton.joint(0);
  for (size_t k = 0; k < root.channels.size(); ++k) {
    if (root.channels[k] != ChannelType::kXposition && root.channels[k] != ChannelType::kZposition) continue;
    auto column = clip.channels.col(clip.skeleton.channel_start(0) + static_cast<int>(k));
    column.setConstant(column(0));
  }
}

// The test walk on a rig, with the arm drift that makes every frame unique.
BvhClip Walk(const SyntheticRigOptions& rig = {}) {
  BvhClip clip = MakeWalkingClip(rig, kFrames, 1.0 / 30.0);
  RaiseLeftArmOverTime(clip);
  return clip;
}

// ---------------------------------------------------------------------------------------------
// The pipeline (tests/support/clip_points.h): rig model, prepared clip, body points, index.

// An index over `clips`; the first clip of each rig defines that rig's model.
absl::StatusOr<PoseIndex> BuildIndex(const std::vector<BvhClip>& clips, const BodyPointOptions& options = {}) {
  PoseIndex index(options);
  std::vector<RigModel> rigs;
  for (const BvhClip& clip : clips) {
    auto same =
        std::find_if(rigs.begin(), rigs.end(), [&](const RigModel& r) { return r.skeleton.SameRigAs(clip.skeleton); });
    if (same == rigs.end()) {
      MOCAP_ASSIGN_OR_RETURN(RigModel rig, BuildRigModel(clip, {}));
      rigs.push_back(std::move(rig));
      same = rigs.end() - 1;
    }
    MOCAP_ASSIGN_OR_RETURN(ClipPoints points, PointsOf(clip, *same, options));
    index.AddClip(std::move(points));
  }
  MOCAP_RETURN_IF_ERROR(index.Build());
  return index;
}

// Fraction of sampled query frames whose best match is clip `clip`, within one frame of the
// query frame.
struct Retrieval {
  int queries = 0;
  int hits = 0;
  std::string misses;  // "query->clip:frame" for the first few misses
  double rate() const { return queries > 0 ? static_cast<double>(hits) / queries : 0.0; }
};

Retrieval RetrieveOwnFrames(const PoseIndex& index, const ClipPoints& query, const PoseSearchOptions& options,
                            int clip = 0, int first = 0, int step = 3) {
  Retrieval r;
  for (int f = first; f < query.points.rows() - first; f += step) {
    absl::StatusOr<std::vector<PoseMatch>> matches = index.Search(query, f, options);
    EXPECT_TRUE(matches.ok()) << matches.status();
    if (!matches.ok() || matches->empty()) continue;
    ++r.queries;
    const PoseMatch& best = matches->front();
    if (best.clip == clip && std::abs(best.frame - f) <= 1) {
      ++r.hits;
    } else if (r.misses.size() < 200) {
      r.misses += StrCat(" ", f, "->", best.clip, ":", best.frame, " (", best.distance.total, ")");
    }
  }
  return r;
}

// ---------------------------------------------------------------------------------------------
// Invariance: the database is the walk on one rig, the query the same walk changed.

struct InvarianceCase {
  std::string name;
  SyntheticRigOptions database_rig;
  SyntheticRigOptions query_rig;
  std::function<void(BvhClip&)> edit_query;  // after the arm drift
};

void PrintTo(const InvarianceCase& c, std::ostream* out) { *out << c.name; }

std::vector<InvarianceCase> InvarianceCases() {
  auto options = [](auto set) {
    SyntheticRigOptions o;
    set(o);
    return o;
  };
  const SyntheticRigOptions plain;
  std::vector<InvarianceCase> cases = {
      {"Identical", plain, plain, nullptr},
      {"TranslatedAndTurned", plain, plain,
       [](BvhClip& c) {
         MoveOnGround(c, 110.0f, {250.0f, 0.0f, -400.0f});
       }},
      {"TurnedBackwards", plain, plain,
       [](BvhClip& c) {
         MoveOnGround(c, 180.0f, {-30.0f, 0.0f, 70.0f});
       }},
      {"Metres", plain, options([](auto& o) { o.length_scale = 0.01; }), nullptr},
      {"Inches", plain, options([](auto& o) { o.length_scale = 1.0 / 2.54; }), nullptr},
      {"RenamedJoints", plain, plain, RenameJoints},
      {"XyzChannelOrder", plain, options([](auto& o) { o.rotation_order = "XYZ"; }), nullptr},
      {"TwistBones", plain, options([](auto& o) { o.twist_bones = true; }), nullptr},
      {"FingersAndToes", plain, options([](auto& o) { o.fingers_and_toes = true; }), nullptr},
      {"SplitSpine", plain, plain, [](BvhClip& c) { SplitBone(c, "Chest", "SpineMid"); }},
      // A roll joint inside the forearm or shin chain (not a twist leaf beside it).
      {"SplitForearm", plain, plain, [](BvhClip& c) { SplitBone(c, "LeftHand", "LeftForeArmRoll"); }},
      {"SplitShin", plain, plain, [](BvhClip& c) { SplitBone(c, "RightFoot", "RightLegRoll"); }},
      {"ExtraRootAdded", plain, options([](auto& o) { o.extra_root = true; }), nullptr},
      {"RootRemoved", options([](auto& o) { o.extra_root = true; }), plain, nullptr},
      {"ZUpRoot", plain, options([](auto& o) { o.z_up = true; }), nullptr},
      {"ZUpRootRemoved", options([](auto& o) { o.z_up = true; }), plain, nullptr},
      {"PositionChannelsEverywhere", plain, options([](auto& o) { o.position_channels_everywhere = true; }), nullptr},
      {"RichRigAgainstRichRig", options([](auto& o) { o.twist_bones = o.fingers_and_toes = o.extra_root = true; }),
       options([](auto& o) { o.twist_bones = o.fingers_and_toes = o.z_up = true; }), nullptr},
      {"EverythingAtOnce", plain, options([](auto& o) {
         o.z_up = o.extra_root = o.twist_bones = o.fingers_and_toes = true;
         o.rotation_order = "XYZ";
         o.length_scale = 1.0 / 2.54;
       }),
       [](BvhClip& c) {
         SplitBone(c, "Chest", "SpineMid");
         MoveOnGround(c, -75.0f, {40.0f, 0.0f, 90.0f});
         RenameJoints(c);
       }},
  };
  return cases;
}

class PoseIndexInvarianceTest : public ::testing::TestWithParam<InvarianceCase> {};

TEST_P(PoseIndexInvarianceTest, RetrievesItsOwnFramesFirst) {
  const InvarianceCase& c = GetParam();
  absl::StatusOr<PoseIndex> index = BuildIndex({Walk(c.database_rig)});
  ASSERT_TRUE(index.ok()) << index.status();
  ASSERT_EQ(index->num_frames(), kFrames);

  BvhClip query_clip = Walk(c.query_rig);
  if (c.edit_query) c.edit_query(query_clip);
  ASSERT_FALSE(::testing::Test::HasFatalFailure());
  absl::StatusOr<ClipPoints> query = QueryPoints(query_clip);
  ASSERT_TRUE(query.ok()) << query.status();
  ASSERT_EQ(query->points.rows(), kFrames);

  for (bool exact : {true, false}) {
    SCOPED_TRACE(exact ? "exact" : "fast path");
    PoseSearchOptions options;
    options.exact = exact;
    options.top_k = 5;
    options.candidates = 10;  // of 90 frames: the prefilter has to find the right ones
    const Retrieval r = RetrieveOwnFrames(*index, *query, options);
    EXPECT_EQ(r.queries, 30);
    EXPECT_GE(r.rate(), 0.9) << r.hits << " of " << r.queries << "; misses:" << r.misses;
  }
}

INSTANTIATE_TEST_SUITE_P(Rigs, PoseIndexInvarianceTest, ::testing::ValuesIn(InvarianceCases()),
                         [](const auto& info) { return info.param.name; });

// Without the arm drift, frames one gait cycle apart are the same pose: check the drift is what
// the tests above rely on, i.e. that they could fail.
TEST(PoseIndexTest, PeriodicWalkHasEqualPosesOneCycleApart) {
  absl::StatusOr<PoseIndex> index = BuildIndex({MakeWalkingClip({}, kFrames, 1.0 / 30.0)});
  ASSERT_TRUE(index.ok()) << index.status();
  PoseSearchOptions options;
  options.exact = true;
  options.top_k = 3;
  options.suppress_within_frames = 2;
  absl::StatusOr<std::vector<PoseMatch>> matches = index->Search(index->clip(0), 40, options);
  ASSERT_TRUE(matches.ok()) << matches.status();
  ASSERT_EQ(matches->size(), 3u);
  std::vector<int> frames;
  for (const PoseMatch& m : *matches) {
    EXPECT_LT(m.distance.total, 1e-3f);
    frames.push_back(m.frame);
  }
  std::sort(frames.begin(), frames.end());
  EXPECT_EQ(frames, (std::vector<int>{10, 40, 70}));
}

// The drift makes frames a cycle apart clearly different.
TEST(PoseIndexTest, DriftSeparatesFramesOneCycleApart) {
  absl::StatusOr<PoseIndex> index = BuildIndex({Walk()});
  ASSERT_TRUE(index.ok()) << index.status();
  PoseSearchOptions options;
  options.exact = true;
  options.top_k = kFrames;
  absl::StatusOr<std::vector<PoseMatch>> matches = index->Search(index->clip(0), 40, options);
  ASSERT_TRUE(matches.ok()) << matches.status();
  ASSERT_EQ(matches->size(), static_cast<size_t>(kFrames));
  EXPECT_EQ(matches->front().frame, 40);
  EXPECT_LT(matches->front().distance.total, 1e-4f);
  for (const PoseMatch& m : *matches) {
    if (m.frame == 10 || m.frame == 70) {
      EXPECT_GT(m.distance.total, 0.1f) << m.frame;
    }
  }
}

// The seed's rule (keep a chain's joints, drop those nearest the end effector) compares other body
// points once a bone is split; resampling the chain at equal fractions of its length does not.
TEST(PoseIndexTest, ResamplingKeepsTheBodyPointsOfASplitSpine) {
  BvhClip split = Walk();
  SplitBone(split, "Chest", "SpineMid");
  ASSERT_FALSE(HasFatalFailure());
  float own_frame_distance[2] = {0, 0};
  for (PointSampling sampling : {PointSampling::kResampleChains, PointSampling::kDropNearestEndEffector}) {
    BodyPointOptions point_options;
    point_options.sampling = sampling;
    absl::StatusOr<PoseIndex> index = BuildIndex({Walk()}, point_options);
    ASSERT_TRUE(index.ok()) << index.status();
    absl::StatusOr<ClipPoints> query = QueryPoints(split, point_options);
    ASSERT_TRUE(query.ok()) << query.status();
    PoseSearchOptions options;
    options.exact = true;
    options.top_k = kFrames;
    absl::StatusOr<std::vector<PoseMatch>> matches = index->Search(*query, 45, options);
    ASSERT_TRUE(matches.ok()) << matches.status();
    for (const PoseMatch& m : *matches) {
      if (m.frame == 45) own_frame_distance[sampling == PointSampling::kResampleChains ? 0 : 1] = m.distance.total;
    }
  }
  EXPECT_LT(own_frame_distance[0], 1e-3f);
  // Spine: Hips, Spine, Chest, Chest, Chest against Hips, Spine, SpineMid, Chest, Chest; SpineMid
  // is 7.5 cm from the chest, 0.09 leg lengths.
  EXPECT_GT(own_frame_distance[1], 0.05f);
}

// ---------------------------------------------------------------------------------------------
// What a match reports.

TEST(PoseIndexTest, MatchesAreSortedAndCarryTheAlignment) {
  absl::StatusOr<PoseIndex> index = BuildIndex({Walk()});
  ASSERT_TRUE(index.ok()) << index.status();
  BvhClip moved = Walk();
  MoveOnGround(moved, 110.0f, {250.0f, 0.0f, -400.0f});
  absl::StatusOr<ClipPoints> query = QueryPoints(moved);
  ASSERT_TRUE(query.ok()) << query.status();

  for (bool exact : {true, false}) {
    SCOPED_TRACE(exact ? "exact" : "fast path");
    PoseSearchOptions options;
    options.exact = exact;
    options.top_k = 7;
    options.weights = GroupWeights::Locomotion();
    absl::StatusOr<std::vector<PoseMatch>> matches = index->Search(*query, 45, options);
    ASSERT_TRUE(matches.ok()) << matches.status();
    ASSERT_EQ(matches->size(), 7u);
    EXPECT_EQ(matches->front().clip, 0);
    EXPECT_EQ(matches->front().frame, 45);
    EXPECT_LT(matches->front().distance.total, 1e-3f);
    // The query is the database turned by 110 degrees: the alignment maps the match onto it.
    // Clouds are relative to the pelvis, so there is no translation left.
    const GroundAlignment& a = matches->front().distance.alignment;
    EXPECT_NEAR(std::remainder(a.yaw - 110.0f * kDegree, 2.0f * static_cast<float>(M_PI)), 0.0f, 1e-3f);
    EXPECT_NEAR(a.x, 0.0f, 1e-3f);
    EXPECT_NEAR(a.z, 0.0f, 1e-3f);
    for (size_t i = 0; i < matches->size(); ++i) {
      const PoseMatch& m = (*matches)[i];
      EXPECT_EQ(m.clip, 0);
      EXPECT_GE(m.frame, 0);
      EXPECT_LT(m.frame, kFrames);
      float sum = 0.0f;
      for (int g = 0; g < kNumBodyGroups; ++g) sum += options.weights.weight[g] * m.distance.per_group[g];
      EXPECT_NEAR(m.distance.total, sum, 1e-4f + 1e-4f * sum);
      if (i > 0) {
        EXPECT_LE((*matches)[i - 1].distance.total, m.distance.total);
      }
    }
  }
}

TEST(PoseIndexTest, SuppressionSpreadsTheMatches) {
  absl::StatusOr<PoseIndex> index = BuildIndex({MakeWalkingClip({}, kFrames, 1.0 / 30.0)});
  ASSERT_TRUE(index.ok()) << index.status();
  for (int suppress : {0, 3, 8}) {
    PoseSearchOptions options;
    options.exact = true;
    options.top_k = 6;
    options.suppress_within_frames = suppress;
    absl::StatusOr<std::vector<PoseMatch>> matches = index->Search(index->clip(0), 45, options);
    ASSERT_TRUE(matches.ok()) << matches.status();
    ASSERT_FALSE(matches->empty());
    EXPECT_EQ(matches->front().frame % 30, 15);  // a copy of the query pose comes first
    for (size_t i = 0; i < matches->size(); ++i) {
      for (size_t j = 0; j < i; ++j) {
        EXPECT_GT(std::abs((*matches)[i].frame - (*matches)[j].frame), suppress)
            << "suppress " << suppress << ": " << (*matches)[i].frame << " and " << (*matches)[j].frame;
      }
    }
  }
}

TEST(PoseIndexTest, FastPathAgreesWithExactSearchOnSeveralClips) {
  // The same rig (joint names and hierarchy) with other channel orders, rates and motions.
  SyntheticRigOptions xyz;
  xyz.rotation_order = "XYZ";
  BvhClip standing = Walk();
  FreezeRootTravel(standing);
  BvhClip still = MakeWalkingClip({}, 1, 1.0 / 30.0);  // one pose, repeated
  still.channels = still.channels.replicate(40, 1).eval();
  absl::StatusOr<PoseIndex> index = BuildIndex({Walk(), MakeWalkingClip(xyz, 75, 1.0 / 60.0), standing, still});
  ASSERT_TRUE(index.ok()) << index.status();
  EXPECT_EQ(index->num_clips(), 4);
  EXPECT_EQ(index->num_frames(), kFrames + 38 + kFrames + 40);  // 75 frames at 60 fps: 0 .. 37/30 s

  SyntheticRigOptions twist;
  twist.twist_bones = true;
  absl::StatusOr<ClipPoints> query = QueryPoints(MakeWalkingClip(twist, 70, 1.0 / 30.0));
  ASSERT_TRUE(query.ok()) << query.status();
  int agree = 0, total = 0;
  for (int f = 0; f < query->points.rows(); f += 2) {
    PoseSearchOptions options;
    options.top_k = 3;
    options.candidates = 30;
    options.exact = true;
    absl::StatusOr<std::vector<PoseMatch>> exact = index->Search(*query, f, options);
    options.exact = false;
    absl::StatusOr<std::vector<PoseMatch>> fast = index->Search(*query, f, options);
    ASSERT_TRUE(exact.ok() && fast.ok());
    ASSERT_FALSE(exact->empty() || fast->empty());
    ++total;
    // Ties (copies of a periodic pose) make the frame ambiguous; the distance is not.
    if (std::abs(exact->front().distance.total - fast->front().distance.total) <= 1e-5f) ++agree;
  }
  EXPECT_EQ(agree, total);
}

// ---------------------------------------------------------------------------------------------
// A window of frames tells walking from the same poses on the spot.

TEST(PoseIndexTest, WindowTellsWalkingFromWalkingOnTheSpot) {
  BvhClip on_the_spot = Walk();
  FreezeRootTravel(on_the_spot);
  // Clip 0 walks on the spot, clip 1 walks: ties would go to clip 0.
  absl::StatusOr<PoseIndex> index = BuildIndex({on_the_spot, Walk()});
  ASSERT_TRUE(index.ok()) << index.status();
  BvhClip walk = Walk();
  MoveOnGround(walk, 35.0f, {-100.0f, 0.0f, 20.0f});
  absl::StatusOr<ClipPoints> query = QueryPoints(walk);
  ASSERT_TRUE(query.ok()) << query.status();

  // One frame: the poses are the same, so the spot clip is as close as the walk.
  int same_pose = 0, samples = 0;
  for (int f = 6; f < kFrames - 6; f += 4) {
    PoseSearchOptions options;
    options.exact = true;
    options.top_k = 2 * kFrames;
    options.window = 1;
    absl::StatusOr<std::vector<PoseMatch>> matches = index->Search(*query, f, options);
    ASSERT_TRUE(matches.ok()) << matches.status();
    float best[2] = {1e9f, 1e9f};
    for (const PoseMatch& m : *matches) best[m.clip] = std::min(best[m.clip], m.distance.total);
    ++samples;
    if (best[0] < 1e-3f && best[1] < 1e-3f) ++same_pose;
  }
  EXPECT_EQ(same_pose, samples);

  for (bool exact : {true, false}) {
    SCOPED_TRACE(exact ? "exact" : "fast path");
    PoseSearchOptions options;
    options.exact = exact;
    options.window = 5;
    options.candidates = 40;
    const Retrieval r = RetrieveOwnFrames(*index, *query, options, /*clip=*/1, /*first=*/3, /*step=*/3);
    EXPECT_GE(r.rate(), 0.9) << r.hits << " of " << r.queries << "; misses:" << r.misses;

    // And the spot clip's best window is clearly farther than the walk's.
    options.exact = true;
    options.top_k = 2 * kFrames;
    absl::StatusOr<std::vector<PoseMatch>> matches = index->Search(*query, 45, options);
    ASSERT_TRUE(matches.ok()) << matches.status();
    float best[2] = {1e9f, 1e9f};
    for (const PoseMatch& m : *matches) best[m.clip] = std::min(best[m.clip], m.distance.total);
    EXPECT_LT(best[1], 1e-3f);
    EXPECT_GT(best[0], 0.1f);
  }
}

// ---------------------------------------------------------------------------------------------
// Argument checks.

TEST(PoseIndexTest, BuildWithoutFramesFails) {
  PoseIndex index;
  EXPECT_EQ(index.Build().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ(index.num_clips(), 0);
  EXPECT_EQ(index.num_frames(), 0);
}

TEST(PoseIndexTest, SearchChecksItsArguments) {
  absl::StatusOr<ClipPoints> points = QueryPoints(MakeWalkingClip({}, 20, 1.0 / 30.0));
  ASSERT_TRUE(points.ok()) << points.status();
  BodyPointOptions point_options;
  PoseIndex index(point_options);
  index.AddClip(*points);
  EXPECT_EQ(index.num_clips(), 1);
  EXPECT_EQ(index.num_frames(), 20);
  EXPECT_EQ(index.point_options().points_per_group, point_options.points_per_group);

  PoseSearchOptions options;
  EXPECT_EQ(index.Search(*points, 0, options).status().code(), absl::StatusCode::kFailedPrecondition);
  ASSERT_TRUE(index.Build().ok());
  EXPECT_TRUE(index.Search(*points, 0, options).ok());
  EXPECT_TRUE(index.Search(*points, 19, options).ok());
  EXPECT_EQ(index.Search(*points, -1, options).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(index.Search(*points, 20, options).status().code(), absl::StatusCode::kInvalidArgument);
  for (int window : {0, 2, 4, -1}) {
    options.window = window;
    EXPECT_EQ(index.Search(*points, 5, options).status().code(), absl::StatusCode::kInvalidArgument) << window;
  }
  options.window = 3;
  EXPECT_TRUE(index.Search(*points, 0, options).ok());  // a window past the clip's start is fine
  EXPECT_TRUE(index.Search(*points, 19, options).ok());

  // Points made with other options do not fit.
  BodyPointOptions other;
  other.points_per_group = 7;
  absl::StatusOr<ClipPoints> other_points = QueryPoints(MakeWalkingClip({}, 20, 1.0 / 30.0), other);
  ASSERT_TRUE(other_points.ok());
  options.window = 1;
  EXPECT_EQ(index.Search(*other_points, 0, options).status().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace mocap

namespace mocap {
namespace {

// The exact best match in `database_clip` of every 7th frame of `query_clip` (its own rig).
absl::StatusOr<std::vector<PoseMatch>> BestMatchOfEvery7thFrame(const BvhClip& database_clip, const BvhClip& query_clip,
                                                                ChainScaling scaling) {
  const BodyPointOptions points{.scaling = scaling};
  MOCAP_ASSIGN_OR_RETURN(PoseIndex index, BuildIndex({database_clip}, points));
  MOCAP_ASSIGN_OR_RETURN(ClipPoints query, QueryPoints(query_clip, points));
  PoseSearchOptions options;
  options.exact = true;
  std::vector<PoseMatch> best;
  for (int f = 0; f < kFrames; f += 7) {
    MOCAP_ASSIGN_OR_RETURN(std::vector<PoseMatch> matches, index.Search(query, f, options));
    best.push_back(matches.front());
  }
  return best;
}

// Issue #11: the same joint rotations on a differently built body (each group's bones scaled)
// are the same posture. Per-chain scaling finds every frame of the walk itself with a distance
// near zero; the seed's body scale leaves the build in the points.
TEST(PoseIndexTest, PerChainScalingFactorsOutBodyProportions) {
  const BvhClip database_clip = Walk();
  const BvhClip original = Walk({.fingers_and_toes = true});
  BvhClip query_clip = original;
  absl::StatusOr<RigModel> rig = BuildRigModel(query_clip, {});
  ASSERT_TRUE(rig.ok()) << rig.status();
  testing::ScaleProportions(query_clip, rig->topology, {.legs = 1.2f, .arms = 0.8f, .spine = 1.25f, .head = 0.85f});
  // The generator changed the build: the legs' chain is 1.2 times as long, the arm's 0.8 times.
  const BodyChains chains = MakeBodyChains(rig->skeleton, rig->topology);
  const GlobalPoses poses_before =
      ForwardKinematics(original.skeleton, MotionFromChannels(original.skeleton, original.channels, 1.0 / 30));
  const GlobalPoses poses_after =
      ForwardKinematics(query_clip.skeleton, MotionFromChannels(query_clip.skeleton, query_clip.channels, 1.0 / 30));
  auto chain_length = [&](const GlobalPoses& poses, BodyGroup group) {
    const std::vector<int>& chain = chains.joints[static_cast<int>(group)];
    float length = 0;
    for (size_t i = 1; i < chain.size(); ++i)
      length += (poses.position(10, chain[i]) - poses.position(10, chain[i - 1])).norm();
    return length;
  };
  EXPECT_NEAR(chain_length(poses_after, BodyGroup::kLeftLeg) / chain_length(poses_before, BodyGroup::kLeftLeg), 1.2f,
              1e-3f);
  EXPECT_NEAR(chain_length(poses_after, BodyGroup::kRightArm) / chain_length(poses_before, BodyGroup::kRightArm), 0.8f,
              1e-3f);

  float worst_per_chain = 0, best_body_scale = 1e9f;
  for (ChainScaling scaling : {ChainScaling::kBoneDirections, ChainScaling::kPerChain, ChainScaling::kBodyScale}) {
    absl::StatusOr<std::vector<PoseMatch>> best_matches = BestMatchOfEvery7thFrame(database_clip, query_clip, scaling);
    ASSERT_TRUE(best_matches.ok()) << best_matches.status();
    for (int f = 0; f < kFrames; f += 7) {
      const PoseMatch& best = (*best_matches)[f / 7];
      if (scaling != ChainScaling::kBodyScale) {
        EXPECT_LE(std::abs(best.frame - f), 1) << ChainScalingName(scaling) << ", frame " << f;
        worst_per_chain = std::max(worst_per_chain, best.distance.total);
      } else {
        best_body_scale = std::min(best_body_scale, best.distance.total);
      }
    }
  }
  EXPECT_LT(worst_per_chain, 0.02f);
  EXPECT_GT(best_body_scale, 10 * worst_per_chain);
}

// Issue #11: bodies differ bone by bone, not group by group (thigh against shin, clavicle
// against upper arm, left against right). Bone directions see the same posture (distance near
// zero, its own frame first); per-chain scaling, which keeps proportions within a chain, does not.
TEST(PoseIndexTest, BoneDirectionsFactorOutEveryBonesLength) {
  const BvhClip database_clip = Walk();
  BvhClip query_clip = Walk({.fingers_and_toes = true});
  absl::StatusOr<RigModel> rig = BuildRigModel(query_clip, {});
  ASSERT_TRUE(rig.ok()) << rig.status();
  std::mt19937 random(5);
  testing::ScaleEveryBone(query_clip, rig->topology, random);

  std::map<ChainScaling, float> worst;
  for (ChainScaling scaling : {ChainScaling::kBoneDirections, ChainScaling::kPerChain}) {
    absl::StatusOr<std::vector<PoseMatch>> best_matches = BestMatchOfEvery7thFrame(database_clip, query_clip, scaling);
    ASSERT_TRUE(best_matches.ok()) << best_matches.status();
    for (int f = 0; f < kFrames; f += 7) {
      const PoseMatch& best = (*best_matches)[f / 7];
      if (scaling == ChainScaling::kBoneDirections) {
        EXPECT_LE(std::abs(best.frame - f), 1) << "frame " << f;
      }
      worst[scaling] = std::max(worst[scaling], best.distance.total);
    }
  }
  // Measured 4e-6 against 0.78. (A spine keeps its own shape: on a rig whose spine has several
  // bones, vertebrae of different lengths would leave a small distance.)
  EXPECT_LT(worst[ChainScaling::kBoneDirections], 0.01f);
  EXPECT_GT(worst[ChainScaling::kPerChain], 0.1f);
}

}  // namespace
}  // namespace mocap

namespace mocap {
namespace {

TEST(PoseIndexTest, NeighbourReferenceMeasuresOtherClipsAndIsKept) {
  absl::StatusOr<PoseIndex> single = BuildIndex({Walk()});
  ASSERT_TRUE(single.ok()) << single.status();
  EXPECT_EQ(single->NeighbourReference({}).status().code(), absl::StatusCode::kFailedPrecondition);

  SyntheticRigOptions other;
  other.clavicle_length = 18.0;
  absl::StatusOr<PoseIndex> index = BuildIndex({Walk(), Walk(other)});
  ASSERT_TRUE(index.ok()) << index.status();
  PoseSearchOptions options;
  options.exact = true;
  // Left out: its own clip (else every frame would find itself at 0).
  options.exclude_clip = 0;
  absl::StatusOr<std::vector<PoseMatch>> matches = index->Search(index->clip(0), 10, options);
  ASSERT_TRUE(matches.ok()) << matches.status();
  for (const PoseMatch& match : *matches) EXPECT_EQ(match.clip, 1);
  options.exclude_clip = -1;
  absl::StatusOr<NeighbourDistances> reference = index->NeighbourReference(options);
  ASSERT_TRUE(reference.ok()) << reference.status();
  EXPECT_EQ(reference->frames, std::min<int>(kNeighbourReferenceFrames, static_cast<int>(index->num_frames())));
  EXPECT_GT(reference->median, 0.0f);  // the other clip's shoulders are wider: near, not equal
  EXPECT_GE(reference->isolated, reference->median);
  absl::StatusOr<NeighbourDistances> again = index->NeighbourReference(options);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->isolated, reference->isolated);
  // A pose no clip has (the left arm raised overhead) is further than the isolated frames.
  BvhClip raised = Walk();
  RaiseLeftArmOverTime(raised, 170.0f);
  absl::StatusOr<PoseIndex> query_index = BuildIndex({raised});
  ASSERT_TRUE(query_index.ok());
  absl::StatusOr<std::vector<PoseMatch>> best =
      index->Search(query_index->clip(0), static_cast<int>(query_index->clip(0).points.rows()) - 1, options);
  ASSERT_TRUE(best.ok() && !best->empty());
  EXPECT_GT(best->front().distance.total, kNoSimilarPoseNovelty * reference->isolated);
}

// ---------------------------------------------------------------------------------------------
// Searches run in steps (the service's slices of bounded time, issue #24) find what one call finds.

TEST(PoseIndexTest, ASearchRunInStepsFindsWhatOneSearchFinds) {
  SyntheticRigOptions other;
  other.clavicle_length = 18.0;
  absl::StatusOr<PoseIndex> index = BuildIndex({Walk(), Walk(other), MakeWalkingClip({}, 75, 1.0 / 60.0)});
  ASSERT_TRUE(index.ok()) << index.status();
  for (bool exact : {true, false}) {
    for (int window : {1, 5}) {
      for (int suppress : {0, 3}) {
        PoseSearchOptions options;
        options.exact = exact;
        options.window = window;
        options.top_k = 4;
        options.candidates = 40;
        options.suppress_within_frames = suppress;
        SCOPED_TRACE(::testing::Message() << "exact " << exact << " window " << window << " suppress " << suppress);
        absl::StatusOr<std::vector<PoseMatch>> whole = index->Search(index->clip(1), 17, options);
        ASSERT_TRUE(whole.ok()) << whole.status();
        absl::StatusOr<PoseIndex::Run> run = index->StartSearch(index->clip(1), 17, options);
        ASSERT_TRUE(run.ok()) << run.status();
        int steps = 1;
        while (!run->Step(3)) ++steps;
        EXPECT_EQ(steps, exact ? (index->num_frames() + 2) / 3 : (40 + 2) / 3);
        const std::vector<PoseMatch> stepped = run->Matches();
        ASSERT_EQ(stepped.size(), whole->size());
        for (size_t i = 0; i < stepped.size(); ++i) {
          EXPECT_EQ(stepped[i].clip, (*whole)[i].clip);
          EXPECT_EQ(stepped[i].frame, (*whole)[i].frame);
          EXPECT_EQ(stepped[i].distance.total, (*whole)[i].distance.total);
        }
      }
    }
  }
  // Arguments are checked when the run starts.
  PoseSearchOptions even;
  even.window = 4;
  EXPECT_EQ(index->StartSearch(index->clip(0), 0, even).status().code(), absl::StatusCode::kInvalidArgument);
}

TEST(PoseIndexTest, TheNeighbourReferenceMeasuredInStepsIsTheOneKeptForEveryCaller) {
  SyntheticRigOptions other;
  other.clavicle_length = 18.0;
  absl::StatusOr<PoseIndex> measured_at_once = BuildIndex({Walk(), Walk(other)});
  absl::StatusOr<PoseIndex> measured_in_steps = BuildIndex({Walk(), Walk(other)});
  ASSERT_TRUE(measured_at_once.ok() && measured_in_steps.ok());
  PoseSearchOptions options;
  options.window = 3;
  absl::StatusOr<NeighbourDistances> at_once = measured_at_once->NeighbourReference(options);
  ASSERT_TRUE(at_once.ok()) << at_once.status();

  EXPECT_FALSE(measured_in_steps->CachedNeighbourReference(options).has_value());
  absl::StatusOr<PoseIndex::ReferenceRun> run = measured_in_steps->StartNeighbourReference(options);
  ASSERT_TRUE(run.ok()) << run.status();
  EXPECT_EQ(run->Result().status().code(), absl::StatusCode::kFailedPrecondition);  // not measured yet
  int steps = 1;
  while (!run->Step(5)) ++steps;
  EXPECT_GT(steps, kNeighbourReferenceFrames / 10);  // sample searches are cut, not run whole
  absl::StatusOr<NeighbourDistances> in_steps = run->Result();
  ASSERT_TRUE(in_steps.ok()) << in_steps.status();
  EXPECT_EQ(in_steps->median, at_once->median);
  EXPECT_EQ(in_steps->isolated, at_once->isolated);
  EXPECT_EQ(in_steps->frames, at_once->frames);
  // Kept: and an exact search of the same weights and window is measured by the same yardstick.
  options.exact = true;
  std::optional<NeighbourDistances> kept = measured_in_steps->CachedNeighbourReference(options);
  ASSERT_TRUE(kept.has_value());
  EXPECT_EQ(kept->isolated, in_steps->isolated);
  options.window = 5;
  EXPECT_FALSE(measured_in_steps->CachedNeighbourReference(options).has_value());
}

}  // namespace
}  // namespace mocap
