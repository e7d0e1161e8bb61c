#include "motion/reconstruct/frame_history.h"

#include <gtest/gtest.h>

namespace mocap {
namespace {

TEST(FrameHistoryTest, AddressesFramesByNumberAfterForgettingOldOnes) {
  FrameHistory<int> history;
  for (int f = 0; f < 1000; ++f) history.push_back(f * 10);
  history.ForgetBefore(990);
  EXPECT_EQ(history.size(), 1000);
  EXPECT_EQ(history.first(), 990);
  EXPECT_EQ(history[990], 9900);
  EXPECT_EQ(history[999], 9990);
  history[995] = -1;
  EXPECT_EQ(history[995], -1);
  const std::span<const int> tail = history.Since(997);
  ASSERT_EQ(tail.size(), 3u);
  EXPECT_EQ(tail[0], 9970);
  history.ForgetBefore(100);  // already forgotten: no effect
  EXPECT_EQ(history.first(), 990);
}

TEST(FrameHistoryTest, StorageStaysBoundedByWhatIsKept) {
  FrameHistory<int> history;
  int most_stored = 0;
  for (int f = 0; f < 100'000; ++f) {
    history.push_back(f);
    history.ForgetBefore(f - 20);  // keep the last 20 frames
    most_stored = std::max(most_stored, history.stored());
    ASSERT_EQ(history[f], f);
    ASSERT_EQ(history[std::max(0, f - 20)], std::max(0, f - 20));
  }
  EXPECT_LE(most_stored, 64 + 21 + 1);
  EXPECT_EQ(history.size(), 100'000);
}

TEST(FrameHistoryTest, ForgettingBeyondTheEndForgetsEverything) {
  FrameHistory<int> history;
  history.push_back(1);
  history.push_back(2);
  history.ForgetBefore(10);
  EXPECT_EQ(history.first(), 2);
  EXPECT_EQ(history.size(), 2);
  history.push_back(3);
  EXPECT_EQ(history[2], 3);
}

}  // namespace
}  // namespace mocap
