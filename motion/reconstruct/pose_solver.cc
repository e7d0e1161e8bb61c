#include "motion/reconstruct/pose_solver.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <unsupported/Eigen/NonLinearOptimization>
#include <unsupported/Eigen/NumericalDiff>

#include "motion/core/str_cat.h"

namespace mocap {
namespace {

// Residuals r with Σ r² = the A6 energy. x = (w[0..n), z_R (w,x,y,z), z_P).
struct PoseEnergy {
  using Scalar = double;
  using InputType = Eigen::VectorXd;
  using ValueType = Eigen::VectorXd;
  using JacobianType = Eigen::MatrixXd;
  enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };

  const BodyModel& body;
  const LocalPoseModel& model;
  const ControlTargets& targets;
  const SolvedPose* previous;
  const SolvedPose* before_previous;
  const PoseSolverOptions& options;
  Eigen::Vector3d pelvis_up_local;
  Eigen::VectorXd mean;
  Eigen::MatrixXd basis;
  Eigen::VectorXd inverse_std;
  Eigen::Vector4d smooth_rotation_target;  // 2 z_R^(t−1) − z_R^(t−2), sign-aligned
  Eigen::Vector3d smooth_position_target;
  Eigen::VectorXd smooth_q_target;
  mutable Eigen::VectorXd m;               // scratch
  mutable std::vector<double> clearances;  // scratch, per floor joint

  int components() const { return static_cast<int>(basis.cols()); }
  int inputs() const { return components() + 7; }
  int values() const {
    return 3 + components() + 3 * kNumControlPoints + body.num_floor_joints() +
           (previous && before_previous ? 7 + static_cast<int>(mean.size()) - 2 : 0);
  }

  int operator()(const Eigen::VectorXd& x, Eigen::VectorXd& r) const {
    const int n = components();
    const double scale = options.length_scale;
    m.noalias() = mean + basis * x.head(n);
    const Eigen::Quaterniond z_r(x[n], x[n + 1], x[n + 2], x[n + 3]);
    const Eigen::Vector3d z_p = x.segment<3>(n + 4);
    const double norm_sq = z_r.squaredNorm();
    const Eigen::Quaterniond unit = norm_sq > 1e-12 ? z_r.normalized() : Eigen::Quaterniond::Identity();
    const double tilt = std::acos(std::clamp((unit * pelvis_up_local).y(), -1.0, 1.0));
    int i = 0;
    const double w_const = std::sqrt(options.constraint_weight);
    r[i++] = norm_sq - 1.0;
    r[i++] = w_const * (m[0] - tilt);
    r[i++] = w_const * scale * (m[1] - z_p.y());
    const double w_prior = std::sqrt(options.prior_weight);
    for (int c = 0; c < n; ++c) r[i++] = w_prior * x[c] * inverse_std[c];
    std::array<Eigen::Vector3d, kNumControlPoints> points;
    body.ControlPoints(unit, z_p, m.data() + 2, &points, clearances.data());
    const double w_ctrl = std::sqrt(options.control_weight) * scale;
    for (int c = 0; c < kNumControlPoints; ++c) {
      if (!options.control_ankles && c >= kLeftAnkle) {
        for (int axis = 0; axis < 3; ++axis) r[i++] = 0.0;
        continue;
      }
      const Eigen::Vector3d miss = points[c] - targets[c].cast<double>();
      for (int axis = 0; axis < 3; ++axis) r[i++] = w_ctrl * miss[axis];
    }
    const double w_floor = std::sqrt(options.floor_weight) * scale;
    for (const double clearance : clearances) r[i++] = w_floor * std::min(clearance, 0.0);
    if (previous && before_previous) {
      const double w_smooth = std::sqrt(options.smooth_weight);
      for (int k = 0; k < 4; ++k) r[i++] = w_smooth * (z_r.coeffs()[(k + 3) % 4] - smooth_rotation_target[k]);
      for (int axis = 0; axis < 3; ++axis) r[i++] = w_smooth * scale * (z_p[axis] - smooth_position_target[axis]);
      const int q_size = static_cast<int>(m.size()) - 2;
      for (int k = 0; k < q_size; ++k) r[i++] = w_smooth * (m[2 + k] - smooth_q_target[k]);
    }
    return 0;
  }
};

Eigen::Vector4d Wxyz(const Eigen::Quaternionf& q) { return Eigen::Vector4d(q.w(), q.x(), q.y(), q.z()); }

}  // namespace

float PelvisTilt(const Eigen::Quaternionf& pelvis_rotation, const Eigen::Vector3f& pelvis_up_local) {
  return std::acos(std::clamp((pelvis_rotation.normalized() * pelvis_up_local).y(), -1.0f, 1.0f));
}

absl::StatusOr<SolvedPose> SolvePose(const BodyModel& body, const LocalPoseModel& model, const ControlTargets& targets,
                                     const SolvedPose& initial, const SolvedPose* previous,
                                     const SolvedPose* before_previous, const PoseSolverOptions& options) {
  const int features = 2 + 3 * body.num_pose_joints();
  if (model.mean.size() != features || model.basis.rows() != features) {
    return absl::InvalidArgumentError(
        StrCat("pose model has ", model.mean.size(), " features; the body needs ", features));
  }
  if (initial.pose_feature.size() != features) {
    return absl::InvalidArgumentError(
        StrCat("initial pose has ", initial.pose_feature.size(), " features; the body needs ", features));
  }
  for (const Eigen::Vector3f& target : targets) {
    if (!target.allFinite()) return absl::InvalidArgumentError("control target is not finite");
  }
  PoseEnergy energy{body, model, targets, previous, before_previous, options};
  energy.pelvis_up_local = body.rig().pelvis_up_local.cast<double>();
  energy.mean = model.mean.cast<double>();
  energy.basis = model.basis.cast<double>();
  energy.inverse_std = model.variances.cast<double>().array().max(options.min_variance).rsqrt().matrix();
  energy.m.resize(features);
  energy.clearances.resize(body.num_floor_joints());
  if (previous && before_previous) {
    // Quaternions q and −q are one rotation: align both history frames with the initial guess.
    Eigen::Vector4d q1 = Wxyz(previous->pelvis_rotation), q2 = Wxyz(before_previous->pelvis_rotation);
    const Eigen::Vector4d q0 = Wxyz(initial.pelvis_rotation);
    if (q1.dot(q0) < 0) q1 = -q1;
    if (q2.dot(q1) < 0) q2 = -q2;
    energy.smooth_rotation_target = 2 * q1 - q2;
    energy.smooth_position_target = (2 * previous->pelvis_position - before_previous->pelvis_position).cast<double>();
    energy.smooth_q_target =
        (2 * previous->pose_feature.tail(features - 2) - before_previous->pose_feature.tail(features - 2))
            .cast<double>();
  }
  const int n = energy.components();
  Eigen::VectorXd x(n + 7);
  x.head(n) = model.Project(initial.pose_feature).cast<double>();
  x.segment<4>(n) = Wxyz(initial.pelvis_rotation.normalized());
  x.segment<3>(n + 4) = initial.pelvis_position.cast<double>();

  Eigen::NumericalDiff<PoseEnergy> differentiated(energy);
  Eigen::LevenbergMarquardt<Eigen::NumericalDiff<PoseEnergy>> solver(differentiated);
  solver.parameters.maxfev = options.max_evaluations;
  solver.minimize(x);

  SolvedPose result;
  result.pose_feature = (energy.mean + energy.basis * x.head(n)).cast<float>();
  result.pelvis_rotation = Eigen::Quaternionf(x[n], x[n + 1], x[n + 2], x[n + 3]).normalized();
  result.pelvis_position = x.segment<3>(n + 4).cast<float>();
  Eigen::VectorXd residuals(energy.values());
  energy(x, residuals);
  result.cost = static_cast<float>(residuals.squaredNorm());
  result.prior_cost = static_cast<float>((x.head(n).array() * energy.inverse_std.array()).square().sum());
  result.evaluations = static_cast<int>(solver.nfev);
  std::array<Eigen::Vector3d, kNumControlPoints> points;
  const Eigen::VectorXd q = result.pose_feature.tail(features - 2).cast<double>();
  body.ControlPoints(result.pelvis_rotation.cast<double>(), result.pelvis_position.cast<double>(), q.data(), &points);
  for (int c = 0; c < kNumControlPoints; ++c)
    result.control_error[c] = static_cast<float>((points[c] - targets[c].cast<double>()).norm());
  if (!result.pose_feature.allFinite() || !result.pelvis_position.allFinite()) {
    return absl::InternalError("pose solve diverged");
  }
  return result;
}

}  // namespace mocap
