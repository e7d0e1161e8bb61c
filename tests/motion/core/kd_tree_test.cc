#include "motion/core/kd_tree.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace mocap {
namespace {

TEST(KdTreeTest, ExactNearestNeighboursInAnyDimension) {
  for (int dims : {1, 3, 24}) {
    std::mt19937 random(static_cast<unsigned>(dims));
    std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
    std::vector<float> points(2000 * dims);
    for (float& v : points) v = uniform(random);
    const std::vector<float> copy = points;
    KdTree tree;
    // The array is freed inside Build: the tree searches its own copy (ASan would see a read).
    ASSERT_TRUE(tree.Build(std::move(points), dims).ok());
    EXPECT_EQ(tree.size(), 2000);
    std::vector<float> query(dims);
    for (float& v : query) v = uniform(random);
    auto found = tree.Search(query.data(), 50);
    ASSERT_TRUE(found.ok());
    std::vector<float> all;
    for (int r = 0; r < 2000; ++r) {
      float d = 0;
      for (int i = 0; i < dims; ++i) d += (copy[r * dims + i] - query[i]) * (copy[r * dims + i] - query[i]);
      all.push_back(d);
    }
    std::sort(all.begin(), all.end());
    for (int i = 0; i < 50; ++i) EXPECT_NEAR((*found)[i].distance, all[i], 1e-5f) << dims << " " << i;
    auto exhaustive = BruteForceNearest(copy, dims, query.data(), 50);
    ASSERT_TRUE(exhaustive.ok());
    for (int i = 0; i < 50; ++i) EXPECT_NEAR((*exhaustive)[i].distance, all[i], 1e-5f) << dims << " " << i;
    EXPECT_GE(tree.memory_bytes(), copy.size() * sizeof(float));  // the leaf-ordered copy
  }
}

TEST(KdTreeTest, ClearErrors) {
  KdTree tree;
  const float query[3] = {0, 0, 0};
  EXPECT_EQ(tree.Search(query, 1).status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ(tree.Build({}, 3).code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ(tree.Build({1, 2, 3, 4}, 3).code(), absl::StatusCode::kFailedPrecondition);  // not whole points
  ASSERT_TRUE(tree.Build({1, 2, 3, 4, 5, 6}, 3).ok());
  EXPECT_EQ(tree.Search(query, 0).status().code(), absl::StatusCode::kInvalidArgument);
  const float nan_query[3] = {0, std::nanf(""), 0};
  EXPECT_EQ(tree.Search(nan_query, 1).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(tree.Search(query, 10)->size(), 2u);
  EXPECT_EQ(BruteForceNearest(std::vector<float>{1, 2, 3, 4}, 3, query, 1).status().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(BruteForceNearest(std::vector<float>{1, 2, 3}, 3, query, 0).status().code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace mocap
