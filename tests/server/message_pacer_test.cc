#include "server/message_pacer.h"

#include <chrono>

#include <gtest/gtest.h>

namespace mocap {
namespace {

using std::chrono::milliseconds;
using Clock = MessagePacer::Clock;

TEST(MessagePacerTest, UnpacedReadsAtOnce) {
  MessagePacer pacer({});
  const Clock::time_point now = Clock::now();
  EXPECT_FALSE(pacer.enabled());
  for (int i = 0; i < 10000; ++i) EXPECT_EQ(pacer.Charge(1, now), now);
}

TEST(MessagePacerTest, ABurstIsReadAtOnceAndThenTheRateHolds) {
  MessagePacer pacer({.messages_per_second = 1000, .burst = 10});
  const Clock::time_point start = Clock::now();
  for (int i = 0; i < 9; ++i) EXPECT_LE(pacer.Charge(7, start), start) << "message " << i << " of the burst";
  // The burst is spent: the next read waits one message's share of a second, the one after two.
  EXPECT_EQ(pacer.Charge(7, start), start + milliseconds(1));
  EXPECT_EQ(pacer.Charge(7, start + milliseconds(1)), start + milliseconds(2));
  // Reading at the rate keeps the stream at the rate, however long it goes on.
  Clock::time_point now = start + milliseconds(2);
  for (int i = 0; i < 1000; ++i, now += milliseconds(1)) ASSERT_EQ(pacer.Charge(7, now), now + milliseconds(1));
}

TEST(MessagePacerTest, AnUnsetBurstIsATenthOfASecondsWorth) {
  MessagePacer pacer({.messages_per_second = 1000});
  const Clock::time_point start = Clock::now();
  for (int i = 0; i < 99; ++i) ASSERT_LE(pacer.Charge(4, start), start) << "message " << i;
  EXPECT_EQ(pacer.Charge(4, start), start + milliseconds(1));
}

TEST(MessagePacerTest, ManyStreamsOfOneTenantShareItsBudget) {
  MessagePacer pacer({.messages_per_second = 1000, .burst = 1});
  const Clock::time_point start = Clock::now();
  // 64 streams each reading one message at the same moment: the last may read again 64 ms later.
  Clock::time_point last;
  for (int stream = 0; stream < 64; ++stream) last = pacer.Charge(3, start);
  EXPECT_EQ(last, start + milliseconds(64));
}

TEST(MessagePacerTest, TenantsArePacedApart) {
  MessagePacer pacer({.messages_per_second = 100, .burst = 1});
  const Clock::time_point now = Clock::now();
  for (int i = 0; i < 100; ++i) pacer.Charge(1, now);  // one tenant a second behind its budget
  EXPECT_EQ(pacer.Charge(2, now), now + milliseconds(10)) << "another tenant's first read waits only its own share";
}

TEST(MessagePacerTest, AnIdleTenantsBudgetFillsAgainButNoFurtherThanTheBurst) {
  MessagePacer pacer({.messages_per_second = 1000, .burst = 5});
  const Clock::time_point start = Clock::now();
  for (int i = 0; i < 50; ++i) pacer.Charge(1, start);
  // Ten seconds of silence: five messages at once again, not ten thousand.
  const Clock::time_point later = start + std::chrono::seconds(10);
  for (int i = 0; i < 4; ++i) EXPECT_LE(pacer.Charge(1, later), later);
  EXPECT_GT(pacer.Charge(1, later), later);
}

TEST(MessagePacerTest, ForgetsTenantsWithFullBudgetsWhenTheTableGrows) {
  MessagePacer pacer({.messages_per_second = 1000, .burst = 2});
  const Clock::time_point start = Clock::now();
  for (MessagePacer::Key key = 0; key < 5000; ++key) pacer.Charge(key, start);
  EXPECT_EQ(pacer.tracked_tenants(), 5000u);
  // Every one of those budgets is full again a second later: forgotten, and tenant 1 starts afresh.
  const Clock::time_point later = start + std::chrono::seconds(1);
  EXPECT_LE(pacer.Charge(1, later), later);
  EXPECT_EQ(pacer.tracked_tenants(), 1u);
  EXPECT_EQ(pacer.Charge(1, later), later + milliseconds(1));
}

}  // namespace
}  // namespace mocap
