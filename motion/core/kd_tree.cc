#include "motion/core/kd_tree.h"

#include <algorithm>
#include <cmath>

#include <flann/flann.hpp>

#include "motion/core/str_cat.h"

namespace mocap {
namespace {

using FlannTree = flann::KDTreeSingleIndex<flann::L2<float>>;

// FLANN's single kd-tree holding the only copy of the points. Built with `reorder`, it copies the
// points into leaf order and from then on searches only that copy (searching through its per-row
// pointers into the caller's array instead, as `reorder = false` does, is 2.5x slower at K = 1000:
// mocap_wrist_knn_benchmark). Those pointers are read again only to build, add points, save or
// getPoint, none of which KdTree does after Build, so they are dropped with the caller's array:
// each row then costs its leaf-ordered copy, FLANN's row index and its share of the nodes
// (issue #26: database memory per frame). KdTreeTest searches after the array is gone, under ASan.
class SearchOnlyFlannTree : public FlannTree {
 public:
  using FlannTree::FlannTree;
  void ForgetSourcePoints() {
    // KDTreeSingleIndex re-declares its base's members private; they are NNIndex's, protected.
    std::vector<float*>& rows = this->flann::NNIndex<flann::L2<float>>::points_;
    rows.clear();
    rows.shrink_to_fit();
  }
};

}  // namespace

struct KdTree::Impl {
  int dims = 0;
  int rows = 0;
  std::unique_ptr<SearchOnlyFlannTree> tree;
};

KdTree::KdTree() : impl_(std::make_unique<Impl>()) {}
KdTree::~KdTree() = default;
KdTree::KdTree(KdTree&&) noexcept = default;
KdTree& KdTree::operator=(KdTree&&) noexcept = default;

absl::Status KdTree::Build(std::vector<float> points, int dims) {
  if (dims < 1 || points.empty() || points.size() % static_cast<size_t>(dims) != 0) {
    return absl::FailedPreconditionError("kd-tree needs at least one point of at least one dimension");
  }
  impl_->dims = dims;
  impl_->rows = static_cast<int>(points.size() / dims);
  try {
    flann::Matrix<float> matrix(points.data(), static_cast<size_t>(impl_->rows), static_cast<size_t>(dims));
    impl_->tree = std::make_unique<SearchOnlyFlannTree>(matrix, flann::KDTreeSingleIndexParams(16, /*reorder=*/true));
    impl_->tree->buildIndex();
    impl_->tree->ForgetSourcePoints();
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

absl::StatusOr<std::vector<Neighbour>> BruteForceNearest(std::span<const float> points, int dims, const float* query,
                                                         int k) {
  if (k < 1) return absl::InvalidArgumentError("k must be at least 1");
  if (dims < 1 || points.size() % static_cast<size_t>(dims) != 0) {
    return absl::InvalidArgumentError("points are not whole rows of at least one dimension");
  }
  const size_t rows = points.size() / static_cast<size_t>(dims);
  std::vector<Neighbour> all(rows);
  for (size_t row = 0; row < rows; ++row) {
    const float* x = points.data() + row * static_cast<size_t>(dims);
    float sum = 0.0f;
    for (int d = 0; d < dims; ++d) sum += (x[d] - query[d]) * (x[d] - query[d]);
    all[row] = {static_cast<int>(row), sum};
  }
  const size_t count = std::min(static_cast<size_t>(k), rows);
  std::partial_sort(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(count), all.end(),
                    [](const Neighbour& a, const Neighbour& b) { return a.distance < b.distance; });
  all.resize(count);
  return all;
}

int KdTree::size() const { return impl_->rows; }

size_t KdTree::memory_bytes() const {
  if (!impl_->tree) return 0;
  // FLANN's node pool and row index (usedMemory), and its leaf-ordered copy of the points.
  return static_cast<size_t>(impl_->tree->usedMemory()) +
         static_cast<size_t>(impl_->rows) * static_cast<size_t>(impl_->dims) * sizeof(float);
}
int KdTree::dims() const { return impl_->dims; }

}  // namespace mocap
