// The performer's size as a stream learns it (motion/reconstruct/body_sizer.h): off, it is the
// uniform scale the session always applied; online, input within the database's reach changes
// nothing, input beyond it grows the body by the reach's ratio, eased in over a quarter of a second, with the
// hands' midpoint kept in place however far from the origin the performer stands; each frame goes
// back through the map its input went through.
#include "motion/reconstruct/body_sizer.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "tests/support/synthetic_database.h"

namespace mocap {
namespace {

constexpr WristReach kDatabase{.separation = 1.2f, .height = 1.9f};

// `seconds` of 60 Hz input: hands `apart` metres apart at `height`, swinging a little, standing
// `at` on the ground plane.
std::vector<WristSample> Held(float apart, float height, double seconds, Eigen::Vector3f at = Eigen::Vector3f::Zero()) {
  std::vector<WristSample> samples;
  for (int i = 0; i < static_cast<int>(seconds * 60); ++i) {
    const float swing = 0.02f * std::sin(0.3f * static_cast<float>(i));
    samples.push_back({.time = i / 60.0,
                       .left = at + Eigen::Vector3f(0.5f * apart, height + swing, 0.1f),
                       .right = at + Eigen::Vector3f(-0.5f * apart, height - swing, 0.1f)});
  }
  return samples;
}

TEST(BodySizerTest, OffItIsAUniformScaleAboutTheOrigin) {
  BodySizer sizer(kDatabase, 1.25f);
  for (const WristSample& s : Held(1.8f, 2.2f, 3.0, Eigen::Vector3f(5, 0, -2))) {
    const WristSample d = sizer.ToDatabase(s);
    EXPECT_TRUE(d.left.isApprox(s.left / 1.25f));
    EXPECT_TRUE(d.right.isApprox(s.right / 1.25f));
  }
  EXPECT_EQ(sizer.map().scale, 1.25f);  // far beyond the reach, but not online
  EXPECT_EQ(sizer.resizes(), 0);
  const Eigen::Vector3f p(1, 2, 3);
  EXPECT_TRUE(sizer.map().ToPerformer(sizer.map().ToDatabase(p)).isApprox(p));
}

TEST(BodySizerTest, OnlineInputWithinTheReachChangesNothing) {
  BodySizer sizer(kDatabase, 1.0f, {.online = true});
  for (const WristSample& s : Held(0.9f, 1.5f, 5.0, Eigen::Vector3f(5, 0, -2))) {
    const WristSample d = sizer.ToDatabase(s);
    EXPECT_EQ(d.left, s.left);
    EXPECT_EQ(d.right, s.right);
  }
  EXPECT_EQ(sizer.resizes(), 0);
  EXPECT_EQ(sizer.map(), SizeMap{});
}

TEST(BodySizerTest, OnlineTheBodyGrowsByTheReachsRatioEasedInWithTheHandsKeptInPlace) {
  const BodySizerOptions options{.online = true};
  BodySizer sizer(kDatabase, 1.0f, options);
  const Eigen::Vector3f at(5, 0, -2);  // five metres from the origin
  const std::vector<WristSample> input = Held(1.5f, 1.4f, 4.0, at);
  float previous_scale = 1.0f;
  Eigen::Vector3f previous_centre = Eigen::Vector3f::Zero();
  double grew_from = -1, grew_until = -1;
  for (size_t i = 0; i < input.size(); ++i) {
    const WristSample d = sizer.ToDatabase(input[i]);
    const float scale = sizer.map().scale;
    EXPECT_GE(scale, previous_scale);
    // A 60 Hz step of the ease of a 25% change: 1.7% per sample over a quarter second, never a pop.
    EXPECT_LE(scale - previous_scale, 0.25f / static_cast<float>(60.0 * options.ramp_seconds) + 1e-4f)
        << "sample " << i;
    if (scale > 1.0f && grew_from < 0) grew_from = input[i].time;
    if (scale > previous_scale) grew_until = input[i].time;
    const Eigen::Vector3f centre = 0.5f * (d.left + d.right);
    if (i > 0) {  // the database-space hands move no more than the performer's do (2 cm swing)
      EXPECT_LT((centre - previous_centre).cwiseProduct(Eigen::Vector3f(1, 0, 1)).norm(), 1e-3f) << "sample " << i;
    }
    previous_scale = scale;
    previous_centre = centre;
  }
  EXPECT_NEAR(sizer.map().scale, 1.5f / 1.2f, 0.01f);
  EXPECT_EQ(sizer.resizes(), 1);
  EXPECT_NEAR(grew_from, options.reach.min_seconds, 0.02);  // once the input has lasted long enough
  EXPECT_NEAR(grew_until - grew_from, options.ramp_seconds, 0.05);
  // The frames go back where the performer is.
  const WristSample last = sizer.ToDatabase({.time = 4.1, .left = at, .right = at});
  EXPECT_TRUE(sizer.map().ToPerformer(last.left).isApprox(at));
}

TEST(BodySizerTest, EachFrameGoesBackThroughTheMapItsInputWentThrough) {
  BodySizer sizer(kDatabase, 1.0f, {.online = true});
  const std::vector<WristSample> input = Held(1.5f, 1.4f, 3.0);
  std::vector<SizeMap> used;
  for (const WristSample& s : input) {
    sizer.ToDatabase(s);
    used.push_back(sizer.map());
  }
  // Frames leave later, in order, between the samples' times.
  for (size_t i = 0; i + 1 < input.size(); i += 7) {
    EXPECT_EQ(sizer.MapAt(input[i].time), used[i]) << i;
    EXPECT_EQ(sizer.MapAt(0.5 * (input[i].time + input[i + 1].time)), used[i]) << i;
  }
}

TEST(BodySizerTest, ASampleOutOfOrderIsNeitherCountedNorAStep) {
  BodySizer sizer(kDatabase, 1.0f, {.online = true});
  std::vector<WristSample> input = Held(1.5f, 1.4f, 3.0);
  for (size_t i = 0; i < 90; ++i) sizer.ToDatabase(input[i]);
  const SizeMap before = sizer.map();
  WristSample stale = input[10];
  stale.left.x() = 40.0f;
  sizer.ToDatabase(stale);
  EXPECT_EQ(sizer.map(), before);
  EXPECT_EQ(sizer.MapAt(input[89].time), before);
}

TEST(BodySizerTest, ASessionSizedOnlineIsTheOfflineSessionWhenTheInputIsWithinReach) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 90);
  const std::vector<WristSample> samples = testing::WristSamplesOf(setup);
  ReconstructionOptions options;
  options.mode = StreamMode::kFixedLag;
  options.lag = 5;
  const absl::StatusOr<std::vector<ReconstructedFrame>> plain = ReconstructOffline(setup.database, options, samples);
  ASSERT_TRUE(plain.ok()) << plain.status();
  BodySizer sizer(setup.database->wrist_reach(), 1.0f, {.online = true});
  std::vector<SizeMap> maps;
  const absl::StatusOr<std::vector<ReconstructedFrame>> sized =
      ReconstructSized(setup.database, options, samples, sizer, &maps);
  ASSERT_TRUE(sized.ok()) << sized.status();
  ASSERT_EQ(sized->size(), plain->size());
  ASSERT_EQ(maps.size(), sized->size());
  for (size_t i = 0; i < sized->size(); ++i) {
    EXPECT_EQ((*sized)[i].pose.root_position, (*plain)[i].pose.root_position) << i;
    EXPECT_EQ(maps[i], SizeMap{}) << i;
  }
}

}  // namespace
}  // namespace mocap
