// BodyModel: the database rig as docs/method.md A6 drives it. The unknowns are the pelvis' world
// transform z = (z_R, z_P) and the joint rotations q of the pose feature (rotation vectors relative
// to the rig's reference rotations, for ReconstructionDatabase::pose_joints()). Joints on the
// root-to-pelvis chain keep their reference rotations; the root's transform follows from z.
//
// Thread safety: immutable after Create; share freely.
#pragma once

#include <array>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "absl/status/statusor.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/skeleton/local_motion.h"

namespace mocap {

// One frame of a body on the model's skeleton: root translation (metres, world) and every
// joint's local rotation.
struct BodyPose {
  Eigen::Vector3f root_position = Eigen::Vector3f::Zero();
  std::vector<Eigen::Quaternionf> rotations;
};

// The four control points of A6, in this order.
enum ControlPoint { kLeftWrist = 0, kRightWrist = 1, kLeftAnkle = 2, kRightAnkle = 3 };
inline constexpr int kNumControlPoints = 4;

class BodyModel {
 public:
  // `skeleton`: the rig's hierarchy with offsets in metres (a database performer's, optionally
  // scaled). InvalidArgument when it is not the rig's hierarchy or a pose joint is on the pelvis
  // chain.
  static absl::StatusOr<BodyModel> Create(const RigModel& rig, const Skeleton& skeleton,
                                          const std::vector<int>& pose_joints);

  const Skeleton& skeleton() const { return skeleton_; }
  const RigModel& rig() const { return rig_; }
  int num_pose_joints() const { return static_cast<int>(pose_joints_.size()); }

  // World positions (metres) of the wrists and ankles. `q` holds 3 values per pose joint. With
  // `clearances`, also how far each floor joint is above its lowest height (negative: under it),
  // num_floor_joints() values.
  void ControlPoints(const Eigen::Quaterniond& pelvis_rotation, const Eigen::Vector3d& pelvis_position, const double* q,
                     std::array<Eigen::Vector3d, kNumControlPoints>* out, double* clearances = nullptr) const;
  template <typename Derived>
  void ControlPoints(const Eigen::Quaterniond& pelvis_rotation, const Eigen::Vector3d& pelvis_position,
                     const Eigen::MatrixBase<Derived>& q, std::array<Eigen::Vector3d, kNumControlPoints>* out) const {
    const Eigen::VectorXd qd = q.template cast<double>();
    ControlPoints(pelvis_rotation, pelvis_position, qd.data(), out);
  }

  // The joints the body rests on when it is down on the ground, which the solve keeps above it
  // (docs/method.md A6, "The floor"): pelvis, head, shoulders, elbows, hips, knees — not the feet
  // and hands, which have their own rules.
  int num_floor_joints() const { return static_cast<int>(floor_joints_.size()); }
  // How far the lowest of them is above its lowest height in a pose's world positions (every
  // joint's, WorldTransforms), metres; negative: under it; +infinity for a rig without them.
  float FloorClearance(std::span<const Eigen::Vector3f> world_positions) const;

  // The whole pose: every joint's local rotation and the root translation that puts the pelvis
  // at `pelvis_position` (other joints keep their offsets).
  BodyPose Pose(const Eigen::Quaternionf& pelvis_rotation, const Eigen::Vector3f& pelvis_position,
                const float* q) const;
  // World rotations and positions of every joint of `pose`.
  void WorldTransforms(const BodyPose& pose, std::vector<Eigen::Quaternionf>* rotations,
                       std::vector<Eigen::Vector3f>* positions) const;
  // A motion of `poses` on this skeleton (metres, Y up).
  LocalMotion ToLocalMotion(const std::vector<BodyPose>& poses, double frame_time) const;

  // Root world transform that places the pelvis at z (the chain at its reference rotations).
  void RootFromPelvis(const Eigen::Quaterniond& pelvis_rotation, const Eigen::Vector3d& pelvis_position,
                      Eigen::Quaterniond* root_rotation, Eigen::Vector3d* root_position) const;

 private:
  BodyModel() = default;
  RigModel rig_;
  Skeleton skeleton_;
  std::vector<int> pose_joints_;
  std::vector<int> pose_slot_;       // per joint: index into pose_joints_, or -1
  std::vector<int> control_joints_;  // joints on the root-to-control-point paths, parents first
  std::array<int, kNumControlPoints> control_landmarks_{};
  std::vector<int> floor_joints_;      // see num_floor_joints()
  std::vector<double> floor_heights_;  // per floor joint: the lowest its joint centre goes, metres
  std::vector<Eigen::Quaterniond> reference_;
  std::vector<Eigen::Vector3d> offset_;
  Eigen::Quaterniond chain_rotation_ = Eigen::Quaterniond::Identity();  // root→pelvis, reference pose
  Eigen::Vector3d chain_translation_ = Eigen::Vector3d::Zero();
};

// Standing height of the body, metres: the extent of its zero-rotation pose along that pose's own
// up axis (pelvis → head, BodyTopology::rest_up_axis), end sites included. Used to scale a
// performer of another height (docs/method.md does not scale; the service does).
float RestPoseHeight(const BodyModel& body);

// The performer's standing height (floor to the top of the head), metres, told from the legs'
// bone lengths (hip → knee → ankle landmarks, mean of both sides; kLegShareOfStature): what a
// person means by their height, which RestPoseHeight is not on rigs whose zero-rotation pose does
// not stand (Bandai's lies along +X with the legs spread: 1.84 m for a 1.70 m actor). 0 when the
// rig's landmarks give no legs.
float EstimatedStature(const BodyModel& body);

// The farthest apart the body can hold its wrists, metres: both arms (shoulder → elbow → wrist
// landmarks) and the shoulders' breadth, arms spread. 0 when the rig's landmarks give no arms.
float WristSpan(const BodyModel& body);

// Elbow to wrist landmark, metres, the mean of both arms. 0 when the rig's landmarks give no arms.
float ForearmLength(const BodyModel& body);

}  // namespace mocap
