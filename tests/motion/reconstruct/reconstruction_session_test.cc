#include "motion/reconstruct/reconstruction_session.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "motion/reconstruct/hand_floor.h"
#include "tests/support/synthetic_database.h"

namespace mocap {
namespace {

class ReconstructionSessionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    setup_ = testing::MakeSyntheticReconstructionSetup({}, 75);
    options_.ankle_candidates = 60;  // the synthetic database is small
    options_.pose_neighbours = 40;
  }

  // Mean joint position error (metres) of `frames` against the test clip.
  double Mpjpe(const std::vector<ReconstructedFrame>& frames) const {
    std::vector<Eigen::Quaternionf> rotations;
    std::vector<Eigen::Vector3f> positions;
    double sum = 0;
    long count = 0;
    for (const ReconstructedFrame& frame : frames) {
      setup_.database->body().WorldTransforms(frame.pose, &rotations, &positions);
      for (int j = 0; j < setup_.truth.num_joints(); ++j) {
        sum += (positions[j] - setup_.truth.position(frame.frame_in_segment, j)).norm();
        ++count;
      }
    }
    return sum / count;
  }

  testing::SyntheticReconstructionSetup setup_;
  ReconstructionOptions options_;
};

TEST_F(ReconstructionSessionTest, OfflineReconstructionFollowsTheCapturedWalk) {
  auto frames = ReconstructOffline(setup_.database, options_, testing::WristSamplesOf(setup_));
  ASSERT_TRUE(frames.ok()) << frames.status();
  ASSERT_EQ(frames->size(), 75u);
  EXPECT_LT(Mpjpe(*frames), 0.05);
  const BodyLandmarks& l = setup_.rig.topology.landmarks;
  for (const ReconstructedFrame& frame : *frames) {
    if (getenv("DEBUG_SESSION")) {
      const int f = frame.frame_in_segment;
      const int row = frame.diagnostics.ankle_source_row;
      std::cerr << f << " truth " << setup_.truth.position(f, l.left_ankle).transpose() << " est "
                << frame.ankles[0].transpose() << " row " << row << " clip " << setup_.database->clip_of(row) << ":"
                << setup_.database->frame_in_clip(row) << " wd " << frame.diagnostics.wrist_neighbour_distance
                << " contact " << frame.diagnostics.contact[0] << "\n";
    }
    EXPECT_LT((frame.pelvis_position - setup_.truth.position(frame.frame_in_segment, l.pelvis)).norm(), 0.08);
    EXPECT_LT((frame.ankles[0] - setup_.truth.position(frame.frame_in_segment, l.left_ankle)).norm(), 0.15);
    EXPECT_EQ(frame.index, frame.frame_in_segment);
    EXPECT_EQ(frame.segment, 0);
  }
  // The walk has planted feet: the cleanup finds contacts on both sides.
  int left = 0, right = 0;
  for (const ReconstructedFrame& frame : *frames) {
    left += frame.diagnostics.contact[0];
    right += frame.diagnostics.contact[1];
  }
  EXPECT_GT(left, 10);
  EXPECT_GT(right, 10);
}

TEST_F(ReconstructionSessionTest, StreamingInSubIntervalsEqualsOfflineWithTheSameWindows) {
  options_.window = 20;
  const auto samples = testing::WristSamplesOf(setup_);
  auto offline = ReconstructOffline(setup_.database, options_, samples);
  ASSERT_TRUE(offline.ok());
  auto session = ReconstructionSession::Create(setup_.database, options_);
  ASSERT_TRUE(session.ok());
  std::vector<ReconstructedFrame> streamed;
  for (size_t i = 0; i < samples.size(); ++i) {
    ASSERT_TRUE((*session)->Push(samples[i], &streamed).ok());
    // Windows of 20 leave as they fill (after A2's look-ahead of 2 frames), less the joint
    // filter's lag.
    if (i == 19 + 2) {
      EXPECT_EQ(static_cast<int>(streamed.size()), 20 - 3);
    } else if (i == 18 + 2) {
      EXPECT_TRUE(streamed.empty());
    }
  }
  ASSERT_TRUE((*session)->Finish(&streamed).ok());
  ASSERT_EQ(streamed.size(), offline->size());
  for (size_t f = 0; f < streamed.size(); ++f) {
    EXPECT_EQ(streamed[f].pelvis_position, (*offline)[f].pelvis_position);
    for (size_t j = 0; j < streamed[f].pose.rotations.size(); ++j) {
      EXPECT_EQ(streamed[f].pose.rotations[j].coeffs(), (*offline)[f].pose.rotations[j].coeffs());
    }
  }
  EXPECT_EQ((*session)->latency_frames(), 2 + 19 + 3);
}

TEST_F(ReconstructionSessionTest, FixedLagEmitsFrameTMinusDWhenFrameTArrives) {
  for (int lag : {0, 2, 8}) {
    options_.mode = StreamMode::kFixedLag;
    options_.lag = lag;
    auto session = ReconstructionSession::Create(setup_.database, options_);
    ASSERT_TRUE(session.ok());
    std::vector<ReconstructedFrame> out;
    const auto samples = testing::WristSamplesOf(setup_);
    for (size_t t = 0; t < samples.size(); ++t) {
      ASSERT_TRUE((*session)->Push(samples[t], &out).ok());
      ASSERT_EQ(static_cast<int>(out.size()), std::max(0, static_cast<int>(t) - lag + 1))
          << "lag " << lag << " t " << t;
    }
    ASSERT_TRUE((*session)->Finish(&out).ok());
    EXPECT_EQ(out.size(), samples.size());
    EXPECT_LT(Mpjpe(out), 0.08) << "lag " << lag;
  }
}

// Stop 86: at lag 0 the joint filter has no frame ahead of the one it emits; repeating that frame
// for the taps beyond held the pelvis of a walking body behind where it was solved. The line
// through the frames there are follows it (ReconstructionOptions::pelvis_edge_fit).
TEST_F(ReconstructionSessionTest, ALagZeroStreamsPelvisKeepsUpWithAWalk) {
  options_.mode = StreamMode::kFixedLag;
  options_.lag = 0;
  const BodyLandmarks& l = setup_.rig.topology.landmarks;
  const double dt = setup_.database->frame_time();
  // The mean of the pelvis's miss along the captured walk's direction (negative: behind), metres,
  // once the stream's first half second (read as standing, MotionGuardOptions::start_rest_seconds)
  // has passed.
  const int kSettled = static_cast<int>(std::lround(0.5 / setup_.database->frame_time()));
  auto mean_lead = [&](bool edge_fit) {
    options_.pelvis_edge_fit = edge_fit;
    auto frames = ReconstructOffline(setup_.database, options_, testing::WristSamplesOf(setup_));
    EXPECT_TRUE(frames.ok()) << frames.status();
    double sum = 0.0;
    int count = 0;
    for (const ReconstructedFrame& frame : *frames) {
      const int f = frame.frame_in_segment;
      if (f < kSettled) continue;
      Eigen::Vector3f velocity = (setup_.truth.position(f, l.pelvis) - setup_.truth.position(f - 1, l.pelvis)) / dt;
      velocity.y() = 0.0f;
      if (velocity.norm() < 0.5f) continue;
      sum += (frame.pelvis_position - setup_.truth.position(f, l.pelvis)).dot(velocity.normalized());
      ++count;
    }
    EXPECT_GT(count, 10);
    return sum / std::max(count, 1);
  };
  const double repeated = mean_lead(false), fitted = mean_lead(true);
  EXPECT_LT(repeated, -0.005) << "the repeated newest frame held the pelvis back";
  // The filter's share of the lag (a third of a frame at σ = 1, less as the guard's catching up
  // after the standing start); A6's E_smooth over the frames before keeps the rest.
  EXPECT_GT(fitted, repeated + 0.002) << "fitted " << fitted << " m, repeated " << repeated;
}

// ... and a standing body's is not: where the guard holds the body as standing, a line through the
// solve's hops between stances would carry them ahead.
TEST_F(ReconstructionSessionTest, ALagZeroStreamDoesNotExtrapolateAStandingBodysHops) {
  options_.mode = StreamMode::kFixedLag;
  options_.lag = 0;
  std::vector<WristSample> samples = testing::WristSamplesOf(setup_);
  std::mt19937 random(7);
  std::normal_distribution<float> jitter(0.0f, 0.005f);
  for (WristSample& sample : samples) {  // the first sample's hands held still, a tracker's jitter on them
    sample.left = samples.front().left + Eigen::Vector3f(jitter(random), jitter(random), jitter(random));
    sample.right = samples.front().right + Eigen::Vector3f(jitter(random), jitter(random), jitter(random));
  }
  options_.pelvis_edge_fit = false;
  auto repeated = ReconstructOffline(setup_.database, options_, samples);
  options_.pelvis_edge_fit = true;
  auto fitted = ReconstructOffline(setup_.database, options_, samples);
  ASSERT_TRUE(repeated.ok() && fitted.ok());
  ASSERT_EQ(repeated->size(), fitted->size());
  double most = 0.0;  // rounding aside (a segment's first frame: one frame's weight 1 against the kernel's sum)
  for (size_t f = 0; f < fitted->size(); ++f)
    most = std::max(most, static_cast<double>(((*fitted)[f].pelvis_position - (*repeated)[f].pelvis_position).norm()));
  EXPECT_LT(most, 1e-4);
}

// Issue #14: a session kept every frame's state for its whole life (~118 kB per 1,000 frames).
TEST_F(ReconstructionSessionTest, ALongSessionHoldsOnlyWhatItsWindowAndLagReach) {
  const auto clip = testing::WristSamplesOf(setup_);
  for (const bool fixed_lag : {true, false}) {
    options_.mode = fixed_lag ? StreamMode::kFixedLag : StreamMode::kSubInterval;
    options_.lag = 5;
    options_.window = 30;
    auto session = ReconstructionSession::Create(setup_.database, options_);
    ASSERT_TRUE(session.ok());
    std::vector<ReconstructedFrame> out;
    const double period = clip[1].time - clip[0].time;
    int most_held = 0;
    for (int t = 0; t < 5'000; ++t) {  // the clip played forwards again and again, time running on
      WristSample sample = clip[t % clip.size()];
      sample.time = t * period;
      ASSERT_TRUE((*session)->Push(sample, &out).ok());
      most_held = std::max(most_held, (*session)->frames_held());
    }
    ASSERT_TRUE((*session)->Finish(&out).ok());
    EXPECT_EQ(out.size(), 5'000u);
    // Window or lag, plus the kernels' reach and the forgotten prefix awaiting compaction.
    EXPECT_LE(most_held, 200) << (fixed_lag ? "fixed lag" : "sub-interval");
    EXPECT_GT(most_held, 5);
  }
}

TEST_F(ReconstructionSessionTest, RefusedSamplesLeaveTheSessionAsItWas) {
  options_.mode = StreamMode::kFixedLag;
  options_.lag = 4;
  const auto samples = testing::WristSamplesOf(setup_);
  auto clean = ReconstructOffline(setup_.database, options_, samples);
  ASSERT_TRUE(clean.ok());
  auto session = ReconstructionSession::Create(setup_.database, options_);
  ASSERT_TRUE(session.ok());
  std::vector<ReconstructedFrame> out;
  for (size_t t = 0; t < samples.size(); ++t) {
    if (t == 30) {
      WristSample bad = samples[t];
      bad.left.y() = std::numeric_limits<float>::quiet_NaN();
      EXPECT_EQ((*session)->Push(bad, &out).code(), absl::StatusCode::kInvalidArgument);
      EXPECT_EQ((*session)->Push(samples[t - 3], &out).code(), absl::StatusCode::kInvalidArgument);  // backwards
    }
    ASSERT_TRUE((*session)->Push(samples[t], &out).ok());
  }
  ASSERT_TRUE((*session)->Finish(&out).ok());
  ASSERT_EQ(out.size(), clean->size());
  for (size_t f = 0; f < out.size(); ++f) EXPECT_EQ(out[f].pelvis_position, (*clean)[f].pelvis_position);
  EXPECT_EQ((*session)->statistics().refused_samples, 2);
}

TEST_F(ReconstructionSessionTest, ADropoutIsBridgedAndPredictedUpToMaxGap) {
  auto samples = testing::WristSamplesOf(setup_);
  const double dt = setup_.database->frame_time();
  samples.erase(samples.begin() + 30, samples.begin() + 60);  // a 1 s dropout (as a hand out of view)
  auto frames = ReconstructOffline(setup_.database, options_, samples);
  ASSERT_TRUE(frames.ok()) << frames.status();
  ASSERT_EQ(frames->size(), 75u);  // every frame of the clip, in one segment
  for (const ReconstructedFrame& frame : *frames) {
    EXPECT_EQ(frame.segment, 0);
    const bool in_gap = frame.time > samples[29].time + 1e-9 && frame.time < samples[30].time - 1e-9;
    for (int side = 0; side < 2; ++side) {
      EXPECT_EQ(frame.hand_state[side], in_gap ? TrackingState::kPredicted : TrackingState::kTracked)
          << "t = " << frame.time;
    }
  }
  EXPECT_NEAR(samples[30].time - samples[29].time, 31 * dt, 1e-9);
  // Longer than max_gap_seconds: the segment ends.
  options_.max_gap_seconds = 0.5;
  auto split = ReconstructOffline(setup_.database, options_, samples);
  ASSERT_TRUE(split.ok()) << split.status();
  EXPECT_EQ(split->back().segment, 1);
}

TEST_F(ReconstructionSessionTest, ABodyGoesOnFromTheOtherHandWhileOneIsLost) {
  // The left hand lost for 1.2 s from frame 20 (its samples NaN): no frame is missing, the segment
  // goes on, the left hand is predicted and then lost (after max_gap_seconds), the right tracked
  // throughout.
  options_.max_gap_seconds = 0.51;
  auto samples = testing::WristSamplesOf(setup_);
  for (int i = 20; i < 56; ++i) {
    samples[i].tracked[0] = false;
    samples[i].left = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
  }
  auto frames = ReconstructOffline(setup_.database, options_, samples);
  ASSERT_TRUE(frames.ok()) << frames.status();
  ASSERT_EQ(frames->size(), 75u);
  int predicted = 0, lost = 0;
  for (const ReconstructedFrame& frame : *frames) {
    EXPECT_EQ(frame.segment, 0);
    EXPECT_NE(frame.hand_state[1], TrackingState::kPredicted) << "t = " << frame.time;
    EXPECT_NE(frame.hand_state[1], TrackingState::kLost) << "t = " << frame.time;
    const double since = frame.time - samples[19].time;
    const bool missing = frame.frame_in_segment >= 20 && frame.frame_in_segment < 56;
    if (!missing) {
      EXPECT_NE(frame.hand_state[0], TrackingState::kPredicted) << "t = " << frame.time;
      EXPECT_NE(frame.hand_state[0], TrackingState::kLost) << "t = " << frame.time;
      continue;
    }
    EXPECT_NEAR(frame.diagnostics.untracked_seconds[0], since, 1e-4);
    EXPECT_EQ(frame.diagnostics.untracked_seconds[1], 0.0f);
    const TrackingState expected = since > 0.51 ? TrackingState::kLost : TrackingState::kPredicted;
    EXPECT_EQ(frame.hand_state[0], expected) << "t = " << frame.time;
    (expected == TrackingState::kLost ? lost : predicted)++;
  }
  EXPECT_EQ(predicted, 15);
  EXPECT_EQ(lost, 21);
  // Back at frame 56: tracked, but the hand is still partly the guess for the 0.5 s cross-fade,
  // and its expected error says so, falling as the guess fades (the "recently untracked" cue).
  const int left_wrist = 6;
  const ReconstructedFrame& back = (*frames)[56];
  EXPECT_EQ(back.hand_state[0], TrackingState::kTracked);
  EXPECT_GT(back.diagnostics.fading_guess[0].weight, 0.9f);
  const float settled = (*frames)[74].landmark_error[left_wrist];
  EXPECT_EQ((*frames)[74].diagnostics.fading_guess[0].weight, 0.0f);
  EXPECT_GT(back.landmark_error[left_wrist], 3 * settled);
  for (int f = 57; f < 75; ++f) {
    EXPECT_LE((*frames)[f].diagnostics.fading_guess[0].weight, (*frames)[f - 1].diagnostics.fading_guess[0].weight);
  }
}

// Input lowered out of the arms' reach (a performer reaching for the floor, which the walk's
// neighbours never did): the body crouches towards it, no faster than max_shift_speed, so the
// hands come nearer their input; its feet stay on the ground, none lower than without the shift.
TEST_F(ReconstructionSessionTest, InputBeyondReachBringsTheBodyNearerWithItsFeetOnTheGround) {
  auto samples = testing::WristSamplesOf(setup_);
  for (size_t i = 20; i < samples.size(); ++i) {
    const float drop = 0.35f * std::min(1.0f, static_cast<float>(i - 20) / 15.0f);  // over half a second
    samples[i].left.y() -= drop;
    samples[i].right.y() -= drop;
  }
  ReconstructionOptions still = options_;
  still.reach_lean.max_shift = 0.0f;
  auto shifted = ReconstructOffline(setup_.database, options_, samples);
  auto unshifted = ReconstructOffline(setup_.database, still, samples);
  ASSERT_TRUE(shifted.ok()) << shifted.status();
  ASSERT_TRUE(unshifted.ok()) << unshifted.status();
  ASSERT_EQ(shifted->size(), unshifted->size());
  const BodyModel& body = setup_.database->body();
  const BodyLandmarks& l = setup_.rig.topology.landmarks;
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> with, without;
  double miss_with = 0, miss_without = 0;
  const float ground = setup_.database->planted_ankle_height();
  float fastest = 0;
  int held = 0;  // feet on their pins
  Eigen::Vector3f previous_offset = Eigen::Vector3f::Zero();
  for (size_t f = 0; f < shifted->size(); ++f) {
    body.WorldTransforms((*shifted)[f].pose, &rotations, &with);
    body.WorldTransforms((*unshifted)[f].pose, &rotations, &without);
    for (int side = 0; side < 2; ++side) {
      const int wrist = side == 0 ? l.left_wrist : l.right_wrist;
      const Eigen::Vector3f& input = side == 0 ? samples[f].left : samples[f].right;
      miss_with += (with[wrist] - input).norm();
      miss_without += (without[wrist] - input).norm();
      const int ankle = side == 0 ? l.left_ankle : l.right_ankle;
      // A planted foot stays on its pin; a free one (or one the joint filter eases on or off
      // its pin) is not pushed below the ground by the crouch.
      const auto& pin = (*shifted)[f].ankle_targets[side];
      if (pin && (*shifted)[f].ankle_target_weight[side] == 1.0f) {  // (lifted to the floor where the pin is under it)
        ++held;
        const Eigen::Vector3f on_pin(pin->x(), std::max(pin->y(), ground), pin->z());
        EXPECT_LT((with[ankle] - on_pin).norm(), 0.01f) << "frame " << f;
      } else {
        EXPECT_GE(with[ankle].y(), std::min(without[ankle].y(), ground) - 0.002f) << "frame " << f;
      }
    }
    // The pelvis' offset against the unshifted body moves no faster than the shift may.
    const Eigen::Vector3f offset = with[l.pelvis] - without[l.pelvis];
    if (f > 0) fastest = std::max(fastest, (offset - previous_offset).norm() / static_cast<float>(1.0 / 30.0));
    previous_offset = offset;
  }
  EXPECT_LT(miss_with, 0.7 * miss_without);
  EXPECT_GT(held, 10);
  EXPECT_GT(fastest, 0.0f);
  // The shift's speed, plus what the guard and the joint filter do differently on the moved body.
  EXPECT_LE(fastest, ReachLeanOptions{}.max_shift_speed * 2.0f);
}

// The same input, lowered 35 cm: the solve sinks the body with it, but no ankle ends under the
// database's planted ankle height (the knees bend instead); with the rule off, the ankles sink.
TEST_F(ReconstructionSessionTest, NoAnkleEndsUnderTheFloorWhenTheInputDrops) {
  auto samples = testing::WristSamplesOf(setup_);
  for (size_t i = 20; i < samples.size(); ++i) {
    const float drop = 0.35f * std::min(1.0f, static_cast<float>(i - 20) / 15.0f);
    samples[i].left.y() -= drop;
    samples[i].right.y() -= drop;
  }
  ReconstructionOptions sinking = options_;
  sinking.feet_above_floor = false;
  const BodyModel& body = setup_.database->body();
  const BodyLandmarks& l = setup_.rig.topology.landmarks;
  const float ground = setup_.database->planted_ankle_height();
  auto lowest_ankle = [&](const ReconstructionOptions& options) {
    auto frames = ReconstructOffline(setup_.database, options, samples);
    EXPECT_TRUE(frames.ok()) << frames.status();
    float lowest = 1e9f;
    std::vector<Eigen::Quaternionf> rotations;
    std::vector<Eigen::Vector3f> positions;
    for (const ReconstructedFrame& frame : frames.ok() ? *frames : std::vector<ReconstructedFrame>{}) {
      body.WorldTransforms(frame.pose, &rotations, &positions);
      lowest = std::min({lowest, positions[l.left_ankle].y(), positions[l.right_ankle].y()});
    }
    return lowest;
  };
  EXPECT_LT(lowest_ankle(sinking), ground - 0.05f);
  EXPECT_GE(lowest_ankle(options_), ground - 0.001f);
}

// A tracker that drifted (or a floor declared too high) puts the left wrist 15 cm under the ground
// for a second: the body's hand stops at the floor and the frames say the input is out of reach.
// Every mode.
TEST_F(ReconstructionSessionTest, InputUnderTheFloorHoldsTheHandAtTheFloorAndIsOutOfReach) {
  auto samples = testing::WristSamplesOf(setup_);
  ASSERT_GT(samples.size(), 70u);
  const float start = samples[20].left.y();
  auto depth_at = [&](size_t i) {  // down over half a second, a second under, up over half a second
    const float down = std::clamp((static_cast<float>(i) - 20.0f) / 15.0f, 0.0f, 1.0f);
    const float up = std::clamp((65.0f - static_cast<float>(i)) / 15.0f, 0.0f, 1.0f);
    return std::min(down, up) * (start + 0.15f);
  };
  for (size_t i = 0; i < samples.size(); ++i) samples[i].left.y() -= depth_at(i);
  const BodyModel& body = setup_.database->body();
  const BodyLandmarks& l = setup_.rig.topology.landmarks;
  for (const int lag : {-1, 0, 5}) {
    ReconstructionOptions options = options_;
    if (lag >= 0) {
      options.mode = StreamMode::kFixedLag;
      options.lag = lag;
    }
    auto frames = ReconstructOffline(setup_.database, options, samples);
    ASSERT_TRUE(frames.ok()) << frames.status();
    std::vector<Eigen::Quaternionf> rotations;
    std::vector<Eigen::Vector3f> positions;
    int flagged = 0, under = 0, out_of_reach = 0;
    for (const ReconstructedFrame& frame : *frames) {
      const auto& input = samples[frame.frame_in_segment];
      body.WorldTransforms(frame.pose, &rotations, &positions);
      EXPECT_GE(positions[l.left_wrist].y(), kLowestWristHeight - 0.002f) << "lag " << lag << " frame " << frame.index;
      if (input.left.y() < -0.05f) {  // well under: flagged whatever A2's smoothing did
        ++under;
        // (where the hand stops at the bottom, the jump detector may call it implausible first)
        EXPECT_TRUE(frame.hand_state[0] == TrackingState::kOutOfReach ||
                    frame.hand_state[0] == TrackingState::kImplausible)
            << "lag " << lag << " frame " << frame.index;
        out_of_reach += frame.hand_state[0] == TrackingState::kOutOfReach;
      }
      if (frame.frame_in_segment < 20 && frame.hand_state[0] != TrackingState::kTracked) ++flagged;
    }
    EXPECT_GE(under, 15) << "lag " << lag;
    EXPECT_GE(out_of_reach, under - 4) << "lag " << lag;
    EXPECT_EQ(flagged, 0) << "lag " << lag << ": the input before the drift flagged";
  }
}

// The setup's wrist samples with white noise of `sigma` metres per axis, as a tracker jitters.
std::vector<WristSample> JitteredSamples(const testing::SyntheticReconstructionSetup& setup, float sigma,
                                         unsigned seed) {
  auto samples = testing::WristSamplesOf(setup);
  std::mt19937 random(seed);
  std::normal_distribution<float> jitter(0.0f, sigma);
  for (WristSample& sample : samples) {
    for (Eigen::Vector3f* hand : {&sample.left, &sample.right})
      *hand += Eigen::Vector3f(jitter(random), jitter(random), jitter(random));
  }
  return samples;
}

// Mean over the first `joints` joints (all: -1) and frames [first, last) of |third difference of
// the joint's position| / dt³.
double MeanJerk(const BodyModel& body, const std::vector<ReconstructedFrame>& frames, int first, int last, double dt,
                int joints = -1) {
  std::vector<std::vector<Eigen::Vector3f>> positions(frames.size());
  std::vector<Eigen::Quaternionf> rotations;
  for (size_t i = 0; i < frames.size(); ++i) body.WorldTransforms(frames[i].pose, &rotations, &positions[i]);
  double sum = 0;
  long count = 0;
  for (int f = std::max(first, 3); f < last; ++f) {
    const size_t count_joints = joints < 0 ? positions[f].size() : static_cast<size_t>(joints);
    for (size_t j = 0; j < count_joints; ++j) {
      sum += (positions[f][j] - 3 * positions[f - 1][j] + 3 * positions[f - 2][j] - positions[f - 3][j]).norm();
      ++count;
    }
  }
  return sum / count / (dt * dt * dt);
}

// A phone's AR tracking jitters by centimetres: once a second of it reads as noise, the joint
// filter widens as for a lost hand, and the body moves more smoothly; a tracker's 5 mm jitter
// does not read as noise, and its output is as without the rule.
TEST_F(ReconstructionSessionTest, NoisyInputIsWeakInput) {
  auto jittered = [this](float sigma) { return JitteredSamples(setup_, sigma, 11); };
  ReconstructionOptions blind = options_;
  blind.noisy_input_metres = 0.0f;
  const BodyModel& body = setup_.database->body();
  const double dt = setup_.database->frame_time();
  const auto phone = jittered(0.04f);
  auto detected = ReconstructOffline(setup_.database, options_, phone);
  auto undetected = ReconstructOffline(setup_.database, blind, phone);
  ASSERT_TRUE(detected.ok() && undetected.ok());
  ASSERT_EQ(detected->size(), undetected->size());
  EXPECT_LT(MeanJerk(body, *detected, 35, static_cast<int>(detected->size()), dt),
            0.9 * MeanJerk(body, *undetected, 35, static_cast<int>(undetected->size()), dt));
  const auto tracker = jittered(0.005f);
  auto tracked = ReconstructOffline(setup_.database, options_, tracker);
  auto tracked_blind = ReconstructOffline(setup_.database, blind, tracker);
  ASSERT_TRUE(tracked.ok() && tracked_blind.ok());
  ASSERT_EQ(tracked->size(), tracked_blind->size());
  for (size_t f = 0; f < tracked->size(); ++f) {
    EXPECT_EQ((*tracked)[f].pose.root_position, (*tracked_blind)[f].pose.root_position) << "frame " << f;
  }
}

// Where the solved torso jerks more than `jittery_body_ratio` times as much as the input hands,
// the body's joint filter widens as for weak input, and the hands' targets do not (issues #22,
// #25): the trunk moves more smoothly, the hands stay where they were put. A ratio no body
// reaches changes nothing.
TEST_F(ReconstructionSessionTest, AJitteringBodyIsSmoothedAndItsHandsAreNot) {
  auto samples = JitteredSamples(setup_, 0.005f, 5);
  ReconstructionOptions off = options_, always = options_, never = options_;
  off.jittery_body_ratio = 0.0f;
  always.jittery_body_ratio = 1e-6f;  // every torso jerks more than that
  never.jittery_body_ratio = 1e6f;
  auto kept = ReconstructOffline(setup_.database, off, samples);
  auto smoothed = ReconstructOffline(setup_.database, always, samples);
  auto unreached = ReconstructOffline(setup_.database, never, samples);
  ASSERT_TRUE(kept.ok() && smoothed.ok() && unreached.ok());
  ASSERT_EQ(kept->size(), smoothed->size());
  ASSERT_EQ(kept->size(), unreached->size());
  const BodyModel& body = setup_.database->body();
  const BodyLandmarks& l = body.rig().topology.landmarks;
  const double dt = setup_.database->frame_time();
  const int end = static_cast<int>(kept->size());
  const int trunk = static_cast<int>(l.head) + 1;  // Hips, Spine, Chest, Neck, Head
  // From the frame the jitter is first read (its means span weak_input_hold_seconds).
  const int first = 4 + static_cast<int>(std::ceil(options_.weak_input_hold_seconds / dt));
  EXPECT_LT(MeanJerk(body, *smoothed, first, end, dt, trunk), 0.95 * MeanJerk(body, *kept, first, end, dt, trunk));
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> smoothed_at, kept_at;
  double moved = 0, hands_moved = 0;
  for (int f = 0; f < end; ++f) {
    EXPECT_EQ((*unreached)[f].pose.root_position, (*kept)[f].pose.root_position) << "frame " << f;
    body.WorldTransforms((*smoothed)[f].pose, &rotations, &smoothed_at);
    body.WorldTransforms((*kept)[f].pose, &rotations, &kept_at);
    moved = std::max(moved, static_cast<double>((smoothed_at[l.head] - kept_at[l.head]).norm()));
    for (int wrist : {l.left_wrist, l.right_wrist})
      hands_moved = std::max(hands_moved, static_cast<double>((smoothed_at[wrist] - kept_at[wrist]).norm()));
  }
  EXPECT_GT(moved, 1e-3);  // the head moved by the wider filter
  // The hands stayed on their targets: within 1 cm, where the smoother trunk left a target a
  // little beyond the arm's reach (the whole clip's sharp filter, widened to σ = 2, cuts at 2 Hz:
  // 6.7 mm here, 2.3 with the Gaussian).
  EXPECT_LT(hands_moved, 0.01);
}

TEST_F(ReconstructionSessionTest, WhileAHandIsLostTheJointFilterLeansOnTheMotionAround) {
  // The left hand lost for 1.2 s from frame 20, the input with a tracker's 5 mm jitter: the output
  // moves more smoothly there than with the joint filter kept at its usual width, and not a bit
  // differently before (issue #25).
  auto samples = JitteredSamples(setup_, 0.005f, 7);
  for (int i = 20; i < 56; ++i) {
    samples[i].tracked[0] = false;
    samples[i].left = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
  }
  options_.jittery_body_ratio = 0.0f;  // the weak input's widening alone
  ReconstructionOptions narrow = options_;
  narrow.weak_input_joint_smoothing_sigma = narrow.joint_smoothing_sigma;
  auto widened = ReconstructOffline(setup_.database, options_, samples);
  auto kept = ReconstructOffline(setup_.database, narrow, samples);
  ASSERT_TRUE(widened.ok()) << widened.status();
  ASSERT_TRUE(kept.ok()) << kept.status();
  ASSERT_EQ(widened->size(), kept->size());
  const BodyModel& body = setup_.database->body();
  const double dt = setup_.database->frame_time();
  // Frames 20..70: the loss, the returning hand's cross-fade and the filter's way back. The trunk
  // (pelvis to head, the filter's alone) calms most; the limbs less, as IK puts them on their
  // targets (a knee on a planted ankle moves more when the hip above it is smoothed).
  const int trunk = static_cast<int>(body.rig().topology.landmarks.head) + 1;  // Hips, Spine, Chest, Neck, Head
  const double jerk_widened = MeanJerk(body, *widened, 20, 71, dt), jerk_kept = MeanJerk(body, *kept, 20, 71, dt);
  EXPECT_LT(jerk_widened, jerk_kept);
  EXPECT_LT(MeanJerk(body, *widened, 20, 71, dt, trunk), 0.95 * MeanJerk(body, *kept, 20, 71, dt, trunk));
  for (int f = 0; f < 20; ++f) {
    for (size_t j = 0; j < (*widened)[f].pose.rotations.size(); ++j) {
      EXPECT_TRUE((*widened)[f].pose.rotations[j].isApprox((*kept)[f].pose.rotations[j], 0.0f)) << "frame " << f;
    }
  }
  // Where the input is good throughout, the filter never widens.
  auto clean = ReconstructOffline(setup_.database, options_, testing::WristSamplesOf(setup_));
  auto clean_kept = ReconstructOffline(setup_.database, narrow, testing::WristSamplesOf(setup_));
  ASSERT_TRUE(clean.ok() && clean_kept.ok());
  for (size_t f = 0; f < clean->size(); ++f) {
    EXPECT_EQ((*clean)[f].pose.root_position, (*clean_kept)[f].pose.root_position) << "frame " << f;
  }
}

// Issue #24: with a slice deadline a window's frames are solved a few per call; Continue (or the
// next Push, or Finish) takes the rest in order, and the frames are those of one call.
TEST_F(ReconstructionSessionTest, AWindowSolvedASliceAtATimeGivesTheSameFrames) {
  options_.window = 20;
  auto samples = testing::WristSamplesOf(setup_);
  for (size_t i = 50; i < samples.size(); ++i) samples[i].time += 3.0;  // a second segment
  auto offline = ReconstructOffline(setup_.database, options_, samples);
  ASSERT_TRUE(offline.ok());
  // A slice of one frame: its deadline passed, or a server's other work waiting at every frame.
  for (const bool by_yield : {false, true}) {
    SCOPED_TRACE(by_yield ? "ended by yield" : "ended by deadline");
    auto session = ReconstructionSession::Create(setup_.database, options_);
    ASSERT_TRUE(session.ok());
    if (by_yield) {
      (*session)->SetSliceYield([] { return true; });
    } else {
      (*session)->SetSliceDeadline(std::chrono::steady_clock::time_point::min());
    }
    std::vector<ReconstructedFrame> sliced;
    int pending_after_push = 0, continues = 0;
    for (size_t i = 0; i < samples.size(); ++i) {
      ASSERT_TRUE((*session)->Push(samples[i], &sliced).ok());
      pending_after_push += (*session)->has_pending_frames();
      // Some samples leave what is pending to the next Push, which solves it first.
      while (i % 3 == 0 && (*session)->has_pending_frames()) {
        ASSERT_TRUE((*session)->Continue(&sliced).ok());
        ++continues;
      }
    }
    EXPECT_GT(pending_after_push, 2);
    EXPECT_GE(continues, 19);  // the first window but its first frame, a frame a call
    ASSERT_TRUE((*session)->Finish(&sliced).ok());
    EXPECT_TRUE((*session)->has_pending_frames());  // the last window's frames, one a call
    while ((*session)->has_pending_frames()) ASSERT_TRUE((*session)->Finish(&sliced).ok());
    ASSERT_EQ(sliced.size(), offline->size());
    for (size_t f = 0; f < sliced.size(); ++f) {
      EXPECT_EQ(sliced[f].index, (*offline)[f].index);
      EXPECT_EQ(sliced[f].segment, (*offline)[f].segment);
      EXPECT_EQ(sliced[f].pelvis_position, (*offline)[f].pelvis_position);
      for (size_t j = 0; j < sliced[f].pose.rotations.size(); ++j)
        EXPECT_EQ(sliced[f].pose.rotations[j].coeffs(), (*offline)[f].pose.rotations[j].coeffs());
    }
  }
}

// A tracker that did not update sends its last positions again (wrist_resampler.h): the hands
// neither stop nor catch up, at any lag, and every frame still comes out.
TEST_F(ReconstructionSessionTest, ATrackerThatDidNotUpdateIsNeitherAStopNorACatchUp) {
  const auto samples = testing::WristSamplesOf(setup_);
  std::vector<WristSample> stalled = samples;
  for (size_t i = 1; i + 1 < stalled.size(); i += 2) {  // every other sample repeats the one before
    stalled[i].left = stalled[i - 1].left;
    stalled[i].right = stalled[i - 1].right;
  }
  for (int lag : {0, 5}) {
    options_.mode = StreamMode::kFixedLag;
    options_.lag = lag;
    auto clean = ReconstructOffline(setup_.database, options_, samples);
    auto repeated = ReconstructOffline(setup_.database, options_, stalled);
    ASSERT_TRUE(clean.ok() && repeated.ok());
    ASSERT_EQ(repeated->size(), samples.size()) << "lag " << lag;
    double wrist_gap = 0;
    for (size_t f = 0; f < samples.size(); ++f) {
      for (int side = 0; side < 2; ++side) wrist_gap += ((*repeated)[f].wrists[side] - (*clean)[f].wrists[side]).norm();
      EXPECT_FALSE((*repeated)[f].implausible_input()) << "lag " << lag << " frame " << f;
    }
    // Read as input, the repeats put the smoothed wrists 2 cm from the clean input's on average
    // and are flagged implausible; interpolated across, they are within 2 mm (the path's curve).
    EXPECT_LT(wrist_gap / (2.0 * samples.size()), 0.003) << "lag " << lag;
  }
}

TEST_F(ReconstructionSessionTest, ALongGapEndsTheSegmentAndInputAtAnyRateIsResampled) {
  auto samples = testing::WristSamplesOf(setup_);
  // Second half 3 s later (beyond max_gap_seconds): two segments. Then thin the input to 20 Hz-ish
  // by dropping samples.
  for (size_t i = 40; i < samples.size(); ++i) samples[i].time += 3.0;
  std::vector<WristSample> thinned;
  for (size_t i = 0; i < samples.size(); ++i) {
    if (i % 3 != 1) thinned.push_back(samples[i]);
  }
  auto frames = ReconstructOffline(setup_.database, options_, thinned);
  ASSERT_TRUE(frames.ok()) << frames.status();
  int first = 0, second = 0;
  for (const ReconstructedFrame& frame : *frames) (frame.segment == 0 ? first : second)++;
  EXPECT_EQ(frames->front().time, samples.front().time);
  EXPECT_GE(first, 38);
  EXPECT_GE(second, 33);
  EXPECT_EQ(second, static_cast<int>(frames->back().frame_in_segment) + 1);
}

TEST_F(ReconstructionSessionTest, BaselinesRunThroughTheSamePipeline) {
  for (ReconstructionMethod method : {ReconstructionMethod::kNearestNeighbour, ReconstructionMethod::kWristsOnly}) {
    options_.method = method;
    auto frames = ReconstructOffline(setup_.database, options_, testing::WristSamplesOf(setup_));
    ASSERT_TRUE(frames.ok()) << frames.status();
    EXPECT_EQ(frames->size(), 75u);
    EXPECT_LT(Mpjpe(*frames), 0.10);
  }
}

TEST_F(ReconstructionSessionTest, RefusesBadOptions) {
  ReconstructionOptions bad = options_;
  bad.ankle_candidates = 0;
  EXPECT_EQ(ReconstructionSession::Create(setup_.database, bad).status().code(), absl::StatusCode::kInvalidArgument);
  bad = options_;
  bad.weak_input_joint_smoothing_sigma = 31;  // a kernel of 187 frames per emitted frame
  EXPECT_EQ(ReconstructionSession::Create(setup_.database, bad).status().code(), absl::StatusCode::kInvalidArgument);
  bad = options_;
  bad.lag = -1;
  EXPECT_EQ(ReconstructionSession::Create(setup_.database, bad).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(ReconstructionSession::Create(nullptr, options_).status().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace mocap
