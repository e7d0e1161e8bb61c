#include "motion/core/low_pass_kernel.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "motion/core/gaussian_kernel.h"

namespace mocap {
namespace {

// Amplitude the symmetric kernel passes of a sinusoid of `cycles` per frame.
double Response(const std::vector<float>& kernel, double cycles) {
  const int radius = static_cast<int>(kernel.size()) / 2;
  double sum = 0.0;
  for (int i = -radius; i <= radius; ++i) sum += kernel[i + radius] * std::cos(2.0 * std::numbers::pi * cycles * i);
  return std::abs(sum);
}

TEST(LowPassKernelTest, IsSymmetricSumsToOneAndSpansEightSigma) {
  for (float sigma : {0.5f, 1.0f, 1.5f, 2.0f}) {
    SCOPED_TRACE(sigma);
    const std::vector<float> kernel = LowPassKernel(sigma);
    ASSERT_EQ(kernel.size(), 2 * static_cast<size_t>(std::ceil(8.0f * sigma)) + 1);
    EXPECT_NEAR(std::accumulate(kernel.begin(), kernel.end(), 0.0), 1.0, 1e-5);
    for (size_t i = 0; i < kernel.size(); ++i) EXPECT_FLOAT_EQ(kernel[i], kernel[kernel.size() - 1 - i]);
    EXPECT_EQ(std::max_element(kernel.begin(), kernel.end()) - kernel.begin(), static_cast<long>(kernel.size() / 2));
  }
  EXPECT_EQ(LowPassKernel(0.0f), std::vector<float>{1.0f});
  EXPECT_EQ(LowPassKernel(-1.0f), std::vector<float>{1.0f});
}

// Why it replaced the Gaussian in a whole clip: at the same cutoff it keeps the
// slow motion as well and drops the jitter above (30 frames/s: 2 Hz is 1/15 cycle per frame).
TEST(LowPassKernelTest, KeepsTheMotionBelowTheGaussiansCutoffAndDropsTheJitterAbove) {
  const std::vector<float> sharp = LowPassKernel(1.0f), gaussian = GaussianKernel(1.0f);
  for (double hz : {0.5, 1.0, 2.0}) {
    SCOPED_TRACE(hz);
    EXPECT_NEAR(Response(sharp, hz / 30.0), 1.0, 0.05);
    EXPECT_GT(Response(sharp, hz / 30.0), Response(gaussian, hz / 30.0));
  }
  // About half the amplitude where the Gaussian passes half the power.
  EXPECT_NEAR(Response(sharp, kGaussianHalfPowerCycles), 0.5, 0.05);
  EXPECT_NEAR(Response(gaussian, kGaussianHalfPowerCycles), std::sqrt(0.5), 0.01);
  for (double hz : {6.0, 7.5, 10.0, 15.0}) {
    SCOPED_TRACE(hz);
    EXPECT_LT(Response(sharp, hz / 30.0), 0.05);
    EXPECT_LT(Response(sharp, hz / 30.0), 0.1 * Response(gaussian, hz / 30.0) + 1e-3);
  }
}

// The cutoff follows σ: twice the σ, half the frequency.
TEST(LowPassKernelTest, AWiderSigmaCutsLower) {
  const std::vector<float> one = LowPassKernel(1.0f), two = LowPassKernel(2.0f);
  EXPECT_NEAR(Response(two, 0.5 * kGaussianHalfPowerCycles), 0.5, 0.05);
  EXPECT_GT(Response(one, 3.0 / 30.0), 0.75);
  EXPECT_LT(Response(two, 3.0 / 30.0), 0.1);
}

}  // namespace
}  // namespace mocap
