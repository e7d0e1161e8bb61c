#include "server/stream_capacity.h"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

namespace mocap {
namespace {

TEST(StreamCapacityTest, RefusesPastTheMostAndFreesOnTicketDrop) {
  StreamCapacity capacity(4);
  EXPECT_EQ(capacity.max_per_tenant(), 3);
  auto first = capacity.Admit(1);
  auto second = capacity.Admit(2);
  auto third = capacity.Admit(2);
  auto fourth = capacity.Admit(3);
  ASSERT_TRUE(first.ok() && second.ok() && third.ok() && fourth.ok());
  EXPECT_EQ(capacity.live(), 4);
  auto fifth = capacity.Admit(4);
  EXPECT_EQ(fifth.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_NE(fifth.status().message().find("carries 4 live reconstruction streams"), std::string::npos)
      << fifth.status();
  EXPECT_NE(fifth.status().message().find("--max-streams"), std::string::npos) << fifth.status();
  EXPECT_EQ(capacity.live(), 4);  // a refusal holds nothing
  first->reset();
  EXPECT_EQ(capacity.live(), 3);
  EXPECT_TRUE(capacity.Admit(4).ok());  // admitted, and its ticket dropped at once
  EXPECT_EQ(capacity.live(), 3);
}

TEST(StreamCapacityTest, OneTenantLeavesAQuarterForTheOthers) {
  StreamCapacity capacity(8);
  std::vector<StreamCapacity::Ticket> flood;
  for (int i = 0; i < 6; ++i) {
    auto ticket = capacity.Admit(7);
    ASSERT_TRUE(ticket.ok()) << i << ": " << ticket.status();
    flood.push_back(*std::move(ticket));
  }
  auto seventh = capacity.Admit(7);
  EXPECT_EQ(seventh.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_NE(seventh.status().message().find("this tenant holds 6 of this server's 8"), std::string::npos)
      << seventh.status();
  EXPECT_TRUE(capacity.Admit(8).ok());  // another tenant still gets in
  EXPECT_EQ(StreamCapacity(1).max_per_tenant(), 1);
  // The only tenant with keys gets the whole server.
  StreamCapacity alone(4);
  std::vector<StreamCapacity::Ticket> all;
  for (int i = 0; i < 4; ++i) {
    auto ticket = alone.Admit(7, /*shared=*/false);
    ASSERT_TRUE(ticket.ok()) << i << ": " << ticket.status();
    all.push_back(*std::move(ticket));
  }
  EXPECT_FALSE(alone.Admit(7, false).ok());
}

TEST(StreamCapacityTest, ManyThreadsNeverAdmitMoreThanTheMost) {
  StreamCapacity capacity(5);
  std::vector<std::thread> threads;
  std::vector<StreamCapacity::Ticket> held(8);  // a ticket holds no object: use_count says it is held
  for (int t = 0; t < 8; ++t) {
    threads.emplace_back([&, t] {
      for (int i = 0; i < 2000; ++i) {
        auto ticket = capacity.Admit(static_cast<TenantId>(t % 3));
        EXPECT_LE(capacity.live(), 5);
        if (ticket.ok() && i == 1999) held[t] = *std::move(ticket);
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  int kept = 0;
  for (const auto& ticket : held) kept += ticket.use_count() > 0;
  EXPECT_EQ(capacity.live(), kept);
  EXPECT_LE(kept, 5);
}

}  // namespace
}  // namespace mocap
