// A body reaches further by leaning (motion/reconstruct/reach_lean.h): input within an arm's
// reach changes nothing; input beyond it turns the torso at the lowest spine joint until the
// shoulder is within an arm of it, never further than max_angle, and the pelvis and legs stay.
// Where the turn is not enough the whole body shifts towards the input, at most max_shift, no
// faster than max_shift_speed, and back when the input comes within reach again.
#include "motion/reconstruct/reach_lean.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "tests/support/synthetic_database.h"

namespace mocap {
namespace {

class ReachLeanTest : public ::testing::Test {
 protected:
  void SetUp() override {
    setup_ = &testing::SharedSyntheticReconstructionSetup();
    const BodyModel& body = setup_->database->body();
    pose_.rotations.assign(body.skeleton().num_joints(), Eigen::Quaternionf::Identity());
    pose_.root_position = Eigen::Vector3f(0.3f, 1.0f, -0.2f);  // the body's floor joints ~0.5 m over the ground
    landmarks_ = setup_->database->rig().topology.landmarks;
  }
  const BodyModel& body() const { return setup_->database->body(); }
  std::vector<Eigen::Vector3f> Positions(const BodyPose& pose) const {
    std::vector<Eigen::Quaternionf> rotations;
    std::vector<Eigen::Vector3f> positions;
    body().WorldTransforms(pose, &rotations, &positions);
    return positions;
  }
  // The joint the arm IK turns from (the wrist's grandparent) and the arm's length from it.
  std::pair<int, float> Arm(int wrist) const {
    const std::vector<Eigen::Vector3f> p = Positions(pose_);
    const int elbow = body().skeleton().parent(wrist), shoulder = body().skeleton().parent(elbow);
    return {shoulder, (p[elbow] - p[shoulder]).norm() + (p[wrist] - p[elbow]).norm()};
  }

  const testing::SyntheticReconstructionSetup* setup_ = nullptr;
  BodyPose pose_;
  BodyLandmarks landmarks_;
};

TEST_F(ReachLeanTest, InputWithinReachChangesNothing) {
  ReachLean lean(body().skeleton(), landmarks_);
  ASSERT_GE(lean.pivot(), 0);
  const std::vector<Eigen::Vector3f> p = Positions(pose_);
  BodyPose pose = pose_;
  // Each wrist moved a third and a tenth of the way towards its shoulder (the rest pose's arms
  // are straight).
  const int left = Arm(landmarks_.left_wrist).first, right = Arm(landmarks_.right_wrist).first;
  const std::array<Eigen::Vector3f, 2> targets{
      p[landmarks_.left_wrist] + 0.3f * (p[left] - p[landmarks_.left_wrist]),
      p[landmarks_.right_wrist] + 0.1f * (p[right] - p[landmarks_.right_wrist])};
  EXPECT_EQ(lean.Apply(body(), targets, {true, true}, &pose), 0.0f);
  for (size_t j = 0; j < pose.rotations.size(); ++j) EXPECT_TRUE(pose.rotations[j].isApprox(pose_.rotations[j]));
}

TEST_F(ReachLeanTest, InputBeyondReachTurnsTheTorsoUntilTheShoulderIsWithinAnArm) {
  ReachLean lean(body().skeleton(), landmarks_);
  const auto [shoulder, arm] = Arm(landmarks_.left_wrist);
  const std::vector<Eigen::Vector3f> before = Positions(pose_);
  // 12 cm beyond the straight arm, forward and down from the shoulder.
  const Eigen::Vector3f direction = Eigen::Vector3f(0.2f, -0.6f, 1.0f).normalized();
  const Eigen::Vector3f target = before[shoulder] + (arm + 0.12f) * direction;
  BodyPose pose = pose_;
  const float angle = lean.Apply(body(), {target, before[landmarks_.right_wrist]}, {true, false}, &pose);
  EXPECT_GT(angle, 0.0f);
  EXPECT_LE(angle, ReachLeanOptions{}.max_angle + 1e-5f);
  const std::vector<Eigen::Vector3f> after = Positions(pose);
  EXPECT_LE((target - after[shoulder]).norm(), arm + 0.005f);
  // The pelvis and the legs stay where they were.
  for (int j : {landmarks_.pelvis, landmarks_.left_ankle, landmarks_.right_ankle, landmarks_.left_knee}) {
    if (j >= 0) {
      EXPECT_LT((after[j] - before[j]).norm(), 1e-5f) << j;
    }
  }
  // A hand not asked to reach does not count: with the right hand's input well within its reach,
  // the left's far target is ignored.
  const int right = Arm(landmarks_.right_wrist).first;
  const Eigen::Vector3f within =
      before[landmarks_.right_wrist] + 0.3f * (before[right] - before[landmarks_.right_wrist]);
  BodyPose untouched = pose_;
  EXPECT_EQ(lean.Apply(body(), {target, within}, {false, true}, &untouched), 0.0f);
  // Just short of the arm's length (a relaxed arm hangs straight): no lean.
  const Eigen::Vector3f near = before[shoulder] + (arm - 0.01f) * direction;
  BodyPose straight = pose_;
  EXPECT_EQ(lean.Apply(body(), {near, within}, {true, false}, &straight), 0.0f);
}

TEST_F(ReachLeanTest, ATargetFarBeyondReachTurnsNoFurtherThanMaxAngle) {
  ReachLean lean(body().skeleton(), landmarks_, {.max_angle = 0.3f});
  const auto [shoulder, arm] = Arm(landmarks_.left_wrist);
  const std::vector<Eigen::Vector3f> before = Positions(pose_);
  const Eigen::Vector3f target = before[shoulder] + Eigen::Vector3f(0.0f, -0.3f, arm + 1.5f);
  BodyPose pose = pose_;
  EXPECT_NEAR(lean.Apply(body(), {target, target}, {true, true}, &pose), 0.3f, 1e-4f);
  ReachLean off(body().skeleton(), landmarks_, {.max_angle = 0.0f});
  BodyPose still = pose_;
  EXPECT_EQ(off.Apply(body(), {target, target}, {true, true}, &still), 0.0f);
}

// Streamed, the turn follows the least turn through an exponential filter: a target that appears
// beyond reach is leant towards by dt / (τ + dt) of the way each frame, the whole way once
// settled, and at once with τ = 0; when the target comes back within reach the turn fades.
TEST_F(ReachLeanTest, TheStreamedTurnFollowsTheLeastTurnThroughItsFilter) {
  const auto [shoulder, arm] = Arm(landmarks_.left_wrist);
  const std::vector<Eigen::Vector3f> before = Positions(pose_);
  const Eigen::Vector3f far = before[shoulder] + Eigen::Vector3f(0.0f, -0.3f, arm + 0.1f);
  const std::array<Eigen::Vector3f, 2> targets{far, before[landmarks_.right_wrist]};
  const double frame_time = 1.0 / 30.0;
  ReachLean once(body().skeleton(), landmarks_, {.turn_smoothing_seconds = 0.0f});
  BodyPose least_pose = pose_;
  const float least = once.Apply(body(), targets, {true, false}, &least_pose);
  ASSERT_GT(least, 0.05f);
  Eigen::Vector3f unfiltered = Eigen::Vector3f::Zero();
  BodyPose at_once = pose_;
  EXPECT_NEAR(once.Apply(body(), targets, {true, false}, frame_time, &unfiltered, &at_once), least, 1e-5f);

  ReachLean lean(body().skeleton(), landmarks_, {.turn_smoothing_seconds = 0.1f});
  const float follow = static_cast<float>(frame_time / (0.1 + frame_time));
  Eigen::Vector3f state = Eigen::Vector3f::Zero();
  BodyPose pose = pose_;
  EXPECT_NEAR(lean.Apply(body(), targets, {true, false}, frame_time, &state, &pose), follow * least, 1e-4f);
  float angle = 0.0f;
  for (int frame = 1; frame < 60; ++frame) {
    pose = pose_;
    const float next = lean.Apply(body(), targets, {true, false}, frame_time, &state, &pose);
    EXPECT_GE(next, angle - 1e-5f) << frame;
    angle = next;
  }
  EXPECT_NEAR(angle, least, 1e-3f);
  const std::vector<Eigen::Vector3f> after = Positions(pose);
  EXPECT_LT((after[shoulder] - Positions(least_pose)[shoulder]).norm(), 2e-3f)
      << "settled: where the least turn puts it";
  pose = pose_;
  const float fading = lean.Apply(body(), {before[landmarks_.left_wrist], before[landmarks_.right_wrist]},
                                  {true, false}, frame_time, &state, &pose);
  EXPECT_NEAR(fading, (1.0f - follow) * least, 1e-3f) << "within reach again: the turn fades";
}

TEST_F(ReachLeanTest, WhatTheTurnCannotReachTheBodyStepsTowardsNoFasterThanItsSpeed) {
  const ReachLeanOptions options{.max_angle = 0.2f, .max_shift = 0.3f, .max_shift_speed = 0.5f};
  ReachLean lean(body().skeleton(), landmarks_, options);
  const auto [shoulder, arm] = Arm(landmarks_.left_wrist);
  const std::vector<Eigen::Vector3f> before = Positions(pose_);
  // 20 cm beyond the straight arm, down and forward: more than a turn of 0.2 rad gives.
  const Eigen::Vector3f direction = Eigen::Vector3f(0.1f, -0.8f, 0.6f).normalized();
  const Eigen::Vector3f target = before[shoulder] + (arm + 0.2f) * direction;
  const std::array<Eigen::Vector3f, 2> targets{target, before[landmarks_.right_wrist]};
  const double frame_time = 1.0 / 30.0;
  const float step = options.max_shift_speed * static_cast<float>(frame_time);
  Eigen::Vector3f state = Eigen::Vector3f::Zero();
  Eigen::Vector3f previous = state;
  BodyPose pose;
  for (int frame = 0; frame < 30; ++frame) {
    pose = pose_;
    lean.Apply(body(), targets, {true, false}, &pose);
    const Eigen::Vector3f shift = lean.Shift(body(), targets, {true, false}, frame_time, &state, &pose);
    EXPECT_TRUE(shift.isApprox(state));
    EXPECT_LE((shift - previous).norm(), step + 1e-5f) << frame;  // no faster than its speed
    EXPECT_LE(shift.norm(), options.max_shift + 1e-5f);
    EXPECT_TRUE(pose.root_position.isApprox(pose_.root_position + shift, 1e-5f));
    previous = shift;
  }
  // Settled: the shoulder within an arm of the input, by the least shift (the arm straight).
  const std::vector<Eigen::Vector3f> after = Positions(pose);
  EXPECT_LE((target - after[shoulder]).norm(), arm + 0.005f);
  EXPECT_GE((target - after[shoulder]).norm(), arm - 0.01f);
  EXPECT_GT(state.norm(), 0.05f);
  EXPECT_LT(state.y(), 0.0f);  // down towards the input: a crouch
  // Input back within reach: the body returns at the same speed, to where it was.
  const std::array<Eigen::Vector3f, 2> near{before[landmarks_.left_wrist] + 0.2f * (before[shoulder] - target),
                                            before[landmarks_.right_wrist]};
  for (int frame = 0; frame < 30; ++frame) {
    pose = pose_;
    lean.Apply(body(), near, {true, false}, &pose);
    const Eigen::Vector3f shift = lean.Shift(body(), near, {true, false}, frame_time, &state, &pose);
    EXPECT_LE((shift - previous).norm(), step + 1e-5f) << frame;
    previous = shift;
  }
  EXPECT_LT(state.norm(), 1e-6f);
  EXPECT_TRUE(pose.root_position.isApprox(pose_.root_position));
}

TEST(PartWithinLimitTest, CutsAChangeToWhatTheBoundLeavesAndNeverSpeedsUpABrakingStep) {
  const Eigen::Vector3f step(0.03f, 0.0f, 0.0f);
  // Room for all of it, none at all, and part of it along the step.
  EXPECT_FLOAT_EQ(PartWithinLimit(step, Eigen::Vector3f(0.005f, 0.0f, 0.0f), 0.04f), 1.0f);
  EXPECT_FLOAT_EQ(PartWithinLimit(step, Eigen::Vector3f(0.01f, 0.0f, 0.0f), 0.03f), 0.0f);
  EXPECT_NEAR(PartWithinLimit(step, Eigen::Vector3f(0.02f, 0.0f, 0.0f), 0.04f), 0.5f, 1e-5f);
  // Across the step: |(0.03, 0.04α)| = 0.04 at α = √(0.0007) / 0.04.
  EXPECT_NEAR(PartWithinLimit(step, Eigen::Vector3f(0.0f, 0.04f, 0.0f), 0.04f), std::sqrt(0.0007f) / 0.04f, 1e-4f);
  // Against the step: slows the body, always allowed.
  EXPECT_FLOAT_EQ(PartWithinLimit(step, Eigen::Vector3f(-0.01f, 0.0f, 0.0f), 0.03f), 1.0f);
  // A step already past the limit (a body braking as hard as it can): no faster than it is.
  EXPECT_FLOAT_EQ(PartWithinLimit(step, Eigen::Vector3f(0.01f, 0.0f, 0.0f), 0.02f), 0.0f);
  EXPECT_FLOAT_EQ(PartWithinLimit(step, Eigen::Vector3f(-0.01f, 0.0f, 0.0f), 0.02f), 1.0f);
  // No bound, no change.
  EXPECT_FLOAT_EQ(PartWithinLimit(step, Eigen::Vector3f(0.5f, 0.0f, 0.0f), std::numeric_limits<float>::infinity()),
                  1.0f);
  EXPECT_FLOAT_EQ(PartWithinLimit(step, Eigen::Vector3f::Zero(), 0.0f), 1.0f);
}

// The shift moves on top of a body the motion guard already moves: together no faster than the
// guard's bound (issue #22: the two added up to 1.2 × the allowed pelvis speed on bows at lag 0).
TEST_F(ReachLeanTest, TheShiftAndTheBodyUnderItTogetherStayWithinTheSpeedBound) {
  const ReachLeanOptions options{.max_angle = 0.0f, .max_shift = 0.3f, .max_shift_speed = 0.5f};
  ReachLean lean(body().skeleton(), landmarks_, options);
  const auto [shoulder, arm] = Arm(landmarks_.left_wrist);
  const std::vector<Eigen::Vector3f> before = Positions(pose_);
  const Eigen::Vector3f forward(0.0f, 0.0f, 1.0f);
  const std::array<Eigen::Vector3f, 2> targets{before[shoulder] + (arm + 0.2f) * forward,
                                               before[landmarks_.right_wrist]};
  const double frame_time = 1.0 / 30.0;
  const float dt = static_cast<float>(frame_time);
  const float bound = 1.0f;  // m/s
  auto run = [&](const Eigen::Vector3f& body_velocity) {
    Eigen::Vector3f state = Eigen::Vector3f::Zero();
    Eigen::Vector3f previous = state;
    float fastest = 0.0f;
    const BodyMotion moving{body_velocity, bound};
    for (int frame = 0; frame < 30; ++frame) {
      BodyPose pose = pose_;
      const Eigen::Vector3f shift = lean.Shift(body(), targets, {true, false}, frame_time, &state, &pose, &moving);
      fastest = std::max(fastest, (body_velocity + (shift - previous) / dt).norm());
      previous = shift;
    }
    return std::pair{fastest, state};
  };
  // The body already goes towards the input at 0.9 m/s: the shift adds at most 0.1 m/s.
  const auto [along_fastest, along_state] = run(0.9f * forward);
  EXPECT_LE(along_fastest, bound + 1e-4f);
  EXPECT_NEAR(along_state.z(), 0.1f * 30 * dt, 2e-3f);
  // At the bound, no shift; going away from the input, the shift comes at its own speed.
  EXPECT_LT(run(bound * forward).second.norm(), 1e-6f);
  const auto [away_fastest, away_state] = run(-0.8f * forward);
  EXPECT_LE(away_fastest, 0.8f + 1e-4f);
  EXPECT_GT(away_state.z(), 0.19f);
}

// A body already low (a dancer down on the floor) reaching for input further down: the shift
// takes it no lower than its floor joints allow, and a shift made frames ago gives way, no faster
// than floor_give_way_speed, when the body under it comes lower.
TEST_F(ReachLeanTest, TheShiftTakesTheBodyNoLowerThanTheFloor) {
  const ReachLeanOptions options{
      .max_angle = 0.0f, .max_shift = 0.3f, .max_shift_speed = 0.5f, .floor_give_way_speed = 0.6f};
  ReachLean lean(body().skeleton(), landmarks_, options);
  BodyPose low = pose_;
  low.root_position.y() -= body().FloorClearance(Positions(low)) - 0.05f;  // 5 cm to spare
  ASSERT_NEAR(body().FloorClearance(Positions(low)), 0.05f, 1e-4f);
  const auto [shoulder, arm] = Arm(landmarks_.left_wrist);
  const std::vector<Eigen::Vector3f> before = Positions(low);
  const Eigen::Vector3f target = before[shoulder] + (arm + 0.3f) * Eigen::Vector3f(0.0f, -0.8f, 0.6f).normalized();
  const std::array<Eigen::Vector3f, 2> targets{target, before[landmarks_.right_wrist]};
  const double frame_time = 1.0 / 30.0;
  Eigen::Vector3f state = Eigen::Vector3f::Zero();
  BodyPose pose;
  for (int frame = 0; frame < 30; ++frame) {
    pose = low;
    const Eigen::Vector3f shift = lean.Shift(body(), targets, {true, false}, frame_time, &state, &pose);
    EXPECT_GE(shift.y(), -0.05f - 1e-5f) << frame;
    EXPECT_GE(body().FloorClearance(Positions(pose)), -1e-5f) << frame;
  }
  EXPECT_NEAR(state.y(), -0.05f, 1e-4f);  // down as far as it goes
  EXPECT_GT(state.z(), 0.05f);            // and forward, towards the input
  // The body under the shift comes 6 cm lower (1 cm under its floor height): the shift gives way
  // by at least floor_give_way_speed a frame, and is gone in a few frames.
  BodyPose lower = low;
  lower.root_position.y() -= 0.06f;
  float previous = state.y();
  for (int frame = 0; frame < 4; ++frame) {
    pose = lower;
    const Eigen::Vector3f shift = lean.Shift(body(), targets, {true, false}, frame_time, &state, &pose);
    EXPECT_LE(shift.y(), 1e-5f) << frame;  // gives way, lifts nothing
    if (frame == 0) {
      EXPECT_LT(shift.y(), -0.005f);  // not at once
      EXPECT_GE(shift.y(), previous + options.floor_give_way_speed * frame_time - 1e-5f);
    }
    previous = shift.y();
  }
  EXPECT_NEAR(state.y(), 0.0f, 1e-5f);
}

TEST_F(ReachLeanTest, AShiftNeverGoesFurtherThanMaxShiftAndIsOffAtZero) {
  const auto [shoulder, arm] = Arm(landmarks_.left_wrist);
  const std::vector<Eigen::Vector3f> before = Positions(pose_);
  const Eigen::Vector3f target = before[shoulder] + Eigen::Vector3f(0.0f, 0.0f, arm + 2.0f);
  const std::array<Eigen::Vector3f, 2> targets{target, target};
  for (const float max_shift : {0.0f, 0.15f}) {
    ReachLean lean(body().skeleton(), landmarks_,
                   {.max_angle = 0.0f, .max_shift = max_shift, .max_shift_speed = 100.0f});
    Eigen::Vector3f state = Eigen::Vector3f::Zero();
    BodyPose pose = pose_;
    const Eigen::Vector3f shift = lean.Shift(body(), targets, {true, true}, 1.0 / 30.0, &state, &pose);
    EXPECT_NEAR(shift.norm(), max_shift, 1e-4f);
    EXPECT_GT(shift.z() + (max_shift == 0.0f ? 1.0f : 0.0f), 0.0f);  // towards the input
  }
}

// The collar bones move first: input a few centimetres beyond the straight arm turns the
// collar until the shoulder is within an arm of it, and nothing else moves; input far beyond
// turns it by max_collar_angle towards it and leaves the rest to the lean; within reach, or with
// max_collar_angle = 0, nothing changes.
TEST_F(ReachLeanTest, TheCollarBoneBringsTheShoulderWithinReachFirst) {
  ReachLean lean(body().skeleton(), landmarks_);
  const auto [shoulder, arm] = Arm(landmarks_.left_wrist);
  const int collar = body().skeleton().parent(shoulder);
  const std::vector<Eigen::Vector3f> before = Positions(pose_);
  // 3 cm beyond the straight arm, down and a little forward from the shoulder.
  const Eigen::Vector3f direction = Eigen::Vector3f(0.1f, -1.0f, 0.3f).normalized();
  const Eigen::Vector3f target = before[shoulder] + (arm + 0.03f) * direction;
  BodyPose pose = pose_;
  const float angle = lean.MoveCollars(body(), {target, before[landmarks_.right_wrist]}, {true, true}, &pose);
  EXPECT_GT(angle, 0.0f);
  EXPECT_LT(angle, ReachLeanOptions{}.max_collar_angle);
  std::vector<Eigen::Vector3f> after = Positions(pose);
  // The least turn: just within reach (a millimetre inside, so that the lean after it does not
  // count the hand by rounding).
  EXPECT_LE((target - after[shoulder]).norm(), arm);
  EXPECT_GE((target - after[shoulder]).norm(), arm - 2e-3f);
  for (int j = 0; j < body().skeleton().num_joints(); ++j) {
    if (j == shoulder || body().skeleton().parent(j) < 0) continue;
    bool on_the_arm = false;
    for (int a = j; a >= 0; a = body().skeleton().parent(a)) on_the_arm = on_the_arm || a == shoulder;
    if (!on_the_arm) {
      EXPECT_LT((after[j] - before[j]).norm(), 1e-5f) << body().skeleton().joint(j).name;
    }
  }
  EXPECT_LT((after[collar] - before[collar]).norm(), 1e-6f) << "the collar turns about its own joint";
  // Far beyond: the collar turns by its whole range, towards the target.
  const Eigen::Vector3f far = before[shoulder] + (arm + 0.5f) * direction;
  pose = pose_;
  EXPECT_NEAR(lean.MoveCollars(body(), {far, far}, {true, false}, &pose), ReachLeanOptions{}.max_collar_angle, 1e-5f);
  after = Positions(pose);
  EXPECT_LT((far - after[shoulder]).norm(), (far - before[shoulder]).norm() - 0.01f);
  EXPECT_LT((after[landmarks_.right_wrist] - before[landmarks_.right_wrist]).norm(), 1e-5f) << "not asked to reach";
  // Within reach, or with the collars off: nothing.
  pose = pose_;
  EXPECT_EQ(lean.MoveCollars(body(), {before[shoulder] + (arm - 0.01f) * direction, far}, {true, false}, &pose), 0.0f);
  ReachLean off(body().skeleton(), landmarks_, {.max_collar_angle = 0.0f});
  EXPECT_EQ(off.MoveCollars(body(), {target, far}, {true, true}, &pose), 0.0f);
  for (size_t j = 0; j < pose.rotations.size(); ++j) EXPECT_TRUE(pose.rotations[j].isApprox(pose_.rotations[j]));
}

TEST_F(ReachLeanTest, NoSpineBetweenPelvisAndShouldersNoLean) {
  BodyLandmarks chest_as_pelvis = landmarks_;
  // The arms' common ancestor as the pelvis: nothing between them to turn.
  int chest = body().skeleton().parent(body().skeleton().parent(body().skeleton().parent(landmarks_.left_wrist)));
  while (chest >= 0) {
    int j = body().skeleton().parent(body().skeleton().parent(landmarks_.right_wrist));
    while (j >= 0 && j != chest) j = body().skeleton().parent(j);
    if (j == chest) break;
    chest = body().skeleton().parent(chest);
  }
  ASSERT_GE(chest, 0);
  chest_as_pelvis.pelvis = chest;
  EXPECT_LT(ReachLean(body().skeleton(), chest_as_pelvis).pivot(), 0);
}

}  // namespace
}  // namespace mocap
