#include "motion/reconstruct/stream_ankle_planter.h"

#include <cmath>
#include <numbers>
#include <type_traits>

#include <gtest/gtest.h>

namespace mocap {
namespace {

constexpr double kFrameTime = 1.0 / 30.0;
constexpr float kPlanted = 0.08f;  // the planted ankle height

float Ground(const Eigen::Vector3f& a, const Eigen::Vector3f& b) { return std::hypot(a.x() - b.x(), a.z() - b.z()); }

// The left foot's estimate `left(f)`, the right foot lifted and still, the hands at `hands(f)`
// (both at one point, or left and right): the planted output per frame.
template <typename Left, typename Hands>
std::vector<Eigen::Vector3f> Plant(StreamAnklePlanter* planter, int frames, Left left, Hands hands) {
  std::vector<Eigen::Vector3f> out;
  for (int f = 0; f < frames; ++f) {
    AnklePair ankles = {left(f), Eigen::Vector3f(-0.1f, 0.5f, 0.0f)};
    const auto at = hands(f);
    if constexpr (std::is_same_v<std::remove_cvref_t<decltype(at)>, Eigen::Vector2f>) {
      planter->Next(&ankles, {at, at});
    } else {
      planter->Next(&ankles, at);
    }
    EXPECT_EQ(ankles[1], Eigen::Vector3f(-0.1f, 0.5f, 0.0f)) << "a lifted foot is left as estimated";
    out.push_back(ankles[0]);
  }
  return out;
}

Eigen::Vector2f StillHands(int) { return Eigen::Vector2f(0.0f, 0.3f); }

// A standing foot's estimate wobbles by a few millimetres from frame to frame (each frame another
// candidate of the A4 cloud): A6 is given the mean of the contact so far, which settles.
TEST(StreamAnklePlanterTest, AStandingFootsWobbleBecomesTheContactsMean) {
  StreamAnklePlanter planter(kPlanted, kFrameTime, {}, 0.25f);
  const Eigen::Vector3f stands(0.1f, kPlanted, 0.0f);
  auto wobble = [&](int f) {
    return Eigen::Vector3f(stands + Eigen::Vector3f(0.004f * std::sin(2.1f * f), 0.0f, 0.004f * std::cos(1.3f * f)));
  };
  const std::vector<Eigen::Vector3f> out = Plant(&planter, 90, wobble, StillHands);
  float moved = 0, estimate_moved = 0;
  for (int f = 30; f < 90; ++f) {
    moved += Ground(out[f], out[f - 1]);
    estimate_moved += Ground(wobble(f), wobble(f - 1));
    EXPECT_LT(Ground(out[f], stands), 0.002f) << f;
  }
  EXPECT_LT(moved, 0.1f * estimate_moved);
}

// A foot that steps (lifts and goes) is released: the output returns from the contact's mean to
// the estimate over the cleanup's release frames, in equal parts, never jumping.
TEST(StreamAnklePlanterTest, AFootThatLiftsIsReleasedOverTheReleaseFrames) {
  const FootskateOptions options;
  StreamAnklePlanter planter(kPlanted, kFrameTime, options, 0.25f);
  const int lift = 30;
  auto step = [&](int f) {
    const float x = f < lift ? 0.003f * (f % 2) : 0.05f * static_cast<float>(f - lift + 1);  // 1.5 m/s once lifted
    const float y = f < lift ? kPlanted : kPlanted + 0.03f * static_cast<float>(f - lift + 1);
    return Eigen::Vector3f(x, y, 0.0f);
  };
  auto walking = [](int f) { return Eigen::Vector2f(0.04f * static_cast<float>(f), 0.0f); };  // 1.2 m/s
  const std::vector<Eigen::Vector3f> out = Plant(&planter, lift + 12, step, walking);
  EXPECT_LT(Ground(out[lift - 1], Eigen::Vector3f(0.0015f, 0.0f, 0.0f)), 0.001f) << "planted at the mean";
  for (int f = lift; f < lift + 12; ++f) {
    const float gap = (out[f] - step(f)).norm();
    if (f >= lift + options.release_frames) {
      EXPECT_LT(gap, 1e-6f) << f;
    } else {
      EXPECT_GT(gap, 0.0f) << f;
    }
    EXPECT_LT((out[f] - out[f - 1]).norm(), (step(f) - step(f - 1)).norm() + 0.02f) << f;
  }
}

// The estimate of a standing body's foot slides with its gesturing hands (every A4 candidate is
// placed in the wrists' frame) without lifting: while the hands' midpoint stays put the contact
// goes on. Once the hands travel, the same slide ends it.
TEST(StreamAnklePlanterTest, StandingHandsHoldAFootThatSlidesWithoutLifting) {
  const int slide = 70;  // frames planted first (over 2 s: the hands' windows are full)
  auto sliding = [&](int f) {
    return Eigen::Vector3f(f < slide ? 0.0f : 0.02f * static_cast<float>(f - slide), kPlanted, 0.0f);  // 0.6 m/s
  };
  StreamAnklePlanter standing(kPlanted, kFrameTime, {}, 0.25f);
  const std::vector<Eigen::Vector3f> held = Plant(&standing, slide + 10, sliding, StillHands);
  EXPECT_LT(held.back().x(), 0.5f * sliding(slide + 9).x()) << "held at the contact's mean";

  StreamAnklePlanter travelling(kPlanted, kFrameTime, {}, 0.25f);
  auto walking = [&](int f) { return Eigen::Vector2f(f < slide ? 0.0f : 0.04f * static_cast<float>(f - slide), 0.3f); };
  const std::vector<Eigen::Vector3f> released = Plant(&travelling, slide + 14, sliding, walking);
  EXPECT_LT((released.back() - sliding(slide + 13)).norm(), 1e-6f) << "released to the estimate";

  StreamAnklePlanter never(kPlanted, kFrameTime, {}, 0.0f);  // standing hands hold nothing
  const std::vector<Eigen::Vector3f> plain = Plant(&never, slide + 10, sliding, StillHands);
  EXPECT_LT((plain.back() - sliding(slide + 9)).norm(), 1e-6f);
}

// One hand waves while the other is held still (a goodbye): the wave drags the wrists' midpoint, and every
// A4 candidate with it, to and fro, and the foot's estimate slides along without lifting. The
// resting hand says the body stands: the contact goes on. Read from the midpoint alone (the option
// off) the same slide is a step.
TEST(StreamAnklePlanterTest, AHandThatRestsHoldsAFootWhileTheOtherWaves) {
  const int slide = 70;
  auto sliding = [&](int f) {
    return Eigen::Vector3f(f < slide ? 0.0f : 0.02f * static_cast<float>(f - slide), kPlanted, 0.0f);
  };
  auto waving = [](int f) {
    const float x = 0.3f * std::sin(2.0f * std::numbers::pi_v<float> * 1.2f * static_cast<float>(f * kFrameTime));
    return std::array<Eigen::Vector2f, 2>{Eigen::Vector2f(x, 0.3f), Eigen::Vector2f(-0.2f, 0.3f)};
  };
  StreamAnklePlanter either(kPlanted, kFrameTime, {}, 0.25f);
  const std::vector<Eigen::Vector3f> held = Plant(&either, slide + 10, sliding, waving);
  EXPECT_LT(held.back().x(), 0.5f * sliding(slide + 9).x()) << "held at the contact's mean";

  FootskateOptions midpoint_only;
  midpoint_only.stream_stands_on_either_hand = false;
  StreamAnklePlanter midpoint(kPlanted, kFrameTime, midpoint_only, 0.25f);
  const std::vector<Eigen::Vector3f> released = Plant(&midpoint, slide + 10, sliding, waving);
  EXPECT_LT((released.back() - sliding(slide + 9)).norm(), 1e-6f) << "released to the estimate";

  // Both hands travelling (a walk): released, whichever hand is read.
  auto walking = [&](int f) {
    const float x = f < slide ? 0.0f : 0.04f * static_cast<float>(f - slide);
    return std::array<Eigen::Vector2f, 2>{Eigen::Vector2f(x, 0.5f), Eigen::Vector2f(x, 0.1f)};
  };
  StreamAnklePlanter walker(kPlanted, kFrameTime, {}, 0.25f);
  const std::vector<Eigen::Vector3f> walked = Plant(&walker, slide + 14, sliding, walking);
  EXPECT_LT((walked.back() - sliding(slide + 13)).norm(), 1e-6f);
}

}  // namespace
}  // namespace mocap
