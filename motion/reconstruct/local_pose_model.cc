#include "motion/reconstruct/local_pose_model.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Eigenvalues>

#include "motion/core/str_cat.h"

#define LAPACK_COMPLEX_CPP  // lapacke.h's complex types as std::complex (C's _Complex is not C++)
#include <lapacke.h>

namespace mocap {
namespace {

// The `count` largest eigenpairs of a symmetric matrix, largest first. A5 keeps D' = 6 of ~60
// (issue #26: a full solve spent most of its time on eigenvectors that were thrown away): Eigen
// reduces the matrix to tridiagonal form by Householder reflections, LAPACK's MRRR (dstemr) finds
// only the wanted eigenpairs of that tridiagonal matrix, and the reflections carry its eigenvectors
// back. Same eigenpairs as Eigen's SelfAdjointEigenSolver to rounding (LocalPoseModelTest), up to
// each eigenvector's sign, which the model does not depend on.
absl::Status LargestEigenpairs(const Eigen::MatrixXd& symmetric, int count, Eigen::VectorXd* values,
                               Eigen::MatrixXd* vectors) {
  const int n = static_cast<int>(symmetric.rows());
  const Eigen::Tridiagonalization<Eigen::MatrixXd> tridiagonal(symmetric);
  Eigen::VectorXd diagonal = tridiagonal.diagonal();
  Eigen::VectorXd off_diagonal = Eigen::VectorXd::Zero(n);  // dstemr wants n entries, the last as workspace
  off_diagonal.head(n - 1) = tridiagonal.subDiagonal();
  Eigen::VectorXd ascending(n);
  Eigen::MatrixXd z(n, count);
  std::vector<lapack_int> support(2 * static_cast<size_t>(count));
  lapack_int found = 0;
  lapack_logical try_high_relative_accuracy = 1;
  const lapack_int info =
      LAPACKE_dstemr(LAPACK_COL_MAJOR, 'V', 'I', n, diagonal.data(), off_diagonal.data(), 0.0, 0.0, n - count + 1, n,
                     &found, ascending.data(), z.data(), n, count, support.data(), &try_high_relative_accuracy);
  if (info != 0 || found != count) {
    return absl::InternalError(StrCat("the pose model's eigen-decomposition failed (LAPACK dstemr info ", info, ", ",
                                      found, " of ", count, ")"));
  }
  // Q = H_0 H_1 … H_{n−2} (H_i acts on rows i+1…): Q·z applies the last reflection first.
  Eigen::VectorXd workspace(count);
  const Eigen::MatrixXd& packed = tridiagonal.packedMatrix();
  for (int i = n - 2; i >= 0; --i) {
    z.bottomRows(n - 1 - i).applyHouseholderOnTheLeft(packed.col(i).tail(n - 2 - i),
                                                      tridiagonal.householderCoefficients()(i), workspace.data());
  }
  *values = ascending.head(count).reverse();
  *vectors = z.rowwise().reverse();
  return absl::OkStatus();
}

}  // namespace

float LocalPoseModel::PriorEnergy(const Eigen::VectorXf& weights, float min_variance) const {
  return (weights.array().square() / variances.array().max(min_variance)).sum();
}

Eigen::VectorXf NeighbourKernelWeights(std::span<const float> squared_distances, float kernel) {
  if (kernel <= 0 || squared_distances.empty()) return {};
  std::vector<float> sorted(squared_distances.begin(), squared_distances.end());
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
  const float median = sorted[sorted.size() / 2];
  const float nearest = *std::min_element(squared_distances.begin(), squared_distances.end());
  // Floored so an exact match (median 0) stays finite: examples at the nearest's distance weigh 1.
  const float variance = kernel * std::max(median, 1e-12f);
  Eigen::VectorXf weights(static_cast<Eigen::Index>(squared_distances.size()));
  for (size_t i = 0; i < squared_distances.size(); ++i)
    weights[static_cast<Eigen::Index>(i)] = std::exp(-0.5f * (squared_distances[i] - nearest) / variance);
  return weights;
}

absl::StatusOr<LocalPoseModel> FitLocalPoseModel(const Eigen::MatrixXf& examples, int components,
                                                 const Eigen::VectorXf& weights) {
  if (examples.rows() < 2) return absl::InvalidArgumentError("a pose model needs at least two examples");
  if (!examples.allFinite()) return absl::InvalidArgumentError("pose examples are not finite");
  if (components < 1) return absl::InvalidArgumentError("a pose model needs at least one component");
  if (weights.size() != 0 && (weights.size() != examples.rows() || !weights.allFinite() ||
                              (weights.array() < 0).any() || weights.sum() <= 0)) {
    return absl::InvalidArgumentError("pose example weights must be one per example, finite, ≥ 0 and not all 0");
  }
  LocalPoseModel model;
  const Eigen::MatrixXd x = examples.cast<double>();
  const Eigen::VectorXd w = weights.size() != 0
                                ? Eigen::VectorXd(weights.cast<double>() / weights.cast<double>().sum())
                                : Eigen::VectorXd::Constant(x.rows(), 1.0 / static_cast<double>(x.rows()));
  const Eigen::RowVectorXd mean = w.transpose() * x;
  const Eigen::MatrixXd centred = x.rowwise() - mean;
  const int kept =
      std::min<int>({components, static_cast<int>(examples.rows()) - 1, static_cast<int>(examples.cols())});
  // Reliability weights (normalised to sum 1): Σ wᵢ (xᵢ − μ)(xᵢ − μ)ᵀ / (1 − Σ wᵢ²), the sample
  // covariance / (n − 1) when the weights are equal. K2 (50) examples of ~60 features.
  const double bias = 1.0 - w.squaredNorm();
  if (bias <= 1e-12) return absl::InvalidArgumentError("pose example weights leave a single example");
  const Eigen::MatrixXd covariance = centred.transpose() * w.asDiagonal() * centred / bias;
  Eigen::VectorXd variances;
  Eigen::MatrixXd basis;
  if (absl::Status solved = LargestEigenpairs(covariance, kept, &variances, &basis); !solved.ok()) return solved;
  model.mean = mean.transpose().cast<float>();
  model.basis = basis.cast<float>();  // largest first
  model.variances = variances.cast<float>();
  return model;
}

}  // namespace mocap
