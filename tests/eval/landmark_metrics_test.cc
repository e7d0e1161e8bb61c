// Landmark scoring (eval/landmark_metrics.h) and loading test clips on any rig
// (eval/cross_dataset.h): times, interpolation, groups, units and axes.
#include "eval/landmark_metrics.h"

#include <gtest/gtest.h>

#include "eval/cross_dataset.h"
#include "motion/bvh/bvh_writer.h"
#include "tests/support/synthetic_database.h"
#include "tests/support/temp_dir.h"

namespace mocap::eval {
namespace {

using testing::MakeSyntheticReconstructionSetup;

// Output frames (database rate, from time 0) posed as the synthetic test clip, and the database
// body's landmarks of each.
struct Output {
  std::vector<ReconstructedFrame> frames;
  std::vector<std::array<Eigen::Vector3f, kNumScoredLandmarks>> landmarks;
};

Output PosedAsTestClip(const testing::SyntheticReconstructionSetup& setup) {
  Output out;
  const auto joints = ScoredLandmarkJoints(setup.rig.topology.landmarks);
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> positions;
  const LocalMotion& motion = setup.test_clip.motion;
  for (int f = 0; f < motion.num_frames(); ++f) {
    ReconstructedFrame frame;
    frame.index = frame.frame_in_segment = f;
    frame.time = f * setup.database->frame_time();
    frame.pose.root_position = motion.translation(f, 0);
    for (int j = 0; j < motion.num_joints(); ++j) frame.pose.rotations.push_back(motion.rotation(f, j));
    setup.database->body().WorldTransforms(frame.pose, &rotations, &positions);
    std::array<Eigen::Vector3f, kNumScoredLandmarks> at;
    for (int k = 0; k < kNumScoredLandmarks; ++k) at[k] = positions[joints[k]];
    frame.wrists = {at[kLeftWristLandmark], at[kRightWristLandmark]};
    out.landmarks.push_back(at);
    out.frames.push_back(frame);
  }
  return out;
}

TEST(LandmarkMetricsTest, ScoresAtTheTruthsOwnTimes) {
  const auto setup = MakeSyntheticReconstructionSetup();
  const Output out = PosedAsTestClip(setup);
  // The same body at twice the rate: every other frame halfway between two output frames.
  LandmarkTruth truth{.frame_time = setup.database->frame_time() / 2, .positions = {}};
  for (size_t i = 0; i + 1 < out.landmarks.size(); ++i) {
    truth.positions.push_back(out.landmarks[i]);
    std::array<Eigen::Vector3f, kNumScoredLandmarks> mid;
    for (int k = 0; k < kNumScoredLandmarks; ++k) mid[k] = 0.5f * (out.landmarks[i][k] + out.landmarks[i + 1][k]);
    truth.positions.push_back(mid);
  }
  truth.positions.push_back(out.landmarks.back());
  // Past the output's last frame: not scored.
  truth.positions.push_back(out.landmarks.back());
  const LandmarkMetrics m = MeasureLandmarks(*setup.database, truth, out.frames);
  EXPECT_EQ(m.frames, 2.0 * out.frames.size() - 1);
  EXPECT_LT(m.Mean(m.landmark_error_m), 1e-5);
  // A truth one output frame late is far off: times are not ignored.
  LandmarkTruth late = truth;
  late.positions.erase(late.positions.begin(), late.positions.begin() + 2);
  const LandmarkMetrics off = MeasureLandmarks(*setup.database, late, out.frames);
  EXPECT_GT(off.Mean(off.landmark_error_m), 0.005);
}

TEST(LandmarkMetricsTest, GroupsAverageTheirPairs) {
  const auto setup = MakeSyntheticReconstructionSetup();
  const Output out = PosedAsTestClip(setup);
  LandmarkTruth truth{.frame_time = setup.database->frame_time(), .positions = out.landmarks};
  for (auto& frame : truth.positions) {
    frame[kPelvisLandmark].y() += 0.10f;     // pelvis 10 cm off
    frame[kLeftWristLandmark].x() += 0.04f;  // one wrist 4 cm off: the wrists' group 2 cm
  }
  const LandmarkMetrics m = MeasureLandmarks(*setup.database, truth, out.frames);
  EXPECT_NEAR(m.Mean(m.group_error_m[0]), 0.10, 1e-5);
  EXPECT_NEAR(m.Mean(m.wrist_error_m()), 0.02, 1e-5);
  EXPECT_NEAR(m.Mean(m.group_error_m[7]), 0.0, 1e-5);
  EXPECT_NEAR(m.Mean(m.landmark_error_m), 0.14 / kNumScoredLandmarks, 1e-5);
  EXPECT_EQ(m.clips, 1);
}

// A body sized up on its way out (body_sizer.h) is measured where its capture moves: the
// performer's space. The same output drawn 1.5 times as large moves 1.5 times as fast, and its
// capture, 1.5 times as large too, allows it no more than it allows the unsized body.
TEST(LandmarkMetricsTest, ASizedBodyIsMeasuredInThePerformersSpace) {
  const auto setup = MakeSyntheticReconstructionSetup();
  const Output out = PosedAsTestClip(setup);
  LandmarkTruth truth{.frame_time = setup.database->frame_time(), .positions = out.landmarks};
  LandmarkTruth larger = truth;
  for (auto& frame : larger.positions) {
    for (Eigen::Vector3f& p : frame) p *= 1.5f;
  }
  const SizeMap sized{.scale = 1.5f};
  const LandmarkMetrics same = MeasureLandmarks(*setup.database, truth, out.frames);
  const LandmarkMetrics grown = MeasureLandmarks(*setup.database, larger, out.frames, std::span(&sized, 1));
  EXPECT_LT(grown.Mean(grown.landmark_error_m), 1e-5);
  ASSERT_GT(same.plausibility.pelvis_speed.max(), 0.0f);
  EXPECT_NEAR(grown.plausibility.pelvis_speed.max(), 1.5f * same.plausibility.pelvis_speed.max(), 0.02f);
  EXPECT_NEAR(grown.plausibility.ankle_speed.max(), 1.5f * same.plausibility.ankle_speed.max(), 0.02f);
  EXPECT_NEAR(grown.worst_speed_over_allowed * AllowedSpeed(static_cast<float>(grown.truth_pelvis_speed_max)),
              grown.plausibility.pelvis_speed.max(), 1e-4);
  EXPECT_NEAR(grown.truth_pelvis_speed_max, 1.5 * same.truth_pelvis_speed_max, 1e-4);
  // The lower foot over its planted height grows with the body, as the capture's would.
  EXPECT_NEAR(grown.plausibility.lower_foot_height.max(), 1.5f * same.plausibility.lower_foot_height.max(), 0.003f);
}

// Times between two segments (a dropout the engine did not bridge) have no answer: their
// positions are scored as interpolated, but they give no confidence pairs.
TEST(LandmarkMetricsTest, AnUnansweredGapGivesNoConfidencePairs) {
  const auto setup = MakeSyntheticReconstructionSetup();
  Output out = PosedAsTestClip(setup);
  LandmarkTruth truth{.frame_time = setup.database->frame_time(), .positions = out.landmarks};
  const int size = static_cast<int>(out.frames.size());
  ASSERT_GT(size, 40);
  std::vector<ReconstructedFrame> answered;
  for (int f = 0; f < size; ++f) {
    if (f >= 20 && f < 30) continue;  // a gap of 10 frames
    ReconstructedFrame frame = out.frames[f];
    frame.segment = f >= 30 ? 1 : 0;
    answered.push_back(frame);
  }
  std::vector<ConfidenceSample> pairs;
  const LandmarkMetrics m = MeasureLandmarks(*setup.database, truth, answered, {}, &pairs);
  EXPECT_EQ(m.frames, size);  // every truth frame scored
  EXPECT_EQ(pairs.size(), static_cast<size_t>((size - 10) * kNumBodyLandmarks));
}

// A clip of another rig (metres, authored Z-up, CC-like extra bones, 60 fps) is read on its own
// rig: its landmarks are where the same motion's are on the plain centimetre rig.
TEST(LandmarkTestClipTest, AnyRigUnitAndRateGivesTheSameLandmarks) {
  testing::ScopedTempDir dir;
  const BvhClip plain = testing::MakeWalkingClip({}, 90, 1.0 / 60.0);
  const BvhClip other =
      testing::MakeWalkingClip({.z_up = true, .twist_bones = true, .length_scale = 0.01}, 90, 1.0 / 60.0);
  ASSERT_TRUE(WriteBvhFile(plain, dir.path() / "plain.bvh").ok());
  ASSERT_TRUE(WriteBvhFile(other, dir.path() / "other.bvh").ok());
  auto a = LoadLandmarkTestClip(dir.path() / "plain.bvh", "named", "walk", 0);
  auto b = LoadLandmarkTestClip(dir.path() / "other.bvh", "named", "walk", 0);
  ASSERT_TRUE(a.ok()) << a.status();
  ASSERT_TRUE(b.ok()) << b.status();
  EXPECT_NEAR(a->truth.frame_time, 1.0 / 60.0, 1e-9);
  ASSERT_EQ(a->truth.num_frames(), 90);
  ASSERT_EQ(b->truth.num_frames(), 90);
  EXPECT_TRUE(Moves(a->truth));
  for (int f = 0; f < 90; f += 10) {
    for (int k : {kPelvisLandmark, kLeftWristLandmark, kRightWristLandmark, 12, 13}) {
      EXPECT_LT((a->truth.positions[f][k] - b->truth.positions[f][k]).norm(), 0.01)
          << "frame " << f << " landmark " << k;
    }
  }
  EXPECT_GT(a->truth.positions[0][kPelvisLandmark].y(), 0.5f);  // metres, Y up
  auto cut = LoadLandmarkTestClip(dir.path() / "plain.bvh", "named", "walk", 30);
  ASSERT_TRUE(cut.ok());
  EXPECT_EQ(cut->truth.num_frames(), 30);
}

TEST(LandmarkTestClipTest, StillAndOneFrameClipsAreLeftOut) {
  testing::ScopedTempDir dir;
  ASSERT_TRUE(WriteBvhFile(testing::MakeStandingClip({}, 45), dir.path() / "stand.bvh").ok());
  auto one = LoadLandmarkTestClip(dir.path() / "stand.bvh", "named", "stand", 0);
  EXPECT_EQ(one.status().code(), absl::StatusCode::kFailedPrecondition);
  BvhClip still = testing::MakeStandingClip({}, 45);
  still.channels = still.channels.replicate(40, 1).eval();
  ASSERT_TRUE(WriteBvhFile(still, dir.path() / "still.bvh").ok());
  auto set = LoadLandmarkTests({dir.path() / "still.bvh", dir.path() / "stand.bvh"}, 0);
  ASSERT_TRUE(set.ok()) << set.status();
  EXPECT_TRUE(set->clips.empty());
  ASSERT_EQ(set->left_out.size(), 2u);
  EXPECT_NE(set->left_out[0].find("does not move"), std::string::npos) << set->left_out[0];
}

// Issue #25: the output's jerk after each input dropout against the capture's at the same times.
TEST(ReentryJerkTest, AfterEachDropoutTheOutputsJerkAgainstTheCapturesAtTheSameTimes) {
  const auto setup = MakeSyntheticReconstructionSetup();
  Output out = PosedAsTestClip(setup);
  LandmarkTruth truth{.frame_time = setup.database->frame_time(), .positions = out.landmarks};
  const double dt = setup.database->frame_time();
  const int frames = static_cast<int>(out.frames.size());
  ASSERT_GT(frames, 40);
  // Input every frame but frames 20-29: one dropout, back at frame 30.
  std::vector<WristSample> samples;
  for (int f = 0; f < frames; ++f) {
    if (f < 20 || f >= 30) samples.push_back({.time = f * dt});
  }
  LandmarkMetrics same;
  MeasureReentryJerk(*setup.database, truth, out.frames, samples, {}, &same);
  EXPECT_EQ(same.reentries, 1);
  EXPECT_GT(same.truth_reentry_jerk, 0.0);
  EXPECT_NEAR(same.reentry_jerk, same.truth_reentry_jerk, 1e-3 * same.truth_reentry_jerk);
  // The body jumps 10 cm where the input comes back: the output jerks, the capture does not.
  for (int f = 30; f < frames; ++f) out.frames[f].pose.root_position.x() += 0.1f;
  LandmarkMetrics jumped;
  MeasureReentryJerk(*setup.database, truth, out.frames, samples, {}, &jumped);
  EXPECT_EQ(jumped.reentries, 1);
  EXPECT_GT(jumped.reentry_jerk, 3 * jumped.truth_reentry_jerk);
  // No dropout, no re-entry.
  std::vector<WristSample> steady;
  for (int f = 0; f < frames; ++f) steady.push_back({.time = f * dt});
  LandmarkMetrics none;
  MeasureReentryJerk(*setup.database, truth, out.frames, steady, {}, &none);
  EXPECT_EQ(none.reentries, 0);
}

}  // namespace
}  // namespace mocap::eval
