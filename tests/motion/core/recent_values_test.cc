#include "motion/core/recent_values.h"

#include <algorithm>
#include <vector>

#include <gtest/gtest.h>

namespace mocap {
namespace {

TEST(RecentValuesTest, KeepsTheNewestUpToItsCapacityNewestFirst) {
  RecentValues<int> ring(3);
  EXPECT_TRUE(ring.empty());
  ring.Push(1);
  ring.Push(2);
  ASSERT_EQ(ring.size(), 2u);
  EXPECT_EQ(ring.Back(0), 2);
  EXPECT_EQ(ring.Back(1), 1);
  for (int v = 3; v <= 7; ++v) ring.Push(v);
  ASSERT_EQ(ring.size(), 3u);
  EXPECT_EQ(ring.capacity(), 3u);
  EXPECT_EQ(ring.Back(0), 7);
  EXPECT_EQ(ring.Back(1), 6);
  EXPECT_EQ(ring.Back(2), 5);
}

TEST(RecentValuesTest, UnorderedHoldsExactlyTheValuesKept) {
  RecentValues<int> ring(4);
  ring.Push(10);
  ring.Push(20);
  std::vector<int> kept(ring.Unordered().begin(), ring.Unordered().end());
  std::sort(kept.begin(), kept.end());
  EXPECT_EQ(kept, (std::vector<int>{10, 20}));
  for (int v = 1; v <= 6; ++v) ring.Push(v);
  kept.assign(ring.Unordered().begin(), ring.Unordered().end());
  std::sort(kept.begin(), kept.end());
  EXPECT_EQ(kept, (std::vector<int>{3, 4, 5, 6}));
}

TEST(RecentValuesTest, ClearForgetsAndResizeChangesTheCapacity) {
  RecentValues<int> ring(2);
  ring.Push(1);
  ring.Push(2);
  ring.Clear();
  EXPECT_TRUE(ring.empty());
  ring.Push(3);
  EXPECT_EQ(ring.size(), 1u);
  EXPECT_EQ(ring.Back(0), 3);
  ring.Resize(5);
  EXPECT_TRUE(ring.empty());
  EXPECT_EQ(ring.capacity(), 5u);
  RecentValues<int> none;
  none.Push(1);
  EXPECT_TRUE(none.empty()) << "a ring of capacity 0 keeps nothing";
}

}  // namespace
}  // namespace mocap
