#include "motion/reconstruct/reconstruction_database.h"

#include <algorithm>
#include <cmath>

#include "motion/core/str_cat.h"

namespace mocap {

void WristAnkleFeature(const FrameFeatures& f, const WristAnkleWeights& weights, float out[kWristAnkleFeatureDims]) {
  const float p = std::sqrt(weights.position_weight), v = std::sqrt(1.0f - weights.position_weight);
  const float ap = p * weights.ankle_position_scale, av = v * weights.ankle_velocity_scale;
  for (int side = 0; side < 2; ++side) {
    for (int axis = 0; axis < 3; ++axis) {
      out[3 * side + axis] = p * f.wrist_position[side][axis];
      out[6 + 3 * side + axis] = ap * f.ankle_position[side][axis];
      out[12 + 3 * side + axis] = v * f.wrist_velocity[side][axis];
      out[18 + 3 * side + axis] = av * f.ankle_velocity[side][axis];
    }
  }
}

namespace {

// Frames whose pelvis moves over the ground at `min_speed` or more, measured between the frames
// 1/6 s before and after (a step's stop within a walk still counts as walking).
std::vector<bool> TravellingFrames(const std::vector<FrameFeatures>& clip, double frame_time, float min_speed) {
  const int frames = static_cast<int>(clip.size());
  const int half = std::max(1, static_cast<int>(std::lround(1.0 / 6.0 / frame_time)));
  std::vector<Eigen::Vector2f> pelvis(frames);
  for (int f = 0; f < frames; ++f) {
    const ReferenceFrame ref = ReferenceFrameOf(clip[f]);
    const Eigen::Vector3f world =
        ref.origin + ref.rotation * Eigen::Map<const Eigen::Vector3f>(clip[f].pelvis_position);
    pelvis[f] = Eigen::Vector2f(world.x(), world.z());  // over the ground
  }
  std::vector<bool> travelling(frames, false);
  for (int f = 0; f < frames; ++f) {
    const int a = std::max(0, f - half), b = std::min(frames - 1, f + half);
    if (b > a) travelling[f] = (pelvis[b] - pelvis[a]).norm() >= min_speed * static_cast<float>((b - a) * frame_time);
  }
  return travelling;
}

// 16-bit fixed point per column: each column's step is its largest magnitude / 32767, so every
// value is kept to half a step (issue #26: the pose rows were a third of a database's memory).
template <typename FloatRows, typename IntRows>
void QuantizePoseFeatures(const FloatRows& values, IntRows* stored, Eigen::RowVectorXf* step) {
  constexpr float kLargest = 32767.0f;
  *step = values.cwiseAbs().colwise().maxCoeff() / kLargest;
  for (Eigen::Index c = 0; c < step->size(); ++c) {
    if (!((*step)[c] > 0.0f)) (*step)[c] = 1.0f;  // an all-zero column
  }
  *stored = (values.array().rowwise() / step->array())
                .round()
                .cwiseMax(-kLargest)
                .cwiseMin(kLargest)
                .template cast<int16_t>();
}

}  // namespace

absl::StatusOr<std::shared_ptr<const ReconstructionDatabase>> ReconstructionDatabase::Build(
    const RigModel& rig, const std::vector<DatabaseClip>& clips, const DatabaseBuildOptions& options) {
  const WristAnkleWeights& eq8 = options.pose_query;
  auto usable_scale = [](float scale) { return std::isfinite(scale) && scale >= 0.0f; };
  if (!(eq8.position_weight >= 0.0f && eq8.position_weight <= 1.0f) || !usable_scale(eq8.ankle_position_scale) ||
      !usable_scale(eq8.ankle_velocity_scale)) {
    return absl::InvalidArgumentError("eq. 8 weights: α must lie in [0, 1] and the ankle scales be finite and ≥ 0");
  }
  std::shared_ptr<ReconstructionDatabase> db(new ReconstructionDatabase());
  db->rig_ = rig;
  db->eq2_options_ = options.wrist_query;
  db->eq8_weights_ = options.pose_query;
  db->frame_time_ = options.frame_time;
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
  db->captured_frames_ = static_cast<int>(total);
  // Every row's whole A1 features while the indices are built; the database keeps DatabaseFrames.
  std::vector<FrameFeatures> row_features;
  row_features.reserve(total);
  db->clip_of_row_.reserve(total);
  db->frame_of_row_.reserve(total);
  Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> pose_features(
      static_cast<Eigen::Index>(total), 2 + 3 * static_cast<Eigen::Index>(db->pose_joints_.size()));
  for (size_t c = 0; c < clips.size(); ++c) {
    for (size_t f = 0; f < clips[c].features.size(); ++f) {
      const int row = static_cast<int>(row_features.size());
      const FrameFeatures& features = clips[c].features[f];
      row_features.push_back(features);
      db->clip_of_row_.push_back(static_cast<int>(c));
      db->frame_of_row_.push_back(static_cast<int>(f));
      auto m = pose_features.row(row);
      m[0] = features.pelvis_tilt;
      m[1] = features.pelvis_height;
      const float* pose = clips[c].encoded_poses.data() + f * stride;
      for (size_t i = 0; i < db->pose_joints_.size(); ++i) {
        for (int axis = 0; axis < 3; ++axis) m[2 + 3 * i + axis] = pose[3 + 3 * db->pose_joints_[i] + axis];
      }
    }
  }
  if (!pose_features.allFinite()) return absl::InvalidArgumentError("a clip's pose is not a finite number");
  QuantizePoseFeatures(pose_features, &db->pose_features_, &db->pose_feature_step_);
  // The body the solver drives: the rig's offsets in metres.
  std::vector<Joint> body_joints = rig.skeleton.joints();
  const float metres = static_cast<float>(MetresPerUnit(rig.unit));
  for (Joint& joint : body_joints) {
    joint.offset *= metres;
    if (joint.end_site) *joint.end_site *= metres;
  }
  absl::StatusOr<BodyModel> body = BodyModel::Create(rig, Skeleton(std::move(body_joints)), db->pose_joints_);
  if (!body.ok()) return body.status();
  db->body_.emplace(std::move(*body));
  if (options.time_reversed_copies) {
    // Each clip backwards, last frame first; the pose rows stay shared (clip_frame_row).
    int clip_start = 0;
    for (const DatabaseClip& clip : clips) {
      const int frames = static_cast<int>(clip.features.size());
      const std::vector<FrameFeatures> reversed = PlayedBackwards(clip.features);
      const std::vector<bool> travelling =
          TravellingFrames(clip.features, options.frame_time, options.reversed_min_ground_speed);
      for (int f = frames - 1; f >= 0; --f) {
        if (!travelling[f]) continue;
        row_features.push_back(reversed[frames - 1 - f]);
        db->reversed_source_.push_back(clip_start + f);
      }
      clip_start += frames;
    }
    db->reversed_source_.shrink_to_fit();  // the copies' count was not known
  }
  const size_t rows = row_features.size();
  std::vector<float> lower_ankle(total);
  for (size_t r = 0; r < total; ++r) {
    lower_ankle[r] = std::min(row_features[r].ankle_position[0][1], row_features[r].ankle_position[1][1]);
  }
  std::nth_element(lower_ankle.begin(), lower_ankle.begin() + total / 10, lower_ankle.end());
  db->planted_ankle_height_ = lower_ankle[total / 10];
  std::vector<std::span<const FrameFeatures>> clip_features;
  for (const DatabaseClip& clip : clips) clip_features.emplace_back(clip.features);
  db->motion_limits_ = MeasureMotionLimits(clip_features, options.frame_time);
  db->wrist_reach_ = MeasureWristReach(std::span<const FrameFeatures>(row_features.data(), total));
  if (absl::Status status = db->wrist_index_.Build(row_features, db->eq2_options_); !status.ok()) {
    return status;
  }
  std::vector<float> points(rows * kWristAnkleFeatureDims);
  for (size_t r = 0; r < rows; ++r)
    WristAnkleFeature(row_features[r], db->eq8_weights_, points.data() + r * kWristAnkleFeatureDims);
  if (absl::Status status = db->full_index_.Build(std::move(points), kWristAnkleFeatureDims); !status.ok())
    return status;
  db->frames_ = ToDatabaseFrames(row_features);
  return std::shared_ptr<const ReconstructionDatabase>(std::move(db));
}

ReconstructionDatabase::MemoryUse ReconstructionDatabase::memory_use() const {
  MemoryUse use;
  use.features = frames_.capacity() * sizeof(DatabaseFrame);
  use.pose_features = static_cast<size_t>(pose_features_.size()) * sizeof(int16_t);
  use.row_maps = (reversed_source_.capacity() + clip_of_row_.capacity() + frame_of_row_.capacity()) * sizeof(int);
  use.wrist_index = wrist_index_.memory_bytes();
  use.full_index = full_index_.memory_bytes();
  return use;
}

absl::StatusOr<std::vector<Neighbour>> ReconstructionDatabase::NearestByWristsAndAnkles(
    const float query[kWristAnkleFeatureDims], int k) const {
  return full_index_.Search(query, k);
}

}  // namespace mocap
