// KdTree: exact k-nearest-neighbour search (squared L2) over float points, a thin owner of a
// FLANN single kd-tree. FLANN's matrix does not own its data and its default search visits only
// 32 leaves; this wrapper keeps one copy of the points (FLANN's leaf-ordered one), always searches
// exactly, and turns FLANN's exceptions into statuses (STYLE.md §4; FACTS.md: exact and ~8x faster than brute force at
// K = 1000).
//
// Thread safety: Build once; Search is const and safe from many threads at once.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace mocap {

struct Neighbour {
  int row;         // index of the point in the order given to Build
  float distance;  // squared L2
};

// The min(k, rows) nearest of the row-major `points` (rows of `dims` floats) by exhaustive
// comparison, nearest first: the reference for a tree's recall and speed-up. InvalidArgument for
// k < 1, dims < 1 or points that are not whole rows.
absl::StatusOr<std::vector<Neighbour>> BruteForceNearest(std::span<const float> points, int dims, const float* query,
                                                         int k);

class KdTree {
 public:
  KdTree();
  ~KdTree();
  KdTree(KdTree&&) noexcept;
  KdTree& operator=(KdTree&&) noexcept;

  // `points` holds size() rows of `dims` floats, row-major; the tree keeps one leaf-ordered copy
  // and lets `points` go. FailedPrecondition when empty.
  absl::Status Build(std::vector<float> points, int dims);
  // The min(k, size()) nearest rows, nearest first. FailedPrecondition before Build;
  // InvalidArgument for k < 1 or a non-finite query.
  absl::StatusOr<std::vector<Neighbour>> Search(const float* query, int k) const;

  int size() const;
  int dims() const;
  // Bytes this tree holds: its points, FLANN's nodes, index and row pointers.
  size_t memory_bytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mocap
