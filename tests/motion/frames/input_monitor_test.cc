// Floor calibration and the plausibility checks of motion/frames/input_monitor.h on synthetic
// wrists whose body, floor and sides are known (the real held-out clips: held_out_input_test.cc).
#include "motion/frames/input_monitor.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mocap {
namespace {

constexpr float kHeight = 1.7f;
constexpr double kRate = 30.0;

// A performer walking at `speed` m/s along `direction` (horizontal, unit), wrists hanging around
// the hang fraction and swinging, the hand in front of the body higher (the elbow bends on the
// forward swing), the left wrist on the left of the direction; `floor` added to y. `backwards`:
// the same body facing away from the direction.
std::vector<WristSample> Walk(int frames, float speed, Eigen::Vector3f direction, float floor = 0.0f,
                              bool swapped = false, bool backwards = false) {
  const Eigen::Vector3f facing = backwards ? Eigen::Vector3f(-direction) : direction;
  const Eigen::Vector3f left_side(facing.z(), 0.0f, -facing.x());  // up × facing
  std::vector<WristSample> samples;
  for (int f = 0; f < frames; ++f) {
    const float t = static_cast<float>(f / kRate);
    const Eigen::Vector3f middle = direction * speed * t + Eigen::Vector3f(0, kWristHangFraction * kHeight + floor, 0);
    const float swing = 0.2f * std::sin(2.0f * static_cast<float>(M_PI) * t);
    WristSample s;
    s.time = 5.0 + t;
    const Eigen::Vector3f rise(0.0f, 0.3f * std::abs(swing), 0.0f);
    s.left = middle + 0.2f * left_side + swing * facing + (swing > 0 ? rise : Eigen::Vector3f::Zero());
    s.right = middle - 0.2f * left_side - swing * facing + (swing < 0 ? rise : Eigen::Vector3f::Zero());
    if (swapped) std::swap(s.left, s.right);
    samples.push_back(s);
  }
  return samples;
}

struct Outcome {
  std::vector<MonitoredSample> ready;
  std::vector<InputWarning> warnings;
};

Outcome Monitor(const std::vector<WristSample>& samples, bool calibrate, FrameConvention convention = {}) {
  InputMonitor monitor(convention, calibrate, {.body_height = kHeight});
  Outcome out;
  for (size_t i = 0; i < samples.size(); ++i) monitor.Add(samples[i], static_cast<long>(i), &out.ready, &out.warnings);
  monitor.Finish(&out.ready, &out.warnings);
  return out;
}

bool Has(const Outcome& outcome, InputWarning::Kind kind) {
  for (const InputWarning& warning : outcome.warnings) {
    if (warning.kind == kind) return true;
  }
  return false;
}

TEST(InputMonitorTest, PlausibleInputPassesThroughUntouchedAndUnwarned) {
  const std::vector<WristSample> walk = Walk(150, 1.3f, {0, 0, -1});
  const Outcome outcome = Monitor(walk, false);
  EXPECT_TRUE(outcome.warnings.empty()) << outcome.warnings.front().message;
  ASSERT_EQ(outcome.ready.size(), walk.size());
  for (size_t i = 0; i < walk.size(); ++i) {
    EXPECT_EQ(outcome.ready[i].index, static_cast<long>(i));
    EXPECT_EQ(outcome.ready[i].sample.left, walk[i].left);
  }
}

TEST(InputMonitorTest, CalibrationHoldsTheFirstSecondAndPutsTheFloorAtZero) {
  const std::vector<WristSample> walk = Walk(90, 1.0f, {1, 0, 0}, /*floor=*/-1.45f);
  InputMonitor monitor({}, /*calibrate_floor=*/true, {.body_height = kHeight});
  std::vector<MonitoredSample> ready;
  std::vector<InputWarning> warnings;
  for (int i = 0; i <= 30; ++i) monitor.Add(walk[i], i, &ready, &warnings);  // 0..1 s: held
  EXPECT_TRUE(ready.empty());
  EXPECT_FALSE(monitor.window_done());
  monitor.Add(walk[31], 31, &ready, &warnings);
  ASSERT_TRUE(monitor.window_done());
  EXPECT_NEAR(monitor.calibrated_floor(), -1.45f, 0.01f);
  ASSERT_EQ(ready.size(), 32u);
  EXPECT_EQ(ready[0].index, 0);
  EXPECT_NEAR(ready[0].sample.left.y(), walk[0].left.y() + 1.45f, 0.01f);
  EXPECT_TRUE(warnings.empty());
}

TEST(InputMonitorTest, ShortInputIsCalibratedAtTheEnd) {
  const Outcome outcome = Monitor(Walk(10, 0.0f, {1, 0, 0}, 0.3f), true);
  ASSERT_EQ(outcome.ready.size(), 10u);
  EXPECT_NEAR(outcome.ready[0].sample.left.y(), kWristHangFraction * kHeight, 1e-3);
}

TEST(InputMonitorTest, MetresDeclaredAsCentimetresAreNamed) {
  std::vector<WristSample> walk = Walk(60, 1.2f, {0, 0, 1});
  for (WristSample& s : walk) {  // what a metre stream declared as cm becomes in native metres
    s.left *= 0.01f;
    s.right *= 0.01f;
  }
  const Outcome outcome = Monitor(walk, true, {LengthUnit::kCentimetre});
  ASSERT_TRUE(Has(outcome, InputWarning::Kind::kUnits));
  EXPECT_NE(outcome.warnings.front().message.find("metres declared as centimetres?"), std::string::npos)
      << outcome.warnings.front().message;
}

TEST(InputMonitorTest, WristsBelowOrFarAboveADeclaredFloorAreNamed) {
  Outcome below = Monitor(Walk(60, 1.2f, {0, 0, 1}, -1.6f), false);  // a head-origin space declared as floor-origin
  ASSERT_TRUE(Has(below, InputWarning::Kind::kBelowFloor));
  EXPECT_NE(below.warnings.front().message.find("wrists below the floor"), std::string::npos)
      << below.warnings.front().message;
  Outcome above = Monitor(Walk(60, 1.2f, {0, 0, 1}, +1.6f), false);  // the floor declared 1.6 m too low
  EXPECT_TRUE(Has(above, InputWarning::Kind::kAboveFloor));
  // A calibrated floor is right by construction: nothing to say.
  EXPECT_TRUE(Monitor(Walk(60, 1.2f, {0, 0, 1}, -1.6f), true).warnings.empty());
}

TEST(InputMonitorTest, SwappedSidesAreNamedOnlyWhileTheBodyTravels) {
  for (const Eigen::Vector3f& direction : {Eigen::Vector3f(0, 0, -1), Eigen::Vector3f(0.6f, 0, 0.8f)}) {
    EXPECT_FALSE(Has(Monitor(Walk(200, 1.3f, direction), false), InputWarning::Kind::kSwapped));
    const Outcome swapped = Monitor(Walk(200, 1.3f, direction, 0.0f, /*swapped=*/true), false);
    ASSERT_TRUE(Has(swapped, InputWarning::Kind::kSwapped));
    EXPECT_NE(swapped.warnings.front().message.find("left and right look swapped"), std::string::npos);
    EXPECT_EQ(swapped.warnings.size(), 1u);  // once per session
  }
  // Standing still, a swapped pair is just another pose.
  EXPECT_TRUE(Monitor(Walk(200, 0.0f, {0, 0, 1}, 0.0f, true), false).warnings.empty());
}

// Z-up samples (x, y, z) of a Y-up body: (x, −z, y), as Blender writes them.
std::vector<WristSample> AsZUp(std::vector<WristSample> samples) {
  for (WristSample& s : samples) {
    for (Eigen::Vector3f* p : {&s.left, &s.right}) *p = Eigen::Vector3f(p->x(), -p->z(), p->y());
  }
  return samples;
}

TEST(InputMonitorTest, ZUpDeclaredAsYUpIsNamed) {
  // Standing near the origin: along the declared up axis the wrists are at the floor, along +Z
  // where hanging hands are.
  std::vector<WristSample> near_origin = AsZUp(Walk(90, 0.0f, {0, 0, 1}));
  for (WristSample& s : near_origin) s.left.y() += 0.25f, s.right.y() += 0.25f;
  const Outcome standing = Monitor(near_origin, false);
  ASSERT_TRUE(Has(standing, InputWarning::Kind::kUpAxis));
  EXPECT_FALSE(Has(standing, InputWarning::Kind::kBelowFloor));
  EXPECT_NE(standing.warnings.front().message.find("+Z up declared as +Y up?"), std::string::npos)
      << standing.warnings.front().message;
  // Where the wrists swing below 0 on "up": a floor warning, naming +Z as well.
  const Outcome below = Monitor(AsZUp(Walk(90, 0.0f, {0, 0, 1})), false);
  ASSERT_TRUE(Has(below, InputWarning::Kind::kBelowFloor));
  EXPECT_NE(below.warnings.front().message.find("or +Z up declared as +Y up"), std::string::npos)
      << below.warnings.front().message;
  // Walking along the world's Y with a calibrated floor: the wrists sink metres along "up".
  const Outcome walking = Monitor(AsZUp(Walk(200, 1.3f, {0, 0, 1})), true);
  ASSERT_TRUE(Has(walking, InputWarning::Kind::kUpAxis));
  EXPECT_NE(walking.warnings.back().message.find("sank"), std::string::npos) << walking.warnings.back().message;
  EXPECT_NE(walking.warnings.back().message.find("--up +Z"), std::string::npos) << walking.warnings.back().message;
  // Declared right (the samples reach the monitor in native axes), nothing.
  EXPECT_TRUE(Monitor(Walk(200, 1.3f, {0, 0, 1}), true).warnings.empty());
}

TEST(InputMonitorTest, WalkingBackwardsIsNoSwap) {
  // The left wrist is on the right of the travel, but the hand rising on its swing is the one
  // behind along the travel: the body faces away from where it goes.
  EXPECT_TRUE(Monitor(Walk(300, 0.8f, {0, 0, -1}, 0.0f, false, /*backwards=*/true), false).warnings.empty());
  // Without that rise (hands that do not swing) nothing tells a backwards walk from a swap: no
  // alarm either.
  std::vector<WristSample> stiff = Walk(300, 0.8f, {0, 0, -1}, 0.0f, false, true);
  for (WristSample& s : stiff) s.left.y() = s.right.y() = kWristHangFraction * kHeight;
  EXPECT_TRUE(Monitor(stiff, false).warnings.empty());
  // At a running pace nobody goes backwards: swapped sides are named whatever the hands do.
  std::vector<WristSample> run = Walk(300, 3.0f, {0, 0, -1}, 0.0f, /*swapped=*/true);
  for (WristSample& s : run) s.left.y() = s.right.y() = kWristHangFraction * kHeight;
  EXPECT_TRUE(Has(Monitor(run, false), InputWarning::Kind::kSwapped));
}

TEST(WristSeparationProblemTest, NamesTheUnitThatMakesTheWristsABodys) {
  EXPECT_FALSE(WristSeparationProblem(1.8, LengthUnit::kMetre));
  const std::optional<std::string> cm = WristSeparationProblem(180.0, LengthUnit::kMetre);
  ASSERT_TRUE(cm);
  EXPECT_NE(cm->find("wrist samples 180 units apart"), std::string::npos) << *cm;
  EXPECT_NE(cm->find("centimetres"), std::string::npos) << *cm;
  EXPECT_NE(cm->find(" declared as metres?"), std::string::npos) << *cm;
  const std::optional<std::string> mm =
      WristSeparationProblem(0.45 * 1000 * 0.01, LengthUnit::kCentimetre);  // 450 "cm"
  ASSERT_TRUE(mm);
  EXPECT_NE(mm->find(": millimetres declared as centimetres?"), std::string::npos) << *mm;
  // Nothing a unit explains: no guess.
  const std::optional<std::string> far = WristSeparationProblem(5000.0, LengthUnit::kMetre);
  ASSERT_TRUE(far);
  EXPECT_EQ(far->find("declared as"), std::string::npos) << *far;
}

}  // namespace
}  // namespace mocap
