// The BVH `mocap reconstruct` writes plays on the input's clock: a dropout the session could not
// bridge (a new segment, no frames for the gap) is filled between its two ends. The CLI's sources
// are built into the `mocap` executable only, so the function is compiled into this test.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "client/cli/reconstruction_timeline.cc"  // NOLINT(build/include): FillDropouts

namespace mocap {
namespace {

constexpr double kRate = 30.0;

// A two-joint body turning its second joint about Y by `degrees`, its root at (x, 0.9, 0).
v1::Frame MakeFrame(double time, int segment, float x, float degrees, float body_scale = 0.0f) {
  v1::Frame frame;
  frame.set_time(time);
  frame.set_segment(segment);
  frame.mutable_root_position()->set_x(x);
  frame.mutable_root_position()->set_y(0.9f);
  frame.mutable_pelvis_position()->set_x(x);
  frame.mutable_pelvis_position()->set_y(0.9f);
  frame.mutable_pelvis_rotation()->set_w(1.0f);
  frame.add_rotations()->set_w(1.0f);
  const Eigen::Quaternionf turn(
      Eigen::AngleAxisf(degrees * static_cast<float>(M_PI) / 180.0f, Eigen::Vector3f::UnitY()));
  v1::Quaternion* q = frame.add_rotations();
  q->set_w(turn.w());
  q->set_x(turn.x());
  q->set_y(turn.y());
  q->set_z(turn.z());
  frame.set_body_scale(body_scale);
  frame.set_left_hand_state(v1::TRACKING_STATE_TRACKED);
  frame.set_right_hand_state(v1::TRACKING_STATE_TRACKED);
  return frame;
}

float TurnDegrees(const v1::Frame& frame) {
  const v1::Quaternion& q = frame.rotations(1);
  return Eigen::Quaternionf(q.w(), q.x(), q.y(), q.z()).angularDistance(Eigen::Quaternionf::Identity()) * 180.0f /
         static_cast<float>(M_PI);
}

// Frames every 1/30 s from `from` for `count` frames; the clock's small wobble (a client's times)
// is not a gap.
void AppendSegment(std::vector<v1::Frame>* frames, double from, int count, int segment, float x, float degrees) {
  for (int k = 0; k < count; ++k) {
    const double wobble = (k % 2 ? 0.2 : -0.2) / kRate;
    frames->push_back(MakeFrame(from + k / kRate + (k > 0 ? wobble : 0.0), segment, x, degrees));
  }
}

TEST(ReconstructionTimelineTest, FramesWithoutAGapAreTheTimelineAsTheyAre) {
  std::vector<v1::Frame> frames;
  AppendSegment(&frames, 0.5, 90, 0, 0.0f, 0.0f);
  EXPECT_FALSE(cli::FillDropouts(frames, kRate).has_value());
  EXPECT_FALSE(cli::FillDropouts({}, kRate).has_value());
  EXPECT_FALSE(cli::FillDropouts(frames, 0.0).has_value());
  EXPECT_FALSE(cli::FillDropouts(frames, std::nan("")).has_value());
}

// A 3 s dropout between two segments: 89 frame times filled, the body moving at an even pace from
// where the first segment left it to where the second takes it up, each joint turning the shorter
// way; the made frames are the first segment's, lost in both hands, with no confidence of their
// own; the frames after the gap come at their own times.
TEST(ReconstructionTimelineTest, ADropoutTooLongToBridgeIsFilledFromOneEndToTheOther) {
  std::vector<v1::Frame> frames;
  AppendSegment(&frames, 0.0, 60, 0, 0.0f, 10.0f);
  const double resumed = frames.back().time() + 3.0;
  AppendSegment(&frames, resumed, 60, 1, 3.0f, 70.0f);
  frames[59].mutable_expected_error()->set_pelvis(0.05f);
  const std::optional<cli::FilledTimeline> timeline = cli::FillDropouts(frames, kRate);
  ASSERT_TRUE(timeline.has_value());
  EXPECT_EQ(timeline->gaps, 1);
  EXPECT_EQ(timeline->unfilled_gaps, 0);
  EXPECT_EQ(timeline->filled_frames, 89);
  ASSERT_EQ(timeline->frames.size(), frames.size() + 89);
  for (size_t f = 1; f < timeline->frames.size(); ++f) {
    const double step = timeline->frames[f].time() - timeline->frames[f - 1].time();
    EXPECT_GT(step, 0.5 / kRate) << "frame " << f;
    EXPECT_LT(step, 1.5 / kRate) << "frame " << f;
  }
  for (int k = 1; k <= 89; ++k) {
    const v1::Frame& made = timeline->frames[59 + k];
    const float s = k / 90.0f;
    EXPECT_NEAR(made.time(), frames[59].time() + k / kRate, 1e-9);
    EXPECT_NEAR(made.root_position().x(), 3.0f * s, 1e-5f) << k;
    EXPECT_NEAR(made.pelvis_position().x(), 3.0f * s, 1e-5f) << k;
    EXPECT_NEAR(made.root_position().y(), 0.9f, 1e-6f);
    EXPECT_NEAR(TurnDegrees(made), 10.0f + 60.0f * s, 1e-2f) << k;
    EXPECT_EQ(made.segment(), 0);
    EXPECT_EQ(made.left_hand_state(), v1::TRACKING_STATE_LOST);
    EXPECT_EQ(made.right_hand_state(), v1::TRACKING_STATE_LOST);
    EXPECT_FALSE(made.has_expected_error());
    EXPECT_EQ(made.rotations_size(), 2);
  }
  const v1::Frame& after = timeline->frames[59 + 90];
  EXPECT_EQ(after.segment(), 1);
  EXPECT_DOUBLE_EQ(after.time(), resumed);
  EXPECT_EQ(timeline->frames.back().time(), frames.back().time());
}

// A quaternion and its negation are one rotation: the fill goes the short way, not round.
TEST(ReconstructionTimelineTest, AFlippedQuaternionIsFilledTheShortWay) {
  std::vector<v1::Frame> frames{MakeFrame(0.0, 0, 0.0f, 20.0f), MakeFrame(1.0, 1, 0.0f, 40.0f)};
  v1::Quaternion* q = frames[1].mutable_rotations(1);
  q->set_w(-q->w());
  q->set_x(-q->x());
  q->set_y(-q->y());
  q->set_z(-q->z());
  const std::optional<cli::FilledTimeline> timeline = cli::FillDropouts(frames, kRate);
  ASSERT_TRUE(timeline.has_value());
  ASSERT_EQ(timeline->filled_frames, 29);
  for (const v1::Frame& frame : timeline->frames) {
    EXPECT_GE(TurnDegrees(frame), 20.0f - 1e-2f);
    EXPECT_LE(TurnDegrees(frame), 40.0f + 1e-2f);
  }
}

// A body that grew over the gap (a stream learning the performer's size) grows in the made frames
// too; an unset scale is 1.
TEST(ReconstructionTimelineTest, TheBodysScaleIsFilledWithItsUnsetValueReadAsOne) {
  std::vector<v1::Frame> frames{MakeFrame(0.0, 0, 0.0f, 0.0f, 0.0f), MakeFrame(2.0, 1, 0.0f, 0.0f, 1.2f)};
  const std::optional<cli::FilledTimeline> timeline = cli::FillDropouts(frames, kRate);
  ASSERT_TRUE(timeline.has_value());
  ASSERT_EQ(timeline->frames.size(), 61u);
  EXPECT_NEAR(timeline->frames[30].body_scale(), 1.1f, 1e-5f);
  for (size_t f = 1; f < timeline->frames.size(); ++f) {
    EXPECT_GT(cli::BodyScale(timeline->frames[f]), cli::BodyScale(timeline->frames[f - 1])) << f;
  }
}

// A clock that jumped (a session left open overnight, a timestamp glitch) is not made into hours
// of frames: the gap is counted and left as it is; the shorter gaps around it are still filled.
TEST(ReconstructionTimelineTest, AGapLongerThanTenMinutesIsLeftAndCounted) {
  std::vector<v1::Frame> frames;
  AppendSegment(&frames, 0.0, 10, 0, 0.0f, 0.0f);
  AppendSegment(&frames, frames.back().time() + kLongestFilledGapSeconds + 1.0, 10, 1, 1.0f, 0.0f);
  AppendSegment(&frames, frames.back().time() + 1e9, 10, 2, 2.0f, 0.0f);
  const std::optional<cli::FilledTimeline> only_long = cli::FillDropouts(frames, kRate);
  ASSERT_TRUE(only_long.has_value());
  EXPECT_EQ(only_long->gaps, 0);
  EXPECT_EQ(only_long->unfilled_gaps, 2);
  EXPECT_EQ(only_long->frames.size(), frames.size());
  AppendSegment(&frames, frames.back().time() + 1.0, 10, 3, 3.0f, 0.0f);
  const std::optional<cli::FilledTimeline> mixed = cli::FillDropouts(frames, kRate);
  ASSERT_TRUE(mixed.has_value());
  EXPECT_EQ(mixed->gaps, 1);
  EXPECT_EQ(mixed->unfilled_gaps, 2);
  EXPECT_EQ(mixed->filled_frames, 29);
}

}  // namespace
}  // namespace mocap
