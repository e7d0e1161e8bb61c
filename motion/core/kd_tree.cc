#include "motion/core/kd_tree.h"

#include <algorithm>
#include <cmath>

#include <flann/flann.hpp>

#include "motion/core/str_cat.h"

namespace mocap {

struct KdTree::Impl {
  std::vector<float> points;
  int dims = 0;
  int rows = 0;
  std::unique_ptr<flann::Index<flann::L2<float>>> tree;
};

KdTree::KdTree() : impl_(std::make_unique<Impl>()) {}
KdTree::~KdTree() = default;
KdTree::KdTree(KdTree&&) noexcept = default;
KdTree& KdTree::operator=(KdTree&&) noexcept = default;

absl::Status KdTree::Build(std::vector<float> points, int dims) {
  if (dims < 1 || points.empty() || points.size() % static_cast<size_t>(dims) != 0) {
    return absl::FailedPreconditionError("kd-tree needs at least one point of at least one dimension");
  }
  impl_->points = std::move(points);
  impl_->dims = dims;
  impl_->rows = static_cast<int>(impl_->points.size() / dims);
  try {
    flann::Matrix<float> matrix(impl_->points.data(), static_cast<size_t>(impl_->rows), static_cast<size_t>(dims));
    impl_->tree = std::make_unique<flann::Index<flann::L2<float>>>(matrix, flann::KDTreeSingleIndexParams(16));
    impl_->tree->buildIndex();
  } catch (const std::exception& error) {
    impl_->tree.reset();
    return absl::InternalError(StrCat("building the kd-tree failed: ", error.what()));
  }
  return absl::OkStatus();
}

absl::StatusOr<std::vector<Neighbour>> KdTree::Search(const float* query, int k) const {
  if (!impl_->tree) return absl::FailedPreconditionError("kd-tree is not built");
  if (k < 1) return absl::InvalidArgumentError("k must be at least 1");
  std::vector<float> q(query, query + impl_->dims);
  if (!std::all_of(q.begin(), q.end(), [](float v) { return std::isfinite(v); })) {
    return absl::InvalidArgumentError("query is not finite");
  }
  const size_t count = static_cast<size_t>(std::min(k, impl_->rows));
  std::vector<size_t> indices(count);
  std::vector<float> distances(count);
  flann::Matrix<float> query_matrix(q.data(), 1, static_cast<size_t>(impl_->dims));
  flann::Matrix<size_t> index_matrix(indices.data(), 1, count);
  flann::Matrix<float> distance_matrix(distances.data(), 1, count);
  flann::SearchParams params;
  params.checks = flann::FLANN_CHECKS_UNLIMITED;
  params.sorted = true;
  try {
    impl_->tree->knnSearch(query_matrix, index_matrix, distance_matrix, count, params);
  } catch (const std::exception& error) {
    return absl::InternalError(StrCat("kd-tree search failed: ", error.what()));
  }
  std::vector<Neighbour> out(count);
  for (size_t i = 0; i < count; ++i) out[i] = {static_cast<int>(indices[i]), distances[i]};
  return out;
}

int KdTree::size() const { return impl_->rows; }
int KdTree::dims() const { return impl_->dims; }
const float* KdTree::point(int row) const { return impl_->points.data() + static_cast<size_t>(row) * impl_->dims; }

}  // namespace mocap
