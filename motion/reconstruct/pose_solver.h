// Per-frame pose optimisation of docs/method.md A6 (eqs. 10–14). Unknowns: the local pose model's
// weights w (m = p̄ + U·w, A5) and the pelvis z = (z_R quaternion, z_P position). Minimises
//   E_const  = (z_Rᵀz_R − 1)² + w_θ(θ(w) − θ|z)² + w_h(h(w) − h|z)²
//   E_prior  = Σ w_i² / λ_i                      (= (m − p̄)ᵀ Λ⁻¹ (m − p̄) within the model)
//   E_ctrl   = ‖x(w,z) − x̃‖² + ‖y(w,z) − ỹ‖²    (wrists and ankles by forward kinematics)
//   E_smooth = ‖z^t − 2z^(t−1) + z^(t−2)‖² + ‖q^t − 2q^(t−1) + q^(t−2)‖²
//   E_floor  = Σ_j min(0, y_j − y_j,lowest)²    (the service's: no joint the body rests on under
//                                                the floor, BodyModel::num_floor_joints; 0 standing)
// as E_const + 1.0·E_prior + 0.8·E_ctrl + 0.2·E_smooth + 10·E_floor with Levenberg–Marquardt (Eigen's, with
// forward-difference Jacobians). The patent does not state its length unit; lengths enter the
// energies multiplied by `length_scale` (100: centimetres), which balances E_ctrl against the
// unit-free E_prior (a typical prior cost is ~D' = 6; a 2 cm miss on four points costs 12.8).
#pragma once

#include <array>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "absl/status/statusor.h"
#include "motion/reconstruct/body_model.h"
#include "motion/reconstruct/local_pose_model.h"

namespace mocap {

struct PoseSolverOptions {
  float constraint_weight = 1.0f;  // w_θ = w_h
  float prior_weight = 1.0f;
  float control_weight = 0.8f;
  float smooth_weight = 0.2f;
  float floor_weight = 10.0f;   // E_floor (not the patent's): near-hard; 0: joints may go under the floor
  float length_scale = 100.0f;  // lengths in the energies are in metres × this (cm)
  float min_variance = 1e-6f;   // floor on λ_i
  int max_evaluations = 200;    // residual evaluations (LM steps, excluding the Jacobians')
  bool control_ankles = true;   // false: E_ctrl on the wrists only (the patent's baseline)
};

// One frame's pose: pelvis and the pose feature m = (θ, h, q).
struct SolvedPose {
  Eigen::Quaternionf pelvis_rotation = Eigen::Quaternionf::Identity();
  Eigen::Vector3f pelvis_position = Eigen::Vector3f::Zero();
  Eigen::VectorXf pose_feature;  // 2 + 3 × pose joints
  float cost = 0.0f;             // total energy at the solution
  float prior_cost = 0.0f;       // E_prior at the solution, unweighted (Σ w_i² / λ_i)
  int evaluations = 0;
  std::array<float, kNumControlPoints> control_error{};  // metres, |FK − target|
};

using ControlTargets = std::array<Eigen::Vector3f, kNumControlPoints>;

// `initial` seeds the pelvis and (projected onto the model) w. `previous`/`before_previous`
// are the two preceding frames' solutions for E_smooth (nullptr at a segment's start: the term is
// dropped until two frames exist). InvalidArgument for non-finite targets or a model whose size
// does not match the body model.
absl::StatusOr<SolvedPose> SolvePose(const BodyModel& body, const LocalPoseModel& model, const ControlTargets& targets,
                                     const SolvedPose& initial, const SolvedPose* previous,
                                     const SolvedPose* before_previous, const PoseSolverOptions& options);

// θ|z: the angle between world up (+Y) and the pelvis' up vector.
float PelvisTilt(const Eigen::Quaternionf& pelvis_rotation, const Eigen::Vector3f& pelvis_up_local);

}  // namespace mocap
