#include "motion/core/local_linear_weights.h"

#include <gtest/gtest.h>

#include <numeric>

#include "motion/core/gaussian_kernel.h"

namespace mocap {
namespace {

// Σ cᵢ·x(i) for x(i) = a + b·i over the kernel's offsets.
double FitOfLine(const std::vector<float>& weights, double a, double b) {
  const int radius = static_cast<int>(weights.size()) / 2;
  double sum = 0.0;
  for (int i = -radius; i <= radius; ++i) sum += weights[i + radius] * (a + b * i);
  return sum;
}

TEST(LocalLinearWeightsTest, InsideTheDataIsTheKernelItself) {
  const std::vector<float> kernel = GaussianKernel(1.0f);
  std::vector<float> weights;
  LocalLinearWeights(kernel, -3, 3, &weights);
  ASSERT_EQ(weights.size(), kernel.size());
  for (size_t i = 0; i < kernel.size(); ++i) EXPECT_NEAR(weights[i], kernel[i], 1e-6f);
}

// Why the joint filter fits the pelvis where its taps run out: the end frame repeated for the taps
// beyond it puts a steadily moving point behind where it is; the line's weights do not.
TEST(LocalLinearWeightsTest, FollowsASteadyMotionWhereTheRepeatedEndLagsBehind) {
  for (float sigma : {1.0f, 2.0f}) {
    SCOPED_TRACE(sigma);
    const std::vector<float> kernel = GaussianKernel(sigma);
    const int radius = static_cast<int>(kernel.size()) / 2;
    for (int ahead : {0, 1, radius - 1}) {
      SCOPED_TRACE(ahead);
      std::vector<float> weights;
      LocalLinearWeights(kernel, -radius, ahead, &weights);
      EXPECT_NEAR(std::accumulate(weights.begin(), weights.end(), 0.0), 1.0, 1e-5);
      for (int i = ahead + 1; i <= radius; ++i) EXPECT_EQ(weights[i + radius], 0.0f) << "a frame not there yet";
      EXPECT_NEAR(FitOfLine(weights, 0.3, 0.05), 0.3, 1e-6);  // 5 cm a frame: at the frame's own place
      // The repeat: every tap past `ahead` reads the frame at `ahead`.
      double repeated = 0.0;
      for (int i = -radius; i <= radius; ++i) repeated += kernel[i + radius] * (0.3 + 0.05 * std::min(i, ahead));
      EXPECT_LT(repeated, 0.3 - (ahead == 0 ? 0.01 : 1e-5));  // at lag 0: a third of a frame or more behind
    }
  }
}

TEST(LocalLinearWeightsTest, OneFrameIsItsOwnFitAndRangesAreClampedToTheKernel) {
  const std::vector<float> kernel = GaussianKernel(1.0f);
  std::vector<float> weights;
  LocalLinearWeights(kernel, 0, 0, &weights);  // a segment's first frame at lag 0
  EXPECT_FLOAT_EQ(weights[3], 1.0f);
  EXPECT_FLOAT_EQ(std::accumulate(weights.begin(), weights.end(), 0.0f), 1.0f);
  LocalLinearWeights(kernel, -10, 10, &weights);
  for (size_t i = 0; i < kernel.size(); ++i) EXPECT_NEAR(weights[i], kernel[i], 1e-6f);
  LocalLinearWeights(kernel, -1, 1, &weights);  // both ends missing: symmetric, still the mean
  EXPECT_NEAR(FitOfLine(weights, 0.0, 1.0), 0.0, 1e-6);
  EXPECT_NEAR(weights[2], weights[4], 1e-6f);
}

}  // namespace
}  // namespace mocap
