#include "motion/reconstruct/wrist_smoother.h"

#include <cmath>

#include <gtest/gtest.h>

namespace mocap {
namespace {

TEST(WristSmootherTest, ExponentialSmoothingOfAStep) {
  WristSmoother smoother({.smoothing = 0.5f}, 1.0 / 30.0);
  const Eigen::Vector3f zero = Eigen::Vector3f::Zero(), one(1.0f, 2.0f, -1.0f);
  SmoothedWrists out = smoother.Push(zero, zero);
  EXPECT_EQ(out.velocity[0], Eigen::Vector3f::Zero());
  for (int n = 1; n <= 5; ++n) {
    out = smoother.Push(one, -one);
    const float expected = 1.0f - std::pow(0.5f, n);  // x̃ = s·x + (1−s)·x̃_prev
    EXPECT_TRUE(out.position[0].isApprox(expected * one, 1e-6f)) << n;
    EXPECT_TRUE(out.position[1].isApprox(-expected * one, 1e-6f)) << n;
    const float previous = 1.0f - std::pow(0.5f, n - 1);
    EXPECT_TRUE(out.velocity[0].isApprox((expected - previous) * 30.0f * one, 1e-5f)) << n;
  }
}

TEST(WristSmootherTest, NoSmoothingPassesSamplesThrough) {
  WristSmoother smoother({.smoothing = 1.0f}, 0.1);
  smoother.Push(Eigen::Vector3f(0, 1, 0), Eigen::Vector3f(0, 1, 0));
  const SmoothedWrists out = smoother.Push(Eigen::Vector3f(0.5f, 1, 0), Eigen::Vector3f(0, 1, 0.2f));
  EXPECT_TRUE(out.position[0].isApprox(Eigen::Vector3f(0.5f, 1, 0)));
  EXPECT_TRUE(out.velocity[0].isApprox(Eigen::Vector3f(5.0f, 0, 0), 1e-5f));
  EXPECT_TRUE(out.velocity[1].isApprox(Eigen::Vector3f(0, 0, 2.0f), 1e-5f));
  smoother.Reset();
  EXPECT_EQ(smoother.Push(Eigen::Vector3f::Ones(), Eigen::Vector3f::Ones()).velocity[1], Eigen::Vector3f::Zero());
}

}  // namespace
}  // namespace mocap
