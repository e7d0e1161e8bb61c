#include "motion/reconstruct/wrist_feature_index.h"

#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

namespace mocap {
namespace {

std::vector<FrameFeatures> RandomFrames(int count, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<float> normal(0.0f, 0.3f);
  std::vector<FrameFeatures> frames(count);
  for (FrameFeatures& f : frames) {
    for (int side = 0; side < 2; ++side) {
      for (int axis = 0; axis < 3; ++axis) {
        f.wrist_position[side][axis] = normal(random);
        f.wrist_velocity[side][axis] = 3.0f * normal(random);
      }
    }
  }
  return frames;
}

TEST(WristFeatureIndexTest, FeatureFoldsTheEquation2Weights) {
  FrameFeatures a{}, b{};
  a.wrist_position[0][1] = 1.0f;  // position differs by 1 m on one axis
  b.wrist_velocity[1][2] = 1.0f;  // velocity differs by 1 m/s on one axis
  float fa[kWristFeatureDims], fb[kWristFeatureDims], zero[kWristFeatureDims];
  WristFeature(a, {}, fa);
  WristFeature(b, {}, fb);
  WristFeature(FrameFeatures{}, {}, zero);
  auto squared = [](const float* x, const float* y) {
    float s = 0;
    for (int d = 0; d < kWristFeatureDims; ++d) s += (x[d] - y[d]) * (x[d] - y[d]);
    return s;
  };
  EXPECT_NEAR(squared(fa, zero), 0.8f, 1e-6f);  // α = 0.8
  EXPECT_NEAR(squared(fb, zero), 0.2f, 1e-6f);  // 1 − α
}

TEST(WristFeatureIndexTest, KdTreeMatchesBruteForceExactly) {
  const std::vector<FrameFeatures> frames = RandomFrames(20000, 7);
  WristFeatureIndex index;
  ASSERT_TRUE(index.Build(frames).ok());
  const std::vector<float> points = WristFeatures(frames);
  const std::vector<FrameFeatures> queries = RandomFrames(20, 8);
  for (const FrameFeatures& q : queries) {
    float feature[kWristFeatureDims];
    WristFeature(q, {}, feature);
    auto fast = index.Search(feature, 1000);
    auto exact = BruteForceNearest(points, kWristFeatureDims, feature, 1000);
    ASSERT_TRUE(fast.ok() && exact.ok());
    ASSERT_EQ(fast->size(), 1000u);
    for (size_t i = 1; i < fast->size(); ++i) EXPECT_LE((*fast)[i - 1].distance, (*fast)[i].distance);
    // Same k-th distance (ties may swap rows).
    EXPECT_NEAR(fast->back().distance, exact->back().distance, 1e-5f);
    EXPECT_NEAR(fast->front().distance, exact->front().distance, 1e-6f);
  }
}

TEST(WristFeatureIndexTest, RejectsBadQueries) {
  WristFeatureIndex index;
  float feature[kWristFeatureDims] = {};
  EXPECT_EQ(index.Search(feature, 5).status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ(index.Build({}).code(), absl::StatusCode::kFailedPrecondition);
  ASSERT_TRUE(index.Build(RandomFrames(100, 1)).ok());
  EXPECT_EQ(index.Search(feature, 0).status().code(), absl::StatusCode::kInvalidArgument);
  feature[3] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(index.Search(feature, 5).status().code(), absl::StatusCode::kInvalidArgument);
  feature[3] = 0.0f;
  auto all = index.Search(feature, 500);  // more than the index holds
  ASSERT_TRUE(all.ok());
  EXPECT_EQ(all->size(), 100u);
}

}  // namespace
}  // namespace mocap
