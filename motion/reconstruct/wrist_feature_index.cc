#include "motion/reconstruct/wrist_feature_index.h"

#include <algorithm>
#include <cmath>

#include <flann/flann.hpp>

#include "motion/core/str_cat.h"

namespace mocap {

void WristFeature(const FrameFeatures& features, const WristFeatureOptions& options, float out[kWristFeatureDims]) {
  const float p = std::sqrt(options.position_weight);
  const float v = std::sqrt(1.0f - options.position_weight);
  for (int side = 0; side < 2; ++side) {
    for (int axis = 0; axis < 3; ++axis) {
      out[3 * side + axis] = p * features.wrist_position[side][axis];
      out[6 + 3 * side + axis] = v * features.wrist_velocity[side][axis];
    }
  }
}

struct WristFeatureIndex::Impl {
  std::vector<float> data;  // rows x kWristFeatureDims; FLANN does not own it
  int rows = 0;
  std::unique_ptr<flann::Index<flann::L2<float>>> tree;
};

WristFeatureIndex::WristFeatureIndex() : impl_(std::make_unique<Impl>()) {}
WristFeatureIndex::~WristFeatureIndex() = default;
WristFeatureIndex::WristFeatureIndex(WristFeatureIndex&&) noexcept = default;
WristFeatureIndex& WristFeatureIndex::operator=(WristFeatureIndex&&) noexcept = default;

absl::Status WristFeatureIndex::Build(const std::vector<FrameFeatures>& frames, const WristFeatureOptions& options) {
  if (frames.empty()) return absl::FailedPreconditionError("no frames to index");
  if (!(options.position_weight >= 0.0f && options.position_weight <= 1.0f)) {
    return absl::InvalidArgumentError("position weight α must lie in [0, 1]");
  }
  impl_->rows = static_cast<int>(frames.size());
  impl_->data.resize(frames.size() * kWristFeatureDims);
  for (size_t i = 0; i < frames.size(); ++i) WristFeature(frames[i], options, impl_->data.data() + i * kWristFeatureDims);
  try {
    flann::Matrix<float> matrix(impl_->data.data(), frames.size(), kWristFeatureDims);
    impl_->tree = std::make_unique<flann::Index<flann::L2<float>>>(matrix, flann::KDTreeSingleIndexParams(16));
    impl_->tree->buildIndex();
  } catch (const std::exception& error) {
    return absl::InternalError(StrCat("building the wrist index failed: ", error.what()));
  }
  return absl::OkStatus();
}

absl::StatusOr<std::vector<Neighbour>> WristFeatureIndex::Search(const float query[kWristFeatureDims], int k) const {
  if (!impl_->tree) return absl::FailedPreconditionError("wrist index is not built");
  if (k < 1) return absl::InvalidArgumentError("k must be at least 1");
  for (int d = 0; d < kWristFeatureDims; ++d) {
    if (!std::isfinite(query[d])) return absl::InvalidArgumentError("query feature is not finite");
  }
  const size_t count = static_cast<size_t>(std::min(k, impl_->rows));
  std::vector<size_t> indices(count);
  std::vector<float> distances(count);
  std::vector<float> q(query, query + kWristFeatureDims);
  flann::Matrix<float> query_matrix(q.data(), 1, kWristFeatureDims);
  flann::Matrix<size_t> index_matrix(indices.data(), 1, count);
  flann::Matrix<float> distance_matrix(distances.data(), 1, count);
  flann::SearchParams params;
  params.checks = flann::FLANN_CHECKS_UNLIMITED;
  params.sorted = true;
  try {
    impl_->tree->knnSearch(query_matrix, index_matrix, distance_matrix, count, params);
  } catch (const std::exception& error) {
    return absl::InternalError(StrCat("wrist index search failed: ", error.what()));
  }
  std::vector<Neighbour> out(count);
  for (size_t i = 0; i < count; ++i) out[i] = {static_cast<int>(indices[i]), distances[i]};
  return out;
}

absl::StatusOr<std::vector<Neighbour>> WristFeatureIndex::SearchBruteForce(const float query[kWristFeatureDims],
                                                                          int k) const {
  if (impl_->rows == 0) return absl::FailedPreconditionError("wrist index is not built");
  if (k < 1) return absl::InvalidArgumentError("k must be at least 1");
  std::vector<Neighbour> all(impl_->rows);
  for (int row = 0; row < impl_->rows; ++row) {
    const float* x = impl_->data.data() + static_cast<size_t>(row) * kWristFeatureDims;
    float sum = 0.0f;
    for (int d = 0; d < kWristFeatureDims; ++d) {
      const float diff = x[d] - query[d];
      sum += diff * diff;
    }
    all[row] = {row, sum};
  }
  const size_t count = static_cast<size_t>(std::min(k, impl_->rows));
  std::partial_sort(all.begin(), all.begin() + count, all.end(),
                    [](const Neighbour& a, const Neighbour& b) { return a.distance < b.distance; });
  all.resize(count);
  return all;
}

int WristFeatureIndex::size() const { return impl_->rows; }

}  // namespace mocap
