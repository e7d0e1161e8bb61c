#include "motion/similarity/pose_distance.h"
#include "tests/support/rotation_checks.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

namespace mocap {
namespace {

using testing::kPi;

constexpr int kPointsPerGroup = 5;
constexpr int kPosePoints = kNumBodyGroups * kPointsPerGroup;

// A deterministic, non-degenerate cloud of `frames` poses (kPosePoints points each), roughly the
// size of a body in body scales: x, z in [-0.6, 0.6], y in [-1, 1].
std::vector<float> MakeCloud(int frames = 1) {
  std::vector<float> cloud;
  for (int i = 0; i < frames * kPosePoints; ++i) {
    cloud.push_back(0.6f * std::sin(1.3f * i + 0.2f));
    cloud.push_back(std::cos(0.7f * i + 0.5f));
    cloud.push_back(0.6f * std::sin(2.1f * i + 1.0f));
  }
  return cloud;
}

int NumPoints(const std::vector<float>& cloud) { return static_cast<int>(cloud.size()) / 3; }

// `rotation` * p + `translation` for every point.
std::vector<float> Transformed(const std::vector<float>& cloud, const Eigen::Matrix3f& rotation,
                               const Eigen::Vector3f& translation) {
  std::vector<float> out(cloud.size());
  for (int i = 0; i < NumPoints(cloud); ++i) {
    const Eigen::Vector3f p =
        rotation * Eigen::Vector3f(cloud[3 * i], cloud[3 * i + 1], cloud[3 * i + 2]) + translation;
    out[3 * i] = p.x();
    out[3 * i + 1] = p.y();
    out[3 * i + 2] = p.z();
  }
  return out;
}

Eigen::Matrix3f RotationAbout(const Eigen::Vector3f& axis, float angle) {
  return Eigen::AngleAxisf(angle, axis.normalized()).toRotationMatrix();
}

// Adds `delta` to every point of group `group` (in every frame of the cloud).
std::vector<float> ShiftGroup(std::vector<float> cloud, BodyGroup group, const Eigen::Vector3f& delta) {
  for (int i = 0; i < NumPoints(cloud); ++i) {
    if ((i % kPosePoints) / kPointsPerGroup != static_cast<int>(group)) continue;
    for (int a = 0; a < 3; ++a) cloud[3 * i + a] += delta[a];
  }
  return cloud;
}

float AngleDifference(float a, float b) { return std::atan2(std::sin(a - b), std::cos(a - b)); }

PoseDistance Compare(const std::vector<float>& query, const std::vector<float>& candidate,
                     const GroupWeights& weights = GroupWeights::Uniform()) {
  EXPECT_EQ(query.size(), candidate.size());
  return ComparePoses(query.data(), candidate.data(), NumPoints(query), kPointsPerGroup, weights);
}

TEST(PoseDistanceTest, IdenticalCloudsGiveZero) {
  const std::vector<float> cloud = MakeCloud();
  const PoseDistance d = Compare(cloud, cloud);
  EXPECT_NEAR(d.total, 0.0f, 1e-5f);
  for (int g = 0; g < kNumBodyGroups; ++g) EXPECT_NEAR(d.per_group[g], 0.0f, 1e-5f) << BodyGroupName(BodyGroup(g));
  EXPECT_NEAR(d.alignment.yaw, 0.0f, 1e-5f);
  EXPECT_NEAR(d.alignment.x, 0.0f, 1e-5f);
  EXPECT_NEAR(d.alignment.z, 0.0f, 1e-5f);
}

TEST(PoseDistanceTest, GroundMotionIsRemovedAndRecovered) {
  const std::vector<float> candidate = MakeCloud();
  for (float yaw : {0.3f, -1.2f, 2.5f, -3.0f, 3.1f}) {
    for (const Eigen::Vector3f& t : {Eigen::Vector3f(0.7f, 0.0f, -1.4f), Eigen::Vector3f(-25.0f, 0.0f, 12.0f)}) {
      SCOPED_TRACE(::testing::Message() << "yaw " << yaw << " translation " << t.transpose());
      // The query is the candidate turned by `yaw` about +Y and moved on the ground: the alignment
      // maps the candidate onto the query.
      const std::vector<float> query = Transformed(candidate, RotationAbout(Eigen::Vector3f::UnitY(), yaw), t);
      const PoseDistance d = Compare(query, candidate);
      EXPECT_NEAR(d.total, 0.0f, 1e-3f);
      EXPECT_NEAR(AngleDifference(d.alignment.yaw, yaw), 0.0f, 1e-4f);
      EXPECT_NEAR(d.alignment.x, t.x(), 1e-4f * std::max(1.0f, std::abs(t.x())));
      EXPECT_NEAR(d.alignment.z, t.z(), 1e-4f * std::max(1.0f, std::abs(t.z())));
    }
  }
}

TEST(PoseDistanceTest, OneAlignmentServesAWindowOfFrames) {
  const std::vector<float> candidate = MakeCloud(3);  // three frames in a row
  const float yaw = 1.1f;
  const Eigen::Vector3f t(0.4f, 0.0f, 0.9f);
  const std::vector<float> query = Transformed(candidate, RotationAbout(Eigen::Vector3f::UnitY(), yaw), t);
  const PoseDistance d = Compare(query, candidate);
  EXPECT_NEAR(d.total, 0.0f, 1e-3f);
  EXPECT_NEAR(AngleDifference(d.alignment.yaw, yaw), 0.0f, 1e-4f);
  EXPECT_NEAR(d.alignment.x, t.x(), 1e-4f);
  EXPECT_NEAR(d.alignment.z, t.z(), 1e-4f);

  // Each frame turned by its own yaw is not one rigid ground motion: the distance stays.
  std::vector<float> twisted = candidate;
  for (int frame = 0; frame < 3; ++frame) {
    const std::vector<float> one(candidate.begin() + 3 * kPosePoints * frame,
                                 candidate.begin() + 3 * kPosePoints * (frame + 1));
    const std::vector<float> turned =
        Transformed(one, RotationAbout(Eigen::Vector3f::UnitY(), 0.5f * frame), Eigen::Vector3f::Zero());
    std::copy(turned.begin(), turned.end(), twisted.begin() + 3 * kPosePoints * frame);
  }
  EXPECT_GT(Compare(twisted, candidate).total, 1.0f);
}

TEST(PoseDistanceTest, RotationAboutAHorizontalAxisIsNotRemoved) {
  const std::vector<float> candidate = MakeCloud();
  const PoseDistance moved_on_ground =
      Compare(Transformed(candidate, RotationAbout(Eigen::Vector3f::UnitY(), 0.3f), {1, 0, 1}), candidate);
  for (const Eigen::Vector3f& axis : {Eigen::Vector3f(1, 0, 0), Eigen::Vector3f(0, 0, 1), Eigen::Vector3f(1, 0, 1)}) {
    SCOPED_TRACE(::testing::Message() << "axis " << axis.transpose());
    const PoseDistance tilted =
        Compare(Transformed(candidate, RotationAbout(axis, 0.3f), Eigen::Vector3f::Zero()), candidate);
    // A 0.3 rad tilt moves points ~0.3 body scales each: tens of times the numerical noise.
    EXPECT_GT(tilted.total, 1.0f);
    EXPECT_GT(tilted.total, 100.0f * moved_on_ground.total + 1e-3f);
  }
  // A vertical shift is not a ground motion either: every point is off by the shift.
  const PoseDistance lifted = Compare(Transformed(candidate, Eigen::Matrix3f::Identity(), {0, 0.1f, 0}), candidate);
  EXPECT_NEAR(lifted.total, 0.1f * kPosePoints, 1e-4f);
}

TEST(PoseDistanceTest, PerGroupDistanceIsTheSumOfPointDistances) {
  // A vertical shift of one group leaves the ground alignment at the identity (same centroids on
  // the ground, same cross terms), so each of its points is exactly 0.1 off.
  const std::vector<float> query = MakeCloud();
  const std::vector<float> candidate = ShiftGroup(query, BodyGroup::kHead, {0, 0.1f, 0});
  const PoseDistance d = Compare(query, candidate);
  EXPECT_NEAR(d.alignment.yaw, 0.0f, 1e-5f);
  for (int g = 0; g < kNumBodyGroups; ++g) {
    SCOPED_TRACE(BodyGroupName(BodyGroup(g)));
    EXPECT_NEAR(d.per_group[g], g == static_cast<int>(BodyGroup::kHead) ? 0.1f * kPointsPerGroup : 0.0f, 1e-5f);
  }
  EXPECT_NEAR(d.total, 0.1f * kPointsPerGroup, 1e-5f);
}

TEST(PoseDistanceTest, TotalIsTheWeightedSumOfGroupDistances) {
  const std::vector<float> query = MakeCloud(2);
  std::vector<float> candidate = Transformed(query, RotationAbout(Eigen::Vector3f::UnitY(), 0.7f), {0.3f, 0, -0.2f});
  for (int i = 0; i < NumPoints(candidate); ++i) candidate[3 * i + (i % 3)] += 0.05f * std::sin(5.0f * i);
  GroupWeights weights;
  weights.weight = {0.3f, 1.7f, 0.9f, 2.2f, 0.4f, 1.1f};
  for (const GroupWeights& w :
       {GroupWeights::Uniform(), GroupWeights::Locomotion(), GroupWeights::UpperBody(), weights}) {
    const PoseDistance d = Compare(query, candidate, w);
    float sum = 0.0f;
    for (int g = 0; g < kNumBodyGroups; ++g) {
      EXPECT_GT(d.per_group[g], 0.0f);
      sum += w.weight[g] * d.per_group[g];
    }
    EXPECT_GT(d.total, 0.0f);
    EXPECT_NEAR(d.total, sum, 1e-5f * sum);
  }
}

TEST(PoseDistanceTest, SymmetricWithTheInverseAlignment) {
  const std::vector<float> a = MakeCloud();
  std::vector<float> b = Transformed(a, RotationAbout(Eigen::Vector3f::UnitY(), -0.8f), {0.5f, 0, 0.25f});
  for (int i = 0; i < NumPoints(b); ++i) b[3 * i + 1] += 0.03f * std::cos(3.0f * i);
  const PoseDistance ab = Compare(a, b, GroupWeights::Locomotion());
  const PoseDistance ba = Compare(b, a, GroupWeights::Locomotion());
  EXPECT_GT(ab.total, 0.01f);
  EXPECT_NEAR(ab.total, ba.total, 1e-4f * ab.total);
  EXPECT_NEAR(AngleDifference(ab.alignment.yaw, -ba.alignment.yaw), 0.0f, 1e-4f);
}

TEST(PoseDistanceTest, ZeroWeightGroupIsIgnoredByTheAlignmentToo) {
  const std::vector<float> base = MakeCloud();
  // The candidate's head is somewhere else entirely; with the head weighing nothing, the rest of
  // the body aligns exactly.
  const std::vector<float> candidate = ShiftGroup(base, BodyGroup::kHead, {2.0f, 0.5f, -3.0f});
  const float yaw = -2.2f;
  const Eigen::Vector3f t(1.5f, 0.0f, 0.5f);
  const std::vector<float> query = Transformed(base, RotationAbout(Eigen::Vector3f::UnitY(), yaw), t);
  GroupWeights weights;
  weights.weight[static_cast<int>(BodyGroup::kHead)] = 0.0f;
  const PoseDistance d = Compare(query, candidate, weights);
  EXPECT_NEAR(d.total, 0.0f, 1e-3f);
  EXPECT_NEAR(AngleDifference(d.alignment.yaw, yaw), 0.0f, 1e-4f);
  EXPECT_NEAR(d.alignment.x, t.x(), 1e-4f);
  EXPECT_NEAR(d.alignment.z, t.z(), 1e-4f);
  EXPECT_GT(d.per_group[static_cast<int>(BodyGroup::kHead)], 1.0f);  // still reported
  // With uniform weights the head pulls the alignment off and the distance is large.
  EXPECT_GT(Compare(query, candidate).total, 1.0f);
}

TEST(PoseDistanceTest, WeightPresetsChangeTheRanking) {
  const std::vector<float> query = MakeCloud();
  // Same-sized differences: one candidate in the legs only, one in the arms only.
  const Eigen::Vector3f bend(0.0f, 0.15f, 0.0f);
  const std::vector<float> legs_differ =
      ShiftGroup(ShiftGroup(query, BodyGroup::kLeftLeg, bend), BodyGroup::kRightLeg, bend);
  const std::vector<float> arms_differ =
      ShiftGroup(ShiftGroup(query, BodyGroup::kLeftArm, bend), BodyGroup::kRightArm, bend);

  const float legs_locomotion = Compare(query, legs_differ, GroupWeights::Locomotion()).total;
  const float legs_upper = Compare(query, legs_differ, GroupWeights::UpperBody()).total;
  const float arms_locomotion = Compare(query, arms_differ, GroupWeights::Locomotion()).total;
  const float arms_upper = Compare(query, arms_differ, GroupWeights::UpperBody()).total;
  const float legs_uniform = Compare(query, legs_differ, GroupWeights::Uniform()).total;
  const float arms_uniform = Compare(query, arms_differ, GroupWeights::Uniform()).total;

  EXPECT_LT(legs_upper, legs_locomotion);  // legs count less for the upper body
  EXPECT_LT(arms_locomotion, arms_upper);
  EXPECT_LT(arms_locomotion, legs_locomotion);  // locomotion: the arm-only difference is closer
  EXPECT_LT(legs_upper, arms_upper);            // upper body: the leg-only difference is closer
  EXPECT_NEAR(legs_uniform, arms_uniform, 1e-4f);
}

}  // namespace
}  // namespace mocap
