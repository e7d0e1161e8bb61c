#include "motion/reconstruct/local_pose_model.h"

#include <algorithm>

#include <Eigen/Eigenvalues>

namespace mocap {

float LocalPoseModel::PriorEnergy(const Eigen::VectorXf& weights, float min_variance) const {
  return (weights.array().square() / variances.array().max(min_variance)).sum();
}

absl::StatusOr<LocalPoseModel> FitLocalPoseModel(const Eigen::MatrixXf& examples, int components) {
  if (examples.rows() < 2) return absl::InvalidArgumentError("a pose model needs at least two examples");
  if (!examples.allFinite()) return absl::InvalidArgumentError("pose examples are not finite");
  if (components < 1) return absl::InvalidArgumentError("a pose model needs at least one component");
  LocalPoseModel model;
  const Eigen::MatrixXd x = examples.cast<double>();
  const Eigen::RowVectorXd mean = x.colwise().mean();
  const Eigen::MatrixXd centred = x.rowwise() - mean;
  const int kept =
      std::min<int>({components, static_cast<int>(examples.rows()) - 1, static_cast<int>(examples.cols())});
  // K2 (200) examples of ~60 features: the smaller of the two Gram matrices is cheap either way.
  const Eigen::MatrixXd covariance = centred.transpose() * centred / static_cast<double>(examples.rows() - 1);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(covariance);
  model.mean = mean.transpose().cast<float>();
  model.basis = solver.eigenvectors().rightCols(kept).rowwise().reverse().cast<float>();  // largest first
  model.variances = solver.eigenvalues().tail(kept).reverse().cast<float>();
  return model;
}

}  // namespace mocap
