// ReconstructionDatabase: the immutable, query-ready form of a motion database for docs/method.md
// A3–A6: every frame's A1 features and pose feature m = (θ, h, q), clip boundaries, and the two
// nearest-neighbour indices (A3: wrists only, eq. 2; A5: wrists and ankles, eq. 8). Besides the
// captured frames it may hold the travelling ones played backwards (DatabaseBuildOptions): rows
// [0, num_frames()) are the captured frames, rows [num_frames(), num_rows()) reversed copies.
//
// Thread safety: built once, then shared read-only (const) by any number of sessions.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "absl/status/statusor.h"
#include "motion/core/kd_tree.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/reconstruct/body_model.h"
#include "motion/reconstruct/database_frame.h"
#include "motion/reconstruct/plausibility.h"
#include "motion/reconstruct/wrist_feature_index.h"
#include "motion/reconstruct/wrist_reach.h"

namespace mocap {

// A clip as the database needs it: A1 features and the encoded poses (EncodePoses layout).
struct DatabaseClip {
  std::vector<FrameFeatures> features;
  std::vector<float> encoded_poses;
};

inline constexpr int kWristAnkleFeatureDims = 24;

// How eq. 8 (A5) weighs its terms: α of eq. 2 for the positions against the velocities, and the
// ankles' coordinates scaled against the wrists' (not in the patent, which weighs all four alike;
// docs/method.md A5, stop 84): the A5 examples are found, and weighed, more by where the estimated
// ankles stand and less by how fast the chosen frame's ankles moved.
struct WristAnkleWeights {
  float position_weight = 0.8f;       // α
  float ankle_position_scale = 2.0f;  // × the ankle positions (their squared distance × 4)
  float ankle_velocity_scale = 0.5f;  // × the ankle velocities (their squared distance × 1/4)
};

struct DatabaseBuildOptions {
  // How the two indices weigh their features: eq. 2 (A3, the wrists) and eq. 8 (A5, wrists and
  // ankles). The patent's α is 0.8 in both; each equation keeps its own.
  WristFeatureOptions wrist_query;
  WristAnkleWeights pose_query;
  double frame_time = 1.0 / 30.0;  // the database's frame period, s
  // Also search the travelling frames played backwards (docs/method.md A3, issue #22): a capture
  // of walking forwards, reversed, is a body walking backwards, which few databases hold and users
  // do. Only frames whose pelvis travels over the ground at `reversed_min_ground_speed` or more
  // (over ±1/6 s) are copied: a standing motion reversed (a wave, a bow) is much like one the
  // database has, and every copy costs memory and search time. The reversed frames share their
  // pose rows with the captured ones; only the A1 features (their velocities as the reversed
  // motion measures them) and the two indices grow.
  bool time_reversed_copies = true;
  // m/s: a slow walk. Development split, causal mode: 0.5 / 0.8 / 1.1 m/s → 8 / 7 / 6 clips over
  // the allowed pelvis speed (5 without copies), MPJPE the same to 0.003 cm.
  float reversed_min_ground_speed = 0.8f;
};

// The 24-D eq. 8 feature: √α·(wrist positions, ankle_position_scale × ankle positions),
// √(1−α)·(wrist velocities, ankle_velocity_scale × ankle velocities).
void WristAnkleFeature(const FrameFeatures& features, const WristAnkleWeights& weights,
                       float out[kWristAnkleFeatureDims]);

class ReconstructionDatabase {
 public:
  // InvalidArgument when a clip's poses do not match its features or the rig; FailedPrecondition
  // when there are no frames.
  static absl::StatusOr<std::shared_ptr<const ReconstructionDatabase>> Build(const RigModel& rig,
                                                                             const std::vector<DatabaseClip>& clips,
                                                                             const DatabaseBuildOptions& options = {});

  const RigModel& rig() const { return rig_; }
  // Captured frames (the clips' own), and every searchable row (with the reversed copies).
  int num_frames() const { return captured_frames_; }
  int num_rows() const { return static_cast<int>(frames_.size()); }
  // What every row keeps of its A1 features: ankles and pelvis (a reversed row: its frame's, with
  // the velocities the reversed motion measures).
  const std::vector<DatabaseFrame>& frames() const { return frames_; }
  // Pose feature m of a row: θ, h, then the rotation vectors of every joint below the pelvis
  // chain (the root-to-pelvis joints are the solver's z_R, not part of q). Stored as 16-bit
  // fixed point per column (as animation runtimes keep their clips): a rotation is off by at
  // most π/65534 rad, 0.003°, and h by 1/65534 of the tallest pelvis.
  auto pose_feature(int row) const {
    return pose_features_.row(clip_frame_row(row)).cast<float>().cwiseProduct(pose_feature_step_);
  }
  int pose_feature_size() const { return static_cast<int>(pose_features_.cols()); }
  const std::vector<int>& pose_joints() const { return pose_joints_; }  // joints of q, in order
  int clip_of(int row) const { return clip_of_row_[clip_frame_row(row)]; }
  int frame_in_clip(int row) const { return frame_of_row_[clip_frame_row(row)]; }
  bool is_reversed(int row) const { return row >= captured_frames_; }
  const WristFeatureIndex& wrist_index() const { return wrist_index_; }
  // The weights a query's features take to be compared with the rows': eq. 2's, eq. 8's.
  const WristFeatureOptions& wrist_feature_options() const { return eq2_options_; }
  const WristAnkleWeights& wrist_ankle_weights() const { return eq8_weights_; }
  // The rig with the first performer's offsets in metres, as the A6 solver drives it.
  const BodyModel& body() const { return *body_; }
  // Typical height of a planted ankle (10th percentile of the lower ankle's height): A7's ground.
  float planted_ankle_height() const { return planted_ankle_height_; }
  double frame_time() const { return frame_time_; }
  // How fast the database's own bodies move (plausibility.h), measured when it is built: the
  // motion guard's bounds and the plausibility measures' reference.
  const MotionLimits& motion_limits() const { return motion_limits_; }
  // The farthest its bodies held their wrists apart and up (wrist_reach.h): the performer's size
  // bound.
  const WristReach& wrist_reach() const { return wrist_reach_; }
  // K nearest frames by eq. 8 (exact kd-tree).
  absl::StatusOr<std::vector<Neighbour>> NearestByWristsAndAnkles(const float query[kWristAnkleFeatureDims],
                                                                  int k) const;
  // Bytes the rows and indices hold (what grows with the database; the rig and body are fixed).
  struct MemoryUse {
    size_t features = 0, pose_features = 0, row_maps = 0, wrist_index = 0, full_index = 0;
    size_t total() const { return features + pose_features + row_maps + wrist_index + full_index; }
  };
  MemoryUse memory_use() const;

  ReconstructionDatabase(const ReconstructionDatabase&) = delete;
  ReconstructionDatabase& operator=(const ReconstructionDatabase&) = delete;

 private:
  ReconstructionDatabase() = default;
  // The captured frame a row shows (itself, or the frame a reversed row copies).
  int clip_frame_row(int row) const { return row < captured_frames_ ? row : reversed_source_[row - captured_frames_]; }
  RigModel rig_;
  int captured_frames_ = 0;
  std::vector<int> reversed_source_;  // row num_frames() + i copies captured row reversed_source_[i]
  std::vector<DatabaseFrame> frames_;
  Eigen::Matrix<int16_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> pose_features_;
  Eigen::RowVectorXf pose_feature_step_;  // a column's value per unit of its stored integer
  std::vector<int> pose_joints_;
  std::vector<int> clip_of_row_, frame_of_row_;
  WristFeatureIndex wrist_index_;
  KdTree full_index_;  // eq. 8
  WristFeatureOptions eq2_options_;
  WristAnkleWeights eq8_weights_;
  std::optional<BodyModel> body_;
  float planted_ankle_height_ = 0.0f;
  double frame_time_ = 1.0 / 30.0;
  MotionLimits motion_limits_;
  WristReach wrist_reach_;
};

}  // namespace mocap
