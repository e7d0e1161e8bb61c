// Ankle position clouds of docs/method.md A3: the K1 database frames nearest to the input wrists by
// eq. 2 (WristFeatureIndex), their ankle positions and velocities mapped from each frame's own
// wrist reference frame into the query's world frame.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "absl/status/status.h"
#include "motion/preprocess/frame_features.h"
#include "motion/reconstruct/database_frame.h"
#include "motion/reconstruct/wrist_feature_index.h"
#include "motion/reconstruct/wrist_smoother.h"

namespace mocap {

// One candidate pair of ankles (a DAG node of A4), world coordinates, metres and m/s.
struct AnkleCandidate {
  int row = 0;               // database frame
  float wrist_distance = 0;  // eq. 2 value
  Eigen::Vector3f position[2];
  Eigen::Vector3f velocity[2];
};

// The query side of A1/A3: both wrists' positions and velocities in the reference frame `ref`
// (ankle fields zero).
FrameFeatures WristQueryFeatures(const ReferenceFrame& ref, const SmoothedWrists& wrists);

// Fills `cloud` with the `k` nearest database frames to `wrists`. `heading` carries the
// reference frame's heading between calls (used when the wrists are vertically aligned) and is
// updated. InvalidArgument for non-finite input.
absl::Status FindAnkleCloud(const WristFeatureIndex& index, const std::vector<DatabaseFrame>& database,
                            const WristFeatureOptions& feature_options, const SmoothedWrists& wrists, int k,
                            float* heading, std::vector<AnkleCandidate>* cloud);

}  // namespace mocap
