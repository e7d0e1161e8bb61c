#include "motion/reconstruct/grip_offset.h"

#include <algorithm>

#include "motion/preprocess/frame_features.h"

namespace mocap {

namespace {

// Unit vectors from each elbow to its wrist (left, right) of a body whose joints are at
// `positions`; zero where the rig has no elbow or the two coincide.
std::array<Eigen::Vector3f, 2> Forearms(const BodyModel& body, const std::vector<Eigen::Vector3f>& positions) {
  const BodyLandmarks& l = body.rig().topology.landmarks;
  const std::array<std::array<int, 2>, 2> arms = {{{l.left_elbow, l.left_wrist}, {l.right_elbow, l.right_wrist}}};
  std::array<Eigen::Vector3f, 2> forearms{Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()};
  for (int side = 0; side < 2; ++side) {
    const auto [elbow, wrist] = arms[side];
    if (elbow < 0 || wrist < 0) continue;
    const Eigen::Vector3f forearm = positions[wrist] - positions[elbow];
    if (forearm.norm() > 1e-4f) forearms[side] = forearm.normalized();
  }
  return forearms;
}

}  // namespace

std::array<Eigen::Vector3f, 2> RowForearms(const ReconstructionDatabase& database, int row) {
  const DatabaseFrame& frame = database.frames()[row];
  const Eigen::Quaternionf pelvis_rotation(frame.pelvis_rotation[0], frame.pelvis_rotation[1], frame.pelvis_rotation[2],
                                           frame.pelvis_rotation[3]);
  const Eigen::Vector3f pelvis_position(frame.pelvis_position[0], frame.pelvis_position[1], frame.pelvis_position[2]);
  const Eigen::VectorXf feature = database.pose_feature(row).transpose();
  const BodyModel& body = database.body();
  // m = (θ, h, q): the joints' rotations follow the two pelvis values (reconstruction_database.h).
  const BodyPose pose = body.Pose(pelvis_rotation.normalized(), pelvis_position, feature.data() + 2);
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> positions;
  body.WorldTransforms(pose, &rotations, &positions);
  return Forearms(body, positions);
}

void GripOffset::Remember(const ReconstructionDatabase& database, std::span<const AnkleCandidate> nearest_first) {
  std::array<Eigen::Vector3f, 2> sum{Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()};
  for (const AnkleCandidate& candidate : nearest_first.first(std::min(kRows, nearest_first.size()))) {
    const std::array<Eigen::Vector3f, 2> forearms = RowForearms(database, candidate.row);
    for (int side = 0; side < 2; ++side) sum[side] += forearms[side];
  }
  for (auto& v : sum) v = v.norm() > 1e-4f ? v.normalized() : Eigen::Vector3f::Zero();
  forearms_ = sum;
}

void GripOffset::ToWrists(float heading, SmoothedWrists* points) {
  if (!active() || !forearms_) return;
  const ReferenceFrame ref = WristReferenceFrame(points->position[0], points->position[1], heading, nullptr);
  for (int side = 0; side < 2; ++side) {
    // The nearest rows change from frame to frame, and their forearms with them: followed at once,
    // each change would step the wrists by up to twice the grip.
    const Eigen::Vector3f nearest = ref.rotation * (*forearms_)[side];
    Eigen::Vector3f& forearm = world_forearms_[side];
    forearm = forearm.isZero() ? nearest : (forearm + kFollow * (nearest - forearm)).normalized();
    points->position[side] -= metres_ * forearm;
  }
}

void GripOffset::ToWrists(const BodyModel& body, const std::vector<Eigen::Vector3f>& world_positions,
                          SmoothedWrists* points) const {
  if (!active()) return;
  const std::array<Eigen::Vector3f, 2> forearms = Forearms(body, world_positions);
  for (int side = 0; side < 2; ++side) points->position[side] -= metres_ * forearms[side];
}

}  // namespace mocap
