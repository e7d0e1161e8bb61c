// Issue #22, "never teleport": the motion guard and the input-jump flag on their own, then the
// whole session on a synthetic walk whose wrists arrive as real trackers send them (a 20 cm step
// in one frame, 1 cm quantisation, repeated samples then a catch-up jump, 2–3 cm jitter, a 1 s
// gap), in every mode: the output pelvis never moves faster than max(2 × the clip's own fastest,
// its fastest + 1 m/s), and the jump frames — only they — are flagged.
#include "motion/reconstruct/motion_guard.h"

#include <cmath>
#include <functional>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "motion/reconstruct/plausibility.h"
#include "motion/reconstruct/reconstruction_session.h"
#include "tests/support/synthetic_database.h"

namespace mocap {
namespace {

constexpr double kDt = 1.0 / 30.0;

MotionLimits Limits() {
  MotionLimits limits;
  limits.pelvis_speed_max = 2.0f;
  limits.pelvis_acceleration_max = 10.0f;
  limits.pelvis_speed_beyond_hands_max = 1.0f;
  limits.wrist_speed_max = 4.0f;
  limits.wrist_acceleration_max = 60.0f;
  limits.ankle_speed_max = 5.0f;
  return limits;
}

// The database's bounds as they are, no margins, and no ease-in at a stream's start (tested on
// its own).
MotionGuardOptions Exact() {
  MotionGuardOptions options;
  options.speed_margin = options.acceleration_margin = options.beyond_hands_margin = 1.0f;
  options.input_speed_margin = options.input_acceleration_margin = 1.0f;
  options.start_ease_seconds = 0;
  options.start_rest_seconds = 0;
  return options;
}

// A planted foot stays while the leg can bend for the guard's offset and goes along by the rest:
// no step where the offset crosses the bound, the foot never further from the body's move than it.
TEST(MotionGuardTest, APlantedFootGoesAlongOnlyBeyondWhatTheLegGivesAndNeverSteps) {
  const float give = 0.05f;
  const Eigen::Vector3f direction = Eigen::Vector3f(0.6f, 0.0f, -0.8f);
  EXPECT_TRUE(PlantedFootOffset(Eigen::Vector3f::Zero(), give).isZero());
  EXPECT_TRUE(PlantedFootOffset(0.049f * direction, give).isZero());
  EXPECT_TRUE(PlantedFootOffset(0.3f * direction, give).isApprox(0.25f * direction, 1e-5f));
  Eigen::Vector3f previous = Eigen::Vector3f::Zero();
  for (float norm = 0.0f; norm <= 0.2f; norm += 0.001f) {  // 1 mm more offset a frame
    const Eigen::Vector3f offset = norm * direction;
    const Eigen::Vector3f foot = PlantedFootOffset(offset, give);
    EXPECT_LE((foot - previous).norm(), 0.00101f) << norm;  // no more than the offset moved
    EXPECT_LE((offset - foot).norm(), give + 1e-5f) << norm;
    previous = foot;
  }
}

// The guard's rigid move goes down no further than the body's lowest resting joint allows; from
// under the floor, no further down at all; up and over the ground, untouched.
TEST(MotionGuardTest, TheGuardsMoveTakesTheBodyNoLowerThanTheFloor) {
  const Eigen::Vector3f down(0.3f, -0.10f, 0.2f);
  EXPECT_TRUE(OffsetAboveFloor(down, 0.04f).isApprox(Eigen::Vector3f(0.3f, -0.04f, 0.2f)));
  EXPECT_TRUE(OffsetAboveFloor(down, 0.5f).isApprox(down)) << "room enough: as it is";
  EXPECT_TRUE(OffsetAboveFloor(down, -0.02f).isApprox(Eigen::Vector3f(0.3f, 0.0f, 0.2f))) << "under: no lower";
  const Eigen::Vector3f up(0.0f, 0.07f, -0.1f);
  EXPECT_TRUE(OffsetAboveFloor(up, -0.02f).isApprox(up)) << "never raised nor lowered by the rule";
  EXPECT_TRUE(OffsetAboveFloor(up, 0.0f).isApprox(up));
}

TEST(MotionGuardTest, FollowsMotionWithinTheBoundsExactly) {
  MotionGuard guard(Limits(), kDt, Exact());
  for (int f = 0; f < 60; ++f) {
    const float t = static_cast<float>(f * kDt);
    const Eigen::Vector3f target(1.2f * t, 0.9f + 0.02f * std::sin(6.0f * t), 0.0f);
    bool limited = true;
    const Eigen::Vector3f out = guard.Next(f * kDt, target, Eigen::Vector3f(1.2f * t, 1.0f, 0.0f), &limited);
    EXPECT_FALSE(limited) << f;
    EXPECT_LT((out - target).norm(), 1e-6f) << f;
  }
}

// A standing body's solve hops between its neighbours' stances (±2 cm a frame, 1.2 m/s): while
// the hands' midpoint stays put over the ground, the pelvis eases towards the solve instead of
// hopping; once the hands travel, it follows the solve exactly again.
TEST(MotionGuardTest, AStandingBodyDoesNotHopBetweenStancesAndAWalkingOneFollowsItsSolve) {
  MotionGuard guard(Limits(), kDt, Exact());
  float fastest_standing = 0, farthest_standing = 0;
  Eigen::Vector3f previous = Eigen::Vector3f::Zero();
  for (int f = 0; f < 90; ++f) {
    // A wave: one hand moves up and down, the midpoint goes up and down with it, not over the ground.
    const Eigen::Vector3f hands(0.0f, 1.1f + 0.15f * std::sin(8.0f * static_cast<float>(f * kDt)), 0.0f);
    const Eigen::Vector3f target(f % 2 == 0 ? 0.02f : -0.02f, 0.9f, 0.0f);
    bool limited = false;
    const Eigen::Vector3f out = guard.Next(f * kDt, target, hands, &limited);
    if (f > 0) fastest_standing = std::max(fastest_standing, static_cast<float>((out - previous).norm() / kDt));
    farthest_standing = std::max(farthest_standing, (out - target).norm());
    previous = out;
  }
  EXPECT_LT(fastest_standing, 0.5f) << "m/s: the solve hops at 1.2 m/s";
  EXPECT_LT(farthest_standing, 0.04f) << "m: it stays among the solve's stances";
  // Walking: the hands travel at 1.2 m/s, and after the hands' window the pelvis is the solve's.
  float farthest_walking = 0;
  for (int f = 90; f < 150; ++f) {
    const float walked = 1.2f * static_cast<float>((f - 90) * kDt);
    const Eigen::Vector3f hands(walked, 1.1f, 0.0f), target(walked, 0.9f, 0.0f);
    bool limited = false;
    const Eigen::Vector3f out = guard.Next(f * kDt, target, hands, &limited);
    if (f >= 120) farthest_walking = std::max(farthest_walking, (out - target).norm());
  }
  EXPECT_LT(farthest_walking, 1e-3f) << "m";
}

// A noisier tracker's standing solve hops further: the standing filter's time constant grows with
// the input's measured noise above standing_noise_acceleration, up to standing_noise_max_factor
// times, and not at all for input as clean as the development's.
TEST(MotionGuardTest, ANoisierTrackersStandingBodyIsHeldLonger) {
  MotionLimits limits = Limits();
  limits.pelvis_acceleration_max = 1000.0f;  // the filter alone, not the bound, holds the hops
  auto fastest_standing = [&](float noise) {
    MotionGuard guard(limits, kDt, Exact());
    guard.SetInputNoise(noise);
    float fastest = 0;
    Eigen::Vector3f previous = Eigen::Vector3f::Zero();
    for (int f = 0; f < 60; ++f) {
      const Eigen::Vector3f target(f % 2 == 0 ? 0.03f : -0.03f, 0.9f, 0.0f), hands(0.0f, 1.1f, 0.0f);
      bool limited = false;
      const Eigen::Vector3f out = guard.Next(f * kDt, target, hands, &limited);
      if (f > 30) fastest = std::max(fastest, static_cast<float>((out - previous).norm() / kDt));
      previous = out;
    }
    return fastest;
  };
  const MotionGuardOptions defaults;
  const float clean = fastest_standing(0.0f);
  EXPECT_FLOAT_EQ(fastest_standing(0.5f * defaults.standing_noise_acceleration), clean);
  EXPECT_FLOAT_EQ(fastest_standing(defaults.standing_noise_acceleration), clean);
  const float noisy = fastest_standing(1.5f * defaults.standing_noise_acceleration);
  const float noisiest = fastest_standing(defaults.standing_noise_max_factor * defaults.standing_noise_acceleration);
  EXPECT_LT(noisy, 0.9f * clean);
  EXPECT_LT(noisiest, 0.9f * noisy);
  EXPECT_FLOAT_EQ(fastest_standing(10.0f * defaults.standing_noise_acceleration), noisiest);  // no further
}

TEST(MotionGuardTest, AJumpOfTheTargetBecomesBoundedMotionThatArrives) {
  const MotionLimits limits = Limits();
  MotionGuard guard(limits, kDt, Exact());
  Eigen::Vector3f previous = Eigen::Vector3f::Zero(), previous_velocity = Eigen::Vector3f::Zero();
  int limited_frames = 0;
  for (int f = 0; f < 120; ++f) {
    // The solve put the body 1 m away in one frame, and the hands went along.
    const Eigen::Vector3f target = f < 10 ? Eigen::Vector3f::Zero() : Eigen::Vector3f(1.0f, 0, 0);
    bool limited = false;
    const Eigen::Vector3f out = guard.Next(f * kDt, target, target + Eigen::Vector3f(0, 0.3f, 0.2f), &limited);
    limited_frames += limited;
    if (f > 0) {
      const Eigen::Vector3f velocity = (out - previous) / kDt;
      EXPECT_LE(velocity.norm(), limits.pelvis_speed_max + 1e-3f) << f;
      EXPECT_LE((velocity - previous_velocity).norm() / kDt, limits.pelvis_acceleration_max * 1.001f) << f;
      previous_velocity = velocity;
    }
    previous = out;
  }
  EXPECT_LT((previous - Eigen::Vector3f(1.0f, 0, 0)).norm(), 1e-3f);  // it got there
  EXPECT_GT(limited_frames, 5);
  EXPECT_LT(limited_frames, 60);  // in about a second, no endless oscillation
}

TEST(MotionGuardTest, ABodyDoesNotRunOffWhileItsHandsStayPut) {
  const MotionLimits limits = Limits();
  MotionGuard guard(limits, kDt, Exact());
  Eigen::Vector3f previous = Eigen::Vector3f::Zero();
  for (int f = 0; f < 60; ++f) {
    const Eigen::Vector3f target(1.8f * static_cast<float>(f * kDt), 0.9f, 0.0f);  // 1.8 m/s: a body could
    bool limited = false;
    const Eigen::Vector3f out = guard.Next(f * kDt, target, Eigen::Vector3f(0, 1.0f, 0.3f), &limited);
    if (f > 0) {
      EXPECT_LE((out - previous).norm() / kDt, limits.pelvis_speed_beyond_hands_max + 1e-3f) << f;
      // What it tells the stages after it (ReachLean::Shift): the step it made and the bound it kept.
      EXPECT_TRUE(guard.velocity().isApprox((out - previous) / kDt, 1e-4f)) << f;
      EXPECT_NEAR(guard.speed_bound(), limits.pelvis_speed_beyond_hands_max, 1e-5f) << f;
      EXPECT_NEAR(guard.foot_speed_bound(), limits.ankle_speed_max, 1e-5f) << "no bins: the fastest foot";
    } else {
      EXPECT_TRUE(guard.velocity().isZero());
      EXPECT_TRUE(std::isinf(guard.speed_bound())) << "a stream's first frame has no speed to bound";
      EXPECT_TRUE(std::isinf(guard.foot_speed_bound()));
    }
    previous = out;
  }
}

// A standing body's solve that hops between its neighbours' stances is held to how fast the
// database's pelvis moved while its hands stood, not to what a body that sets off with its hands
// still does; once the hands travel, the bounds by their speed alone hold (stop 85).
TEST(MotionGuardTest, AStandingBodyMovesNoFasterThanTheDatabasesStandingBodies) {
  MotionLimits limits = Limits();
  limits.pelvis_speed_while_hands_stand = 0.3f;
  MotionGuardOptions options = Exact();
  options.standing_smoothing_seconds = 0;  // the bound alone
  auto fastest = [&](const MotionGuardOptions& guard_options, float hands_speed, int from_frame) {
    MotionGuard guard(limits, kDt, guard_options);
    Eigen::Vector3f previous = Eigen::Vector3f::Zero();
    float speed = 0.0f;
    for (int f = 0; f < 90; ++f) {
      const float t = static_cast<float>(f * kDt);
      const Eigen::Vector3f target(0.9f * t, 0.9f, 0.0f);  // the solve drifts off at 0.9 m/s
      bool limited = false;
      const Eigen::Vector3f out = guard.Next(f * kDt, target, Eigen::Vector3f(hands_speed * t, 1.0f, 0.3f), &limited);
      if (f >= from_frame) speed = std::max(speed, (out - previous).norm() / static_cast<float>(kDt));
      previous = out;
    }
    return speed;
  };
  EXPECT_NEAR(fastest(options, 0.0f, 1), 0.3f, 1e-3f) << "hands still: the standing bound";
  EXPECT_NEAR(fastest(options, 0.1f, 1), 0.3f, 1e-3f) << "hands that sway stand too";
  // Hands that travel at 0.8 m/s (past moving_hands_speed once the 1 s window holds it): the
  // solve's 0.9 m/s is within hands + the most the pelvis outran them.
  EXPECT_NEAR(fastest(options, 0.8f, 45), 0.9f, 1e-3f);
  options.bound_standing_body = false;
  EXPECT_NEAR(fastest(options, 0.0f, 1), 0.9f, 1e-3f) << "off: hands + beyond-hands (1.0) lets the drift through";
}

// A database of a standing body that shifts its weight (pelvis 0.5 m/s, hands still) and a walk
// (pelvis and hands at 1.52 m/s): while the hands move at 0.35 m/s the pelvis may move as fast as
// the database's did with hands that slow (0.5 m/s), not hands + the most it ever outran them.
TEST(MotionLimitsTest, BoundsThePelvisByWhatTheDatabaseDidWithHandsThatSlow) {
  constexpr double kStep = 0.1;  // the hands' window is 5 frames
  auto clip = [](float pelvis_speed, float hands_speed) {
    std::vector<FrameFeatures> frames(20);
    for (int f = 0; f < 20; ++f) {
      FrameFeatures& x = frames[f];
      x = {};
      x.ref_origin_x = hands_speed * static_cast<float>(f * kStep);
      x.pelvis_position[0] = (pelvis_speed - hands_speed) * static_cast<float>(f * kStep);
      x.pelvis_position[1] = 0.9f;
      x.wrist_position[0][1] = x.wrist_position[1][1] = 1.0f;
      x.wrist_position[0][2] = 0.2f;
      x.wrist_position[1][2] = -0.2f;
    }
    return frames;
  };
  const std::vector<FrameFeatures> standing = clip(0.5f, 0.0f), walking = clip(1.52f, 1.52f);
  const std::vector<std::span<const FrameFeatures>> clips = {standing, walking};
  const MotionLimits limits = MeasureMotionLimits(clips, kStep);
  EXPECT_NEAR(limits.pelvis_speed_beyond_hands_max, 0.5f, 1e-3f);
  EXPECT_NEAR(limits.PelvisSpeedBoundForHands({0.0f, 0.0f}), 0.5f, 1e-3f);
  EXPECT_NEAR(limits.PelvisSpeedBoundForHands({0.35f, 0.35f}), 0.5f, 1e-3f) << "the sum would allow 0.85";
  EXPECT_NEAR(limits.PelvisSpeedBoundForHands({1.55f, 1.55f}), 1.52f, 1e-3f);
  EXPECT_NEAR(limits.PelvisSpeedBoundForHands({5.0f, 5.0f}), 5.5f, 1e-3f) << "past the database's hands: the sum";
  EXPECT_NEAR(limits.PelvisSpeedBoundForHands({1.55f, 0.0f}), 0.5f, 1e-3f)
      << "hands fast over the last 0.5 s that went nowhere over 2 s: the body stood";
  EXPECT_NEAR(limits.pelvis_speed_while_hands_stand, 0.5f, 1e-3f) << "the walk's hands travel: not standing";
}

// The feet alike: a standing body that shuffles a foot at 0.3 m/s and a walk whose swinging foot
// goes 4 m/s: with still hands a foot may move 0.3 m/s, with walking hands 4, and past the
// database's hands as fast as its fastest foot.
TEST(MotionLimitsTest, BoundsTheFeetByWhatTheDatabaseDidWithHandsThatSlow) {
  constexpr double kStep = 0.1;
  auto clip = [](float ankle_speed, float hands_speed) {
    std::vector<FrameFeatures> frames(20);
    for (int f = 0; f < 20; ++f) {
      FrameFeatures& x = frames[f];
      x = {};
      x.ref_origin_x = hands_speed * static_cast<float>(f * kStep);
      x.pelvis_position[1] = 0.9f;
      x.wrist_position[0][1] = x.wrist_position[1][1] = 1.0f;
      x.wrist_position[0][2] = 0.2f;
      x.wrist_position[1][2] = -0.2f;
      x.ankle_velocity[f % 2][0] = ankle_speed;  // one foot at a time
    }
    return frames;
  };
  const std::vector<FrameFeatures> standing = clip(0.3f, 0.0f), walking = clip(4.0f, 1.52f);
  const MotionLimits limits =
      MeasureMotionLimits(std::vector<std::span<const FrameFeatures>>{standing, walking}, kStep);
  EXPECT_NEAR(limits.ankle_speed_max, 4.0f, 1e-5f);
  EXPECT_NEAR(limits.AnkleSpeedBoundForHands({0.0f, 0.0f}), 0.3f, 1e-5f);
  EXPECT_NEAR(limits.AnkleSpeedBoundForHands({1.55f, 1.55f}), 4.0f, 1e-5f);
  EXPECT_NEAR(limits.AnkleSpeedBoundForHands({1.55f, 0.0f}), 0.3f, 1e-5f) << "hands that went nowhere over 2 s";
  EXPECT_NEAR(limits.AnkleSpeedBoundForHands({5.0f, 5.0f}), 4.0f, 1e-5f) << "past the database's hands: its fastest";
}

// A standing body whose pelvis marker swaps for one frame (0.3 m away and back: 3 m/s twice): in a
// bin of 30,000 frames those two are outliers, and a standing body's hands bound it to 0; in a clip
// of 500 frames there are not enough frames to tell, and the fastest binds.
TEST(MotionLimitsTest, ABinsBoundLeavesOutItsOutliersWhenItHasFramesEnough) {
  constexpr double kStep = 0.1;
  auto standing_with_a_swap = [](int frames) {
    std::vector<FrameFeatures> clip(frames);
    for (int f = 0; f < frames; ++f) {
      FrameFeatures& x = clip[f];
      x = {};
      x.pelvis_position[0] = f == frames / 2 ? 0.3f : 0.0f;
      x.pelvis_position[1] = 0.9f;
      x.wrist_position[0][1] = x.wrist_position[1][1] = 1.0f;
      x.wrist_position[0][2] = 0.2f;
      x.wrist_position[1][2] = -0.2f;
    }
    return clip;
  };
  const std::vector<FrameFeatures> long_clip = standing_with_a_swap(30000), short_clip = standing_with_a_swap(500);
  const MotionLimits many = MeasureMotionLimits(std::vector<std::span<const FrameFeatures>>{long_clip}, kStep);
  EXPECT_NEAR(many.PelvisSpeedBoundForHands({0.0f, 0.0f}), 0.0f, 1e-3f);
  EXPECT_NEAR(many.pelvis_speed_max, 3.0f, 1e-3f) << "the overall maximum is still the fastest";
  const MotionLimits few = MeasureMotionLimits(std::vector<std::span<const FrameFeatures>>{short_clip}, kStep);
  EXPECT_NEAR(few.PelvisSpeedBoundForHands({0.0f, 0.0f}), 3.0f, 1e-3f);
}

// The guard keeps to that bound: hands rising at 0.35 m/s do not let a solve that runs at
// 1.8 m/s take the body faster than the database's bodies went with such hands.
TEST(MotionGuardTest, GesturingHandsLetTheBodyGoOnlyAsFastAsTheDatabasesDidWithSuchHands) {
  MotionLimits limits = Limits();
  limits.pelvis_speed_by_hands_speed[0] = {0.2f, 0.4f, 0.5f, 0.7f, 0.9f};
  MotionGuard guard(limits, kDt, Exact());
  Eigen::Vector3f previous = Eigen::Vector3f::Zero();
  for (int f = 0; f < 60; ++f) {
    const float t = static_cast<float>(f * kDt);
    bool limited = false;
    const Eigen::Vector3f out = guard.Next(f * kDt, Eigen::Vector3f(1.8f * t, 0.9f, 0.0f),
                                           Eigen::Vector3f(0, 1.0f + 0.35f * t, 0.3f), &limited);
    if (f > 0) {
      EXPECT_LE((out - previous).norm() / kDt, 0.7f + 1e-3f) << f << ": hands + beyond would allow 1.35";
    }
    previous = out;
  }
}

// A stream's first frames: the hands' two first samples 3 cm apart (a tracker's jitter) read as
// 0.9 m/s over one frame, and the bound by such hands let the body's first step go as fast. With
// the input ahead known (the hands go nowhere over the next half second) the bound is a standing
// body's from the first step; a stream that goes on ignores a span given later, and a new stream
// without one reads the frames so far again.
TEST(MotionGuardTest, AStreamsFirstStepIsBoundedByTheHandsAheadWhenTheyAreKnown) {
  MotionLimits limits = Limits();
  limits.pelvis_speed_by_hands_speed[0] = {0.3f, 0.5f, 0.8f, 1.0f, 1.2f, 1.4f, 1.6f, 1.8f, 2.0f, 2.0f};
  const Eigen::Vector3f hands(0, 1.0f, 0.3f), jittered = hands + Eigen::Vector3f(0.03f, 0, 0);
  const Eigen::Vector3f far(0.1f, 0.9f, 0);  // the second frame's solve, 10 cm on: 3 m/s
  auto first_step = [&](MotionGuard& guard, double start, bool ahead) {
    bool limited = false;
    if (ahead) guard.SetLeadingHands(0.5, Eigen::Vector3f(0.01f, 0, 0));
    const Eigen::Vector3f a = guard.Next(start, Eigen::Vector3f(0, 0.9f, 0), hands, &limited);
    const Eigen::Vector3f b = guard.Next(start + kDt, far, jittered, &limited);
    return (b - a).norm() / kDt;
  };
  MotionGuard unknown(limits, kDt, Exact()), known(limits, kDt, Exact());
  EXPECT_NEAR(first_step(unknown, 0.0, false), 1.9f, 1e-3f);  // 0.9 m/s of hands + 1.0 beyond them
  EXPECT_NEAR(first_step(known, 0.0, true), 0.3f, 1e-3f);     // 0.02 m/s: a standing body's
  // The stream goes on: a span given now (hands that would go 2 m/s) is not read.
  bool limited = false;
  const Eigen::Vector3f before = known.Next(2 * kDt, far, hands, &limited);
  known.SetLeadingHands(0.5, Eigen::Vector3f(1.0f, 0, 0));
  const Eigen::Vector3f after = known.Next(3 * kDt, Eigen::Vector3f(1.0f, 0.9f, 0), hands, &limited);
  EXPECT_LE((after - before).norm() / kDt, 0.3f + 1e-3f);
  // A new clock (a reused session) without a span: the frames so far again.
  EXPECT_NEAR(first_step(known, 0.0, false), 1.9f, 1e-3f);
}

// A stream's first solves hop between neighbours' stances while the hands' windows hold a few
// frames (a raise-up's hands moving 1-2 m/s let its body hop 2 m/s): over its first
// start_ease_seconds the body eases in through the standing filter where the hands ahead are
// unknown (lag 0), and as far as they stand where they are known.
TEST(MotionGuardTest, AStreamEasesInOverItsFirstFramesUnlessTheHandsAheadTravel) {
  MotionGuardOptions options = Exact();
  options.start_ease_seconds = MotionGuardOptions().start_ease_seconds;
  const Eigen::Vector3f solved(0, 0.9f, 0), hop(0.06f, 0.9f, 0);  // the second solve 6 cm on
  // The hands rise and come forward at 1.5 m/s: not a standing body's by their speed alone.
  auto hands = [](int f) { return Eigen::Vector3f(0, 1.0f + 0.04f * f, 0.3f + 0.03f * f); };
  auto first_step = [&](const MotionGuardOptions& o, std::optional<Eigen::Vector3f> ahead, double span = 0.2) {
    MotionGuard guard(Limits(), kDt, o);
    if (ahead) guard.SetLeadingHands(span, *ahead);
    bool limited = false;
    const Eigen::Vector3f a = guard.Next(0.0, solved, hands(0), &limited);
    const Eigen::Vector3f b = guard.Next(kDt, hop, hands(1), &limited);
    return (b - a).x();
  };
  EXPECT_NEAR(first_step(Exact(), std::nullopt), 0.06f, 1e-5f);  // no ease-in: followed at once
  // Unknown hands ahead: through the 0.1 s filter at nearly full weight (1/6 of the ease gone).
  const float dt = static_cast<float>(kDt), standing = 1.0f - dt / options.start_ease_seconds;
  const float follow = 1.0f - standing * (1.0f - dt / (options.standing_smoothing_seconds + dt));
  EXPECT_NEAR(first_step(options, std::nullopt), 0.06f * follow, 1e-5f);
  EXPECT_LT(first_step(options, std::nullopt), 0.03f);
  // Hands ahead that stand (they rise in place): the same.
  EXPECT_NEAR(first_step(options, Eigen::Vector3f(0, 0.3f, 0.01f)), 0.06f * follow, 1e-5f);
  // Hands ahead that travel (a walk's 1.3 m/s over the ground): no ease, the solve at once.
  EXPECT_NEAR(first_step(options, Eigen::Vector3f(0, 0, 0.26f)), 0.06f, 1e-5f);
  // Read as if they had stood before the stream (start_rest_seconds), 0.26 m over 0.5 s: 0.52 m/s,
  // nearly a standing body's: eased part of the way.
  options.start_rest_seconds = MotionGuardOptions().start_rest_seconds;
  EXPECT_GT(first_step(options, Eigen::Vector3f(0, 0, 0.26f)), 0.06f * follow + 1e-3f);
  EXPECT_LT(first_step(options, Eigen::Vector3f(0, 0, 0.26f)), 0.06f - 1e-3f);
  // Half a second of them at that speed is a walk: no ease (a whole clip's input ahead says
  // whether the hands travel; nothing is assumed).
  EXPECT_NEAR(first_step(options, Eigen::Vector3f(0, 0, 0.65f), 0.5), 0.06f, 1e-5f);
  // Ahead that stand, read over the rest span: standing outright.
  const float held = dt / (options.standing_smoothing_seconds + dt);
  EXPECT_NEAR(first_step(options, Eigen::Vector3f(0, 0.3f, 0.01f)), 0.06f * held, 1e-5f);
}

// Over a stream's first start_rest_seconds the hands are taken to have stood where first seen
// before it began, so its start reads as the middle of a stream does: three frames of arms
// swinging forward at 1 m/s are no walk either way, and a solve that lurches 5 cm a frame
// meanwhile (a body of the wrong size reaching for them) is eased, where the few frames so far
// alone let it go at once.
TEST(MotionGuardTest, AStreamsFirstArmSwingIsNoWalk) {
  MotionGuardOptions options = Exact();
  options.start_rest_seconds = MotionGuardOptions().start_rest_seconds;
  auto last_step = [&](const MotionGuardOptions& o, double start) {
    MotionGuard guard(Limits(), kDt, o);
    bool limited = false;
    Eigen::Vector3f previous = Eigen::Vector3f::Zero(), output = Eigen::Vector3f::Zero();
    const int still = static_cast<int>(std::lround(start / kDt));
    for (int f = 0; f <= still + 3; ++f) {
      const int moving = std::max(0, f - still);  // frames into the swing and the lurch
      const Eigen::Vector3f hands(0, 1.0f, 0.3f + 0.033f * static_cast<float>(moving));
      const Eigen::Vector3f solved(0, 0.9f, 0.05f * static_cast<float>(moving));
      previous = output;
      output = guard.Next(f * kDt, solved, hands, &limited);
    }
    return (output - previous).z();
  };
  EXPECT_LT(last_step(options, 0.0), 0.03f);           // the stream's start: eased
  EXPECT_LT(last_step(options, 1.0), 0.03f);           // as a second in
  EXPECT_NEAR(last_step(Exact(), 0.0), 0.05f, 1e-5f);  // the frames so far alone: followed at once
}

TEST(MotionGuardTest, AGapAllowsWhatItsLengthAllows) {
  MotionGuard guard(Limits(), kDt, Exact());
  bool limited = false;
  guard.Next(0.0, Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero(), &limited);
  // 0.8 m away after a 1 s gap: 0.8 m/s, within the bounds.
  const Eigen::Vector3f out = guard.Next(1.0, Eigen::Vector3f(0.8f, 0, 0), Eigen::Vector3f(0.8f, 0.2f, 0.2f), &limited);
  EXPECT_FALSE(limited);
  EXPECT_LT((out - Eigen::Vector3f(0.8f, 0, 0)).norm(), 1e-6f);
}

// A walk through a 2 s gap: where the hands went while the input was missing is where the body
// may have gone. (Measured from after the gap alone, the hands had not moved: the body crawled
// after the walk at a standing body's speed, metres behind.)
TEST(MotionGuardTest, AfterAGapTheBodyMayGoWhereTheHandsWent) {
  MotionLimits limits = Limits();
  for (auto& by_hands : limits.pelvis_speed_by_hands_speed) {
    for (int bin = 0; bin <= 20; ++bin) by_hands.push_back(0.4f + 0.1f * static_cast<float>(bin));
  }
  MotionGuard guard(limits, kDt, Exact());
  auto walked = [](double t) { return Eigen::Vector3f(1.3f * static_cast<float>(t), 0.9f, 0.0f); };
  bool limited = false;
  for (int f = 0; f < 30; ++f)
    guard.Next(f * kDt, walked(f * kDt), walked(f * kDt) + Eigen::Vector3f(0, 0.2f, 0), &limited);
  const double back = 29 * kDt + 2.0;
  const Eigen::Vector3f out = guard.Next(back, walked(back), walked(back) + Eigen::Vector3f(0, 0.2f, 0), &limited);
  EXPECT_LT((out - walked(back)).norm(), 0.01f) << "m behind the walk";
}

TEST(InputJumpDetectorTest, FlagsStepsNoHandMakes) {
  MotionGuardOptions options = Exact();
  options.input_noise_sigmas = 0.0f;  // the database's bounds alone (noise: the next test)
  InputJumpDetector detector(Limits(), kDt, options);
  const Eigen::Vector3f a(0, 1, 0), b(0.02f, 1, 0), c(0.04f, 1, 0);  // 0.6 m/s, steady
  EXPECT_FALSE(detector.Step(0, &a, &b, c, true));
  EXPECT_FALSE(detector.Step(0, nullptr, nullptr, c, true));
  const Eigen::Vector3f step = b + Eigen::Vector3f(0.2f, 0, 0);  // 20 cm in a frame: 6 m/s
  EXPECT_TRUE(detector.Step(0, &a, &b, step, true));
  const Eigen::Vector3f small_step = b + Eigen::Vector3f(0.1f, 0, 0);  // 3 m/s, but from 0.6 in a frame
  EXPECT_TRUE(detector.Step(1, &a, &b, small_step, true));
}

// A phone held in the hand (AR tracking's 2.5 cm of jitter per axis) of a user walking, against a
// database of walks (its hands at most 2.5 m/s and 19 m/s²): the jitter alone steps 2-3 × faster
// than those hands ever accelerate, and is no jump; a relocalisation's 50 cm step in it is one.
// The guessed input over a dropout does not join the noise measure.
TEST(InputJumpDetectorTest, ATrackersJitterIsNoJumpButAStepInItIs) {
  MotionLimits limits = Limits();
  limits.wrist_speed_max = 2.5f;
  limits.wrist_acceleration_max = 19.0f;
  std::mt19937 random(7);
  std::normal_distribution<float> jitter(0.0f, 0.025f);
  constexpr int kFrames = 600, kStepFrame = 450;
  std::vector<Eigen::Vector3f> input(kFrames);
  for (int f = 0; f < kFrames; ++f) {
    input[f] = Eigen::Vector3f(0.5f * static_cast<float>(f * kDt) + (f >= kStepFrame ? 0.5f : 0.0f), 1.0f, 0.0f) +
               Eigen::Vector3f(jitter(random), jitter(random), jitter(random));
  }
  auto flags = [&](const MotionGuardOptions& options) {
    InputJumpDetector detector(limits, kDt, options);
    std::vector<int> flagged;
    for (int f = 0; f < kFrames; ++f) {
      if (detector.Step(0, f >= 2 ? &input[f - 2] : nullptr, f >= 1 ? &input[f - 1] : nullptr, input[f], true)) {
        flagged.push_back(f);
      }
    }
    EXPECT_NEAR(
        detector.AccelerationNoise(0), std::sqrt(6.0f) * 0.025f / static_cast<float>(kDt * kDt),
        options.input_noise_sigmas > 0 ? 15.0f : 1e-6f + std::sqrt(6.0f) * 0.025f / static_cast<float>(kDt * kDt))
        << "m/s² per axis, measured";
    return flagged;
  };
  MotionGuardOptions options = Exact();
  const std::vector<int> flagged = flags(options);
  for (int f : flagged) {
    EXPECT_GE(f, kStepFrame) << "jitter flagged";
    EXPECT_LE(f, kStepFrame + 1) << "jitter flagged";
  }
  EXPECT_FALSE(flagged.empty()) << "the 50 cm step was not flagged";
  if (!flagged.empty()) {
    EXPECT_EQ(flagged.front(), kStepFrame);
  }
  options.input_noise_sigmas = 0.0f;  // the database's bounds alone: the jitter is flagged
  EXPECT_GT(flags(options).size(), static_cast<size_t>(kFrames / 4));

  // Input guessed over a dropout (smooth) leaves the measure as it was.
  InputJumpDetector detector(limits, kDt, Exact());
  for (int f = 2; f < 60; ++f) detector.Step(1, &input[f - 2], &input[f - 1], input[f], true);
  const float measured = detector.AccelerationNoise(1);
  const Eigen::Vector3f still(0, 1, 0);
  for (int f = 0; f < 60; ++f) detector.Step(1, &still, &still, still, false);
  EXPECT_EQ(detector.AccelerationNoise(1), measured);
  EXPECT_EQ(detector.AccelerationNoise(0), 0.0f) << "the other hand measured nothing";
}

TEST(PlausibilityTest, MeasuresSpeedHandsFeetAndFloor) {
  std::vector<PlausibilityFrame> frames(3);
  for (int f = 0; f < 3; ++f) {
    frames[f].time = f * kDt;
    frames[f].pelvis = Eigen::Vector3f(f == 2 ? 0.5f : 0.0f, 0.9f, 0.0f);  // 15 m/s into frame 2
    frames[f].hands = {Eigen::Vector3f(0.3f, 1, 0), Eigen::Vector3f(-0.3f, 1, 0)};
    frames[f].input = {Eigen::Vector3f(0.3f, 1.02f, 0), Eigen::Vector3f(-0.3f, 1, 0)};
    frames[f].ankles = {Eigen::Vector3f(0.1f, 0.08f, 0), Eigen::Vector3f(f == 2 ? 0.2f : -0.1f, 0.28f, 0)};
    frames[f].lowest_point = f == 1 ? -0.03f : 0.01f;
  }
  frames[2].flagged = true;
  const PlausibilityStats stats = MeasurePlausibility(frames, 0.08f, 2.0f);
  EXPECT_EQ(stats.frames, 3);
  EXPECT_NEAR(stats.pelvis_speed.max(), 15.0f, 1e-3f);
  EXPECT_EQ(stats.frames_over_speed_limit, 1);
  EXPECT_NEAR(stats.pelvis_acceleration_max, 15.0f / kDt, 1.0f);
  EXPECT_NEAR(stats.ankle_speed.max(), 9.0f, 1e-3f) << "the right ankle's 30 cm into frame 2";
  EXPECT_EQ(stats.ankle_speed.count(), 4) << "two ankles, two steps";
  EXPECT_NEAR(stats.hand_distance.max(), 0.02f, 1e-4f);
  EXPECT_LE(stats.hand_distance.Quantile(0.5), 0.001f);
  EXPECT_NEAR(stats.lower_foot_height.max(), 0.0f, 1e-6f);
  EXPECT_NEAR(stats.penetration_max, 0.03f, 1e-6f);
  EXPECT_EQ(stats.penetrating_frames, 1);
  EXPECT_EQ(stats.flagged_frames, 1);
  EXPECT_FLOAT_EQ(AllowedSpeed(0.6f), 1.6f);
  EXPECT_FLOAT_EQ(AllowedSpeed(1.5f), 3.0f);
}

// Input under the floor is out of any arm's reach, however near the shoulder (hand_floor.h).
TEST(PlausibilityTest, InputUnderTheFloorIsOutOfReach) {
  PlausibilityRig rig;
  rig.pelvis = 0;
  rig.wrists = {1, 2};
  rig.ankles = {0, 0};
  rig.shoulders = {3, 3};
  rig.arm_reach = {0.6f, 0.6f};
  const std::vector<Eigen::Vector3f> joints = {Eigen::Vector3f(0, 0.5f, 0), Eigen::Vector3f(0.2f, 0.1f, 0),
                                               Eigen::Vector3f(-0.2f, 0.1f, 0), Eigen::Vector3f(0, 0.45f, 0)};
  const std::array<Eigen::Vector3f, 2> input = {Eigen::Vector3f(0.2f, -0.05f, 0), Eigen::Vector3f(-0.2f, 0.0f, 0)};
  const PlausibilityFrame frame = MakePlausibilityFrame(rig, joints, input, 0.0, 0, false, false);
  EXPECT_FALSE(frame.input_in_reach[0]) << "5 cm under the floor, 51 cm from the shoulder";
  EXPECT_TRUE(frame.input_in_reach[1]) << "on the floor";
}

// --- The session on degraded synthetic input --------------------------------------------------

class NeverTeleportTest : public ::testing::Test {
 protected:
  static constexpr int kFrames = 150;  // 5 s of walking
  static constexpr int kJumpFrame = 70;

  void SetUp() override {
    setup_ = testing::MakeSyntheticReconstructionSetup({}, kFrames);
    options_.ankle_candidates = 60;  // the synthetic database is small
    options_.pose_neighbours = 40;
    const int pelvis = setup_.rig.topology.landmarks.pelvis;
    for (int f = 1; f < setup_.truth.num_frames(); ++f) {
      own_max_speed_ = std::max(
          own_max_speed_,
          static_cast<float>((setup_.truth.position(f, pelvis) - setup_.truth.position(f - 1, pelvis)).norm() / kDt));
    }
  }

  struct Mode {
    std::string name;
    StreamMode mode;
    int window_or_lag;
  };
  static std::vector<Mode> Modes() {
    return {{"lag 0", StreamMode::kFixedLag, 0},         {"lag 5", StreamMode::kFixedLag, 5},
            {"lag 15", StreamMode::kFixedLag, 15},       {"window 10", StreamMode::kSubInterval, 10},
            {"window 50", StreamMode::kSubInterval, 50}, {"whole clip", StreamMode::kSubInterval, 0}};
  }

  std::vector<ReconstructedFrame> Reconstruct(const std::vector<WristSample>& samples, const Mode& mode) const {
    ReconstructionOptions options = options_;
    options.mode = mode.mode;
    (mode.mode == StreamMode::kFixedLag ? options.lag : options.window) = mode.window_or_lag;
    auto frames = ReconstructOffline(setup_.database, options, samples);
    EXPECT_TRUE(frames.ok()) << frames.status();
    return frames.ok() ? *frames : std::vector<ReconstructedFrame>{};
  }

  float MaxPelvisSpeed(const std::vector<ReconstructedFrame>& frames) const {
    std::vector<PlausibilityFrame> measured;
    for (const ReconstructedFrame& f : frames) {
      PlausibilityFrame p;
      p.time = f.time;
      p.segment = f.segment;
      p.pelvis = f.pelvis_position;
      measured.push_back(p);
    }
    return MeasurePlausibility(measured, 0.0f, 0.0f).pelvis_speed.max();
  }

  // The fastest either ankle moves between consecutive frames of a segment.
  float MaxAnkleSpeed(const std::vector<ReconstructedFrame>& frames) const {
    const BodyLandmarks& l = setup_.rig.topology.landmarks;
    std::vector<Eigen::Quaternionf> rotations;
    std::vector<Eigen::Vector3f> positions;
    std::array<Eigen::Vector3f, 2> previous;
    float fastest = 0;
    for (size_t i = 0; i < frames.size(); ++i) {
      setup_.database->body().WorldTransforms(frames[i].pose, &rotations, &positions);
      const std::array<Eigen::Vector3f, 2> ankles = {positions[l.left_ankle], positions[l.right_ankle]};
      if (i > 0 && frames[i].segment == frames[i - 1].segment) {
        for (int side = 0; side < 2; ++side) {
          fastest = std::max(fastest, (ankles[side] - previous[side]).norm() /
                                          static_cast<float>(frames[i].time - frames[i - 1].time));
        }
      }
      previous = ankles;
    }
    return fastest;
  }

  // Every mode: the pelvis bound holds, and no foot outruns the database's fastest (with the
  // guard's margin).
  void ExpectNoTeleport(const std::vector<WristSample>& samples, const std::string& what) {
    const float allowed = AllowedSpeed(own_max_speed_);
    const float feet_allowed = setup_.database->motion_limits().ankle_speed_max * MotionGuardOptions{}.speed_margin;
    for (const Mode& mode : Modes()) {
      const std::vector<ReconstructedFrame> frames = Reconstruct(samples, mode);
      ASSERT_FALSE(frames.empty()) << what << ", " << mode.name;
      EXPECT_LE(MaxPelvisSpeed(frames), allowed)
          << what << ", " << mode.name << ": the capture's own pelvis moves at most " << own_max_speed_ << " m/s";
      EXPECT_LE(MaxAnkleSpeed(frames), feet_allowed + 1e-3f) << what << ", " << mode.name;
    }
  }

  std::vector<WristSample> Clean() const { return testing::WristSamplesOf(setup_); }

  testing::SyntheticReconstructionSetup setup_;
  ReconstructionOptions options_;
  float own_max_speed_ = 0;
};

TEST_F(NeverTeleportTest, CleanInputIsNeitherFlaggedNorHeldBack) {
  ExpectNoTeleport(Clean(), "clean");
  for (const Mode& mode : Modes()) {
    for (const ReconstructedFrame& f : Reconstruct(Clean(), mode)) {
      EXPECT_FALSE(f.implausible_input()) << mode.name << ", frame " << f.index;
    }
  }
}

TEST_F(NeverTeleportTest, AControllerStepOf20CmInOneFrameIsFlaggedAndNotFollowedAtOnce) {
  std::vector<WristSample> samples = Clean();
  for (size_t i = kJumpFrame; i < samples.size(); ++i) samples[i].right += Eigen::Vector3f(0.2f, 0.0f, 0.0f);
  ExpectNoTeleport(samples, "20 cm step");
  for (const Mode& mode : Modes()) {
    const std::vector<ReconstructedFrame> frames = Reconstruct(samples, mode);
    ASSERT_EQ(frames.size(), samples.size());
    EXPECT_EQ(frames[kJumpFrame].hand_state[1], TrackingState::kImplausible) << mode.name;
    EXPECT_EQ(frames[kJumpFrame].hand_state[0], TrackingState::kTracked) << mode.name;
    for (const ReconstructedFrame& f : frames) {
      if (std::abs(f.frame_in_segment - kJumpFrame) > 2) {
        EXPECT_FALSE(f.implausible_input()) << mode.name << ", frame " << f.frame_in_segment;
      }
    }
  }
}

TEST_F(NeverTeleportTest, BothWristsJumping20CmForOneFrameAreFlagged) {
  std::vector<WristSample> samples = Clean();
  samples[kJumpFrame].left += Eigen::Vector3f(0.0f, 0.0f, 0.2f);
  samples[kJumpFrame].right += Eigen::Vector3f(0.0f, 0.0f, 0.2f);
  ExpectNoTeleport(samples, "one-frame glitch");
  const std::vector<ReconstructedFrame> frames = Reconstruct(samples, Modes()[1]);
  ASSERT_EQ(frames.size(), samples.size());
  EXPECT_TRUE(frames[kJumpFrame].implausible_input());
  for (const ReconstructedFrame& f : frames) {
    if (std::abs(f.frame_in_segment - kJumpFrame) > 2) {
      EXPECT_FALSE(f.implausible_input()) << f.frame_in_segment;
    }
  }
}

TEST_F(NeverTeleportTest, QuantisedRepeatedJitteredAndGappedInputNeverTeleports) {
  std::vector<WristSample> quantised = Clean();
  for (WristSample& s : quantised) {
    for (Eigen::Vector3f* p : {&s.left, &s.right}) *p = (*p * 100.0f).array().round().matrix() / 100.0f;
  }
  ExpectNoTeleport(quantised, "1 cm quantisation");

  std::vector<WristSample> repeated = Clean();  // the tracker updates every 4th frame only
  for (size_t i = 0; i < repeated.size(); ++i) {
    if (i % 4 != 0) {
      repeated[i].left = repeated[i - i % 4].left;
      repeated[i].right = repeated[i - i % 4].right;
    }
  }
  ExpectNoTeleport(repeated, "repeated samples then a jump");

  std::vector<WristSample> jittered = Clean();
  std::mt19937 random(22);
  std::normal_distribution<float> noise(0.0f, 0.015f);  // per axis: about 2.6 cm in 3-D
  for (WristSample& s : jittered) {
    for (Eigen::Vector3f* p : {&s.left, &s.right}) *p += Eigen::Vector3f(noise(random), noise(random), noise(random));
  }
  ExpectNoTeleport(jittered, "2–3 cm jitter");

  std::vector<WristSample> gapped;  // 1 s without samples: a new segment
  for (const WristSample& s : Clean()) {
    if (s.time < 2.0 || s.time >= 3.0) gapped.push_back(s);
  }
  ExpectNoTeleport(gapped, "1 s gap");
}

}  // namespace
}  // namespace mocap
