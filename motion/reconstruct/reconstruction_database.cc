#include "motion/reconstruct/reconstruction_database.h"

#include <cmath>

#include <flann/flann.hpp>

#include "motion/core/str_cat.h"

namespace mocap {

void WristAnkleFeature(const FrameFeatures& f, float position_weight, float out[kWristAnkleFeatureDims]) {
  const float p = std::sqrt(position_weight), v = std::sqrt(1.0f - position_weight);
  for (int side = 0; side < 2; ++side) {
    for (int axis = 0; axis < 3; ++axis) {
      out[3 * side + axis] = p * f.wrist_position[side][axis];
      out[6 + 3 * side + axis] = p * f.ankle_position[side][axis];
      out[12 + 3 * side + axis] = v * f.wrist_velocity[side][axis];
      out[18 + 3 * side + axis] = v * f.ankle_velocity[side][axis];
    }
  }
}

struct ReconstructionDatabase::FullIndex {
  std::vector<float> data;
  std::unique_ptr<flann::Index<flann::L2<float>>> tree;
};

ReconstructionDatabase::ReconstructionDatabase() : full_index_(std::make_unique<FullIndex>()) {}
ReconstructionDatabase::~ReconstructionDatabase() = default;

absl::StatusOr<std::shared_ptr<const ReconstructionDatabase>> ReconstructionDatabase::Build(
    const RigModel& rig, const std::vector<DatabaseClip>& clips, float position_weight) {
  std::shared_ptr<ReconstructionDatabase> db(new ReconstructionDatabase());
  db->rig_ = rig;
  const int joints = rig.skeleton.num_joints();
  // q: every joint except those from the root down to the pelvis (their rotations are z_R).
  std::vector<bool> on_pelvis_chain(joints, false);
  for (int j = rig.topology.landmarks.pelvis; j >= 0; j = rig.skeleton.parent(j)) on_pelvis_chain[j] = true;
  for (int j = 0; j < joints; ++j) {
    if (!on_pelvis_chain[j]) db->pose_joints_.push_back(j);
  }
  const int stride = EncodedPoseFloats(joints);
  size_t total = 0;
  for (size_t c = 0; c < clips.size(); ++c) {
    if (clips[c].encoded_poses.size() != clips[c].features.size() * stride) {
      return absl::InvalidArgumentError(StrCat("clip ", c, ": ", clips[c].encoded_poses.size(), " pose floats for ",
                                               clips[c].features.size(), " frames of a ", joints, "-joint rig"));
    }
    total += clips[c].features.size();
  }
  if (total == 0) return absl::FailedPreconditionError("reconstruction database has no frames");
  db->frames_.reserve(total);
  db->pose_features_.resize(static_cast<Eigen::Index>(total), 2 + 3 * static_cast<Eigen::Index>(db->pose_joints_.size()));
  for (size_t c = 0; c < clips.size(); ++c) {
    for (size_t f = 0; f < clips[c].features.size(); ++f) {
      const int row = static_cast<int>(db->frames_.size());
      const FrameFeatures& features = clips[c].features[f];
      db->frames_.push_back(features);
      db->clip_of_row_.push_back(static_cast<int>(c));
      db->frame_of_row_.push_back(static_cast<int>(f));
      auto m = db->pose_features_.row(row);
      m[0] = features.pelvis_tilt;
      m[1] = features.pelvis_height;
      const float* pose = clips[c].encoded_poses.data() + f * stride;
      for (size_t i = 0; i < db->pose_joints_.size(); ++i) {
        for (int axis = 0; axis < 3; ++axis) m[2 + 3 * i + axis] = pose[3 + 3 * db->pose_joints_[i] + axis];
      }
    }
  }
  if (absl::Status status = db->wrist_index_.Build(db->frames_, {.position_weight = position_weight}); !status.ok()) {
    return status;
  }
  FullIndex& full = *db->full_index_;
  full.data.resize(total * kWristAnkleFeatureDims);
  for (size_t r = 0; r < total; ++r) WristAnkleFeature(db->frames_[r], position_weight, full.data.data() + r * kWristAnkleFeatureDims);
  try {
    flann::Matrix<float> matrix(full.data.data(), total, kWristAnkleFeatureDims);
    full.tree = std::make_unique<flann::Index<flann::L2<float>>>(matrix, flann::KDTreeSingleIndexParams(16));
    full.tree->buildIndex();
  } catch (const std::exception& error) {
    return absl::InternalError(StrCat("building the eq. 8 index failed: ", error.what()));
  }
  return std::shared_ptr<const ReconstructionDatabase>(std::move(db));
}

absl::StatusOr<std::vector<Neighbour>> ReconstructionDatabase::NearestByWristsAndAnkles(
    const float query[kWristAnkleFeatureDims], int k) const {
  if (k < 1) return absl::InvalidArgumentError("k must be at least 1");
  for (int d = 0; d < kWristAnkleFeatureDims; ++d) {
    if (!std::isfinite(query[d])) return absl::InvalidArgumentError("query feature is not finite");
  }
  const size_t count = static_cast<size_t>(std::min(k, num_frames()));
  std::vector<float> q(query, query + kWristAnkleFeatureDims);
  std::vector<size_t> indices(count);
  std::vector<float> distances(count);
  flann::Matrix<float> query_matrix(q.data(), 1, kWristAnkleFeatureDims);
  flann::Matrix<size_t> index_matrix(indices.data(), 1, count);
  flann::Matrix<float> distance_matrix(distances.data(), 1, count);
  flann::SearchParams params;
  params.checks = flann::FLANN_CHECKS_UNLIMITED;
  params.sorted = true;
  try {
    full_index_->tree->knnSearch(query_matrix, index_matrix, distance_matrix, count, params);
  } catch (const std::exception& error) {
    return absl::InternalError(StrCat("eq. 8 search failed: ", error.what()));
  }
  std::vector<Neighbour> out(count);
  for (size_t i = 0; i < count; ++i) out[i] = {static_cast<int>(indices[i]), distances[i]};
  return out;
}

}  // namespace mocap
