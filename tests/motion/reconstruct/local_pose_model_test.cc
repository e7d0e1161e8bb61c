#include "motion/reconstruct/local_pose_model.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/QR>

namespace mocap {
namespace {

// Examples drawn from a known 3-D linear model in 20 features, plus a little noise.
Eigen::MatrixXf ExamplesFromModel(const Eigen::MatrixXf& basis, const Eigen::VectorXf& mean, int count, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  Eigen::MatrixXf examples(count, mean.size());
  for (int i = 0; i < count; ++i) {
    Eigen::VectorXf w(basis.cols());
    for (int c = 0; c < w.size(); ++c) w[c] = normal(random) * (3.0f - c);  // stddev 3, 2, 1
    Eigen::VectorXf noise(mean.size());
    for (int d = 0; d < noise.size(); ++d) noise[d] = 0.01f * normal(random);
    examples.row(i) = (mean + basis * w + noise).transpose();
  }
  return examples;
}

TEST(LocalPoseModelTest, RecoversTheSubspaceAndVariances) {
  std::mt19937 random(1);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  Eigen::MatrixXf raw(20, 3);
  for (int i = 0; i < raw.size(); ++i) raw.data()[i] = normal(random);
  const Eigen::MatrixXf basis =
      Eigen::HouseholderQR<Eigen::MatrixXf>(raw).householderQ() * Eigen::MatrixXf::Identity(20, 3);
  Eigen::VectorXf mean(20);
  for (int d = 0; d < 20; ++d) mean[d] = 0.1f * d;
  const Eigen::MatrixXf examples = ExamplesFromModel(basis, mean, 200, 2);

  auto model = FitLocalPoseModel(examples, 6);
  ASSERT_TRUE(model.ok()) << model.status();
  EXPECT_EQ(model->num_components(), 6);
  EXPECT_LT((model->mean - mean).norm(), 0.5f);
  // The first three components span the true subspace: projecting it loses almost nothing.
  const Eigen::MatrixXf top = model->basis.leftCols(3);
  EXPECT_GT((top.transpose() * basis).norm() / std::sqrt(3.0f), 0.999f);
  EXPECT_TRUE((model->basis.transpose() * model->basis).isIdentity(1e-4f));
  // Variances come largest first, near 9, 4, 1, then noise.
  EXPECT_NEAR(model->variances[0], 9.0f, 2.0f);
  EXPECT_NEAR(model->variances[2], 1.0f, 0.4f);
  EXPECT_LT(model->variances[3], 0.01f);
  for (int i = 1; i < 6; ++i) EXPECT_LE(model->variances[i], model->variances[i - 1]);
  // Reconstruction of an example from its projection.
  const Eigen::VectorXf example = examples.row(7).transpose();
  EXPECT_LT((model->Reconstruct(model->Project(example)) - example).norm(), 0.1f);
  // Prior energy: zero at the mean, larger along low-variance directions.
  EXPECT_FLOAT_EQ(model->PriorEnergy(Eigen::VectorXf::Zero(6)), 0.0f);
  Eigen::VectorXf along_first = Eigen::VectorXf::Zero(6), along_third = Eigen::VectorXf::Zero(6);
  along_first[0] = along_third[2] = 1.0f;
  EXPECT_LT(model->PriorEnergy(along_first), model->PriorEnergy(along_third));
}

TEST(LocalPoseModelTest, KeepsAtMostRowsMinusOneComponents) {
  Eigen::MatrixXf examples(3, 5);
  examples << 0, 1, 2, 3, 4, 1, 1, 1, 1, 1, 2, 0, 1, 0, 2;
  auto model = FitLocalPoseModel(examples, 6);
  ASSERT_TRUE(model.ok());
  EXPECT_EQ(model->num_components(), 2);
}

TEST(LocalPoseModelTest, RejectsBadInput) {
  EXPECT_EQ(FitLocalPoseModel(Eigen::MatrixXf::Zero(1, 4)).status().code(), absl::StatusCode::kInvalidArgument);
  Eigen::MatrixXf nan = Eigen::MatrixXf::Zero(5, 4);
  nan(2, 1) = std::nanf("");
  EXPECT_EQ(FitLocalPoseModel(nan).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(FitLocalPoseModel(Eigen::MatrixXf::Zero(5, 4), 0).status().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace mocap
