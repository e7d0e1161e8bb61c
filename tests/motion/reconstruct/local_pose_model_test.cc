#include "motion/reconstruct/local_pose_model.h"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>
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

// The model keeps only the largest eigenpairs (LAPACK's dstemr after Eigen's tridiagonalisation):
// they must be the full solver's, to rounding, each column up to its sign; also where the
// examples are degenerate (all alike, a repeated variance, fewer examples than features, one feature).
void ExpectTheFullSolversLargestEigenpairs(const Eigen::MatrixXf& examples, int components) {
  auto model = FitLocalPoseModel(examples, components);
  ASSERT_TRUE(model.ok()) << model.status();
  const Eigen::MatrixXd x = examples.cast<double>();
  const Eigen::MatrixXd centred = x.rowwise() - x.colwise().mean();
  const Eigen::MatrixXd covariance = centred.transpose() * centred / static_cast<double>(x.rows() - 1);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> full(covariance);
  const int n = static_cast<int>(covariance.rows());
  ASSERT_EQ(model->num_components(), std::min<int>({components, static_cast<int>(x.rows()) - 1, n}));
  const double scale = std::max(1.0, full.eigenvalues()(n - 1));
  for (int c = 0; c < model->num_components(); ++c) {
    EXPECT_NEAR(model->variances[c], full.eigenvalues()(n - 1 - c), 1e-5 * scale) << "component " << c;
  }
  EXPECT_TRUE((model->basis.transpose() * model->basis).isIdentity(1e-4f));
  // Each column is an eigenvector of its variance (this holds within a repeated variance too).
  const Eigen::MatrixXf residual =
      covariance.cast<float>() * model->basis - model->basis * model->variances.asDiagonal();
  EXPECT_LT(residual.norm(), 1e-4f * static_cast<float>(scale));
  for (int c = 0; c < model->num_components(); ++c) {
    const double gap_below = c + 1 < n ? full.eigenvalues()(n - 1 - c) - full.eigenvalues()(n - 2 - c) : 1.0;
    const double gap_above = c > 0 ? full.eigenvalues()(n - c) - full.eigenvalues()(n - 1 - c) : 1.0;
    if (std::min(gap_below, gap_above) < 1e-3 * scale) continue;  // the eigenvector is not unique
    const Eigen::VectorXf expected = full.eigenvectors().col(n - 1 - c).cast<float>();
    const Eigen::VectorXf got = model->basis.col(c);
    EXPECT_LT(std::min((got - expected).norm(), (got + expected).norm()), 1e-4f) << "component " << c;
  }
}

TEST(LocalPoseModelTest, KeepsTheFullSolversLargestEigenpairs) {
  std::mt19937 random(3);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  Eigen::MatrixXf poses(200, 63);  // K2 examples of a 21-joint rig's features, correlated as poses are
  const Eigen::MatrixXf mixing = Eigen::MatrixXf::NullaryExpr(12, 63, [&] { return normal(random); });
  const Eigen::MatrixXf causes = Eigen::MatrixXf::NullaryExpr(200, 12, [&] { return normal(random); });
  poses = causes * mixing + 0.05f * Eigen::MatrixXf::NullaryExpr(200, 63, [&] { return normal(random); });
  ExpectTheFullSolversLargestEigenpairs(poses, 6);
  ExpectTheFullSolversLargestEigenpairs(poses.topRows(20), 6);
  ExpectTheFullSolversLargestEigenpairs(poses.topRows(4), 6);               // three components: rows − 1
  ExpectTheFullSolversLargestEigenpairs(poses.leftCols(1), 6);              // one feature: one component
  ExpectTheFullSolversLargestEigenpairs(Eigen::MatrixXf::Ones(50, 63), 6);  // all alike: no variance at all
  Eigen::MatrixXf isotropic(400, 8);                                        // two equal variances on top
  for (int i = 0; i < isotropic.rows(); ++i) {
    for (int d = 0; d < isotropic.cols(); ++d)
      isotropic(i, d) = (d < 2 ? 3.0f : 0.5f) * (i % 2 ? 1.0f : -1.0f) * (d == i % 8 ? 1.0f : 0.0f);
  }
  ExpectTheFullSolversLargestEigenpairs(isotropic, 6);
}

TEST(LocalPoseModelTest, EqualWeightsAreThePlainFit) {
  std::mt19937 random(4);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  const Eigen::MatrixXf examples = Eigen::MatrixXf::NullaryExpr(50, 12, [&] { return normal(random); });
  auto plain = FitLocalPoseModel(examples, 4);
  auto weighted = FitLocalPoseModel(examples, 4, Eigen::VectorXf::Constant(50, 3.0f));
  ASSERT_TRUE(plain.ok() && weighted.ok());
  EXPECT_TRUE(weighted->mean.isApprox(plain->mean, 1e-5f));
  EXPECT_TRUE(weighted->variances.isApprox(plain->variances, 1e-4f));
}

TEST(LocalPoseModelTest, WeightsLeaveOutWhatTheyZero) {
  // Twenty examples about one pose along feature 0, twenty far away along feature 1: weighted to
  // the first twenty, the model is theirs alone.
  std::mt19937 random(5);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  Eigen::MatrixXf examples = Eigen::MatrixXf::Zero(40, 6);
  for (int i = 0; i < 40; ++i) {
    if (i < 20) {
      examples(i, 0) = normal(random);
    } else {
      examples.row(i).setConstant(5.0f);
      examples(i, 1) += 3.0f * normal(random);
    }
  }
  Eigen::VectorXf weights = Eigen::VectorXf::Zero(40);
  weights.head(20).setOnes();
  auto model = FitLocalPoseModel(examples, 2, weights);
  auto first = FitLocalPoseModel(examples.topRows(20), 2);
  ASSERT_TRUE(model.ok() && first.ok());
  EXPECT_TRUE(model->mean.isApprox(first->mean, 1e-5f));
  EXPECT_NEAR(model->variances[0], first->variances[0], 1e-4f);
  EXPECT_NEAR(std::abs(model->basis(0, 0)), 1.0f, 1e-4f);  // along feature 0, not the far examples' 1
}

TEST(LocalPoseModelTest, KernelWeightsFallWithDistanceFromTheNearest) {
  const std::vector<float> distances = {0.5f, 0.6f, 1.0f, 2.0f, 4.0f};  // squared, nearest first
  EXPECT_EQ(NeighbourKernelWeights(distances, 0.0f).size(), 0);         // 0: alike
  const Eigen::VectorXf w = NeighbourKernelWeights(distances, 0.5f);
  ASSERT_EQ(w.size(), 5);
  EXPECT_FLOAT_EQ(w[0], 1.0f);
  for (int i = 1; i < 5; ++i) EXPECT_LT(w[i], w[i - 1]);
  // Variance 0.5 × the median (1.0): the median neighbour, 0.5 beyond the nearest, weighs e^−0.5.
  EXPECT_NEAR(w[2], std::exp(-0.5f), 1e-5f);
  // The same neighbours twice as far (a query twice as far from the database) weigh the same.
  std::vector<float> doubled = distances;
  for (float& d : doubled) d *= 2.0f;
  EXPECT_TRUE(NeighbourKernelWeights(doubled, 0.5f).isApprox(w, 1e-5f));
  EXPECT_TRUE(NeighbourKernelWeights(std::vector<float>(4, 0.0f), 1.0f).isApprox(Eigen::VectorXf::Ones(4)));
}

TEST(LocalPoseModelTest, RejectsBadInput) {
  EXPECT_EQ(FitLocalPoseModel(Eigen::MatrixXf::Zero(1, 4)).status().code(), absl::StatusCode::kInvalidArgument);
  Eigen::MatrixXf nan = Eigen::MatrixXf::Zero(5, 4);
  nan(2, 1) = std::nanf("");
  EXPECT_EQ(FitLocalPoseModel(nan).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(FitLocalPoseModel(Eigen::MatrixXf::Zero(5, 4), 0).status().code(), absl::StatusCode::kInvalidArgument);
  const Eigen::MatrixXf five = Eigen::MatrixXf::Random(5, 4);
  for (const Eigen::VectorXf& bad :
       {Eigen::VectorXf(Eigen::VectorXf::Ones(4)), Eigen::VectorXf(Eigen::VectorXf::Zero(5)),
        Eigen::VectorXf(Eigen::VectorXf::Unit(5, 2)),  // one example alone
        Eigen::VectorXf(-Eigen::VectorXf::Ones(5))}) {
    EXPECT_EQ(FitLocalPoseModel(five, 2, bad).status().code(), absl::StatusCode::kInvalidArgument) << bad.transpose();
  }
}

}  // namespace
}  // namespace mocap
