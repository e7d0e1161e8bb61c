// Local linear pose model of docs/method.md A5 (eqs. 8–9; Chai & Hodgins 2005): PCA over the pose
// features m = (θ, h, q) of the K2 database frames nearest to the current wrists and ankles,
//   m ≈ p̄ + U·w,  w ∈ R^D' (D' = 6),
// with Λ the examples' covariance, which the A6 prior term E_prior = (m − p̄)ᵀ Λ⁻¹ (m − p̄) uses
// (in the model's own coordinates: Σ w_i² / λ_i).
#pragma once

#include <span>

#include <Eigen/Core>

#include "absl/status/statusor.h"

namespace mocap {

struct LocalPoseModel {
  Eigen::VectorXf mean;       // p̄, one entry per pose feature
  Eigen::MatrixXf basis;      // U: features x components, orthonormal columns
  Eigen::VectorXf variances;  // λ: variance of the examples along each basis column
  int num_components() const { return static_cast<int>(basis.cols()); }

  Eigen::VectorXf Reconstruct(const Eigen::VectorXf& weights) const { return mean + basis * weights; }
  Eigen::VectorXf Project(const Eigen::VectorXf& pose) const { return basis.transpose() * (pose - mean); }
  // E_prior for weights w: Σ w_i² / λ_i (λ floored at `min_variance` so flat directions stay finite).
  float PriorEnergy(const Eigen::VectorXf& weights, float min_variance = 1e-8f) const;
};

// PCA of `examples` (one pose feature vector per row). At most min(components, rows − 1)
// components are kept. `weights` (one per row, ≥ 0, not all 0), when given, weigh the examples in
// the mean and the covariance (reliability weights: unbiased, the plain PCA when they are equal).
// InvalidArgument with fewer than two examples, non-finite values or bad weights.
absl::StatusOr<LocalPoseModel> FitLocalPoseModel(const Eigen::MatrixXf& examples, int components = 6,
                                                 const Eigen::VectorXf& weights = {});

// Weights for the K2 examples of A5 from their squared eq. 8 distances (nearest first): a Gaussian
// kernel whose variance is `kernel` × the median neighbour's squared distance, measured from the
// nearest's, so the weighting does not depend on how far the input is from the whole database.
// Empty (equal weights) for kernel ≤ 0.
Eigen::VectorXf NeighbourKernelWeights(std::span<const float> squared_distances, float kernel);

}  // namespace mocap
