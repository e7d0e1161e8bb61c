// TenantAdmission (server/tenant_admission.h): at most N tickets per tenant at once, counted per
// tenant, refused with RESOURCE_EXHAUSTED naming what is counted, and a slot freed when the last
// copy of its ticket goes.
#include "server/tenant_admission.h"

#include <gtest/gtest.h>

#include <atomic>
#include <barrier>
#include <thread>
#include <vector>

namespace mocap {
// Named, so that helpers do not meet other files' in a unity batch.
namespace tenant_admission_test {
namespace {

using Ticket = TenantAdmission::Ticket;

TEST(TenantAdmissionTest, AdmitsUpToTheLimitThenRefusesNamingIt) {
  TenantAdmission admission(3, "reconstruction sessions");
  std::vector<Ticket> held;
  for (int i = 0; i < 3; ++i) {
    auto ticket = admission.Admit(7);
    ASSERT_TRUE(ticket.ok()) << i << ": " << ticket.status();
    held.push_back(*std::move(ticket));
  }
  auto refused = admission.Admit(7);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_NE(refused.status().message().find("3 reconstruction sessions in progress"), std::string::npos)
      << refused.status();
  EXPECT_NE(refused.status().message().find("(3)"), std::string::npos) << refused.status();
  // Still refused on a second try: a refusal takes no slot and frees none.
  EXPECT_EQ(admission.Admit(7).status().code(), absl::StatusCode::kResourceExhausted);
}

TEST(TenantAdmissionTest, DefaultWordingCountsCalls) {
  TenantAdmission admission(1);
  auto first = admission.Admit(1);
  ASSERT_TRUE(first.ok());
  auto second = admission.Admit(1);
  ASSERT_FALSE(second.ok());
  EXPECT_NE(second.status().message().find("1 calls in progress"), std::string::npos) << second.status();
}

TEST(TenantAdmissionTest, TenantsAreCountedSeparately) {
  TenantAdmission admission(2);
  auto a1 = admission.Admit(1), a2 = admission.Admit(1);
  ASSERT_TRUE(a1.ok() && a2.ok());
  EXPECT_FALSE(admission.Admit(1).ok());
  // Tenant 1 at its limit does not take tenant 2's slots.
  auto b1 = admission.Admit(2), b2 = admission.Admit(2);
  EXPECT_TRUE(b1.ok());
  EXPECT_TRUE(b2.ok());
  EXPECT_FALSE(admission.Admit(2).ok());
  // Ending one of tenant 2's calls frees a slot for tenant 2 only.
  b1->reset();
  EXPECT_FALSE(admission.Admit(1).ok());
  EXPECT_TRUE(admission.Admit(2).ok());
}

TEST(TenantAdmissionTest, DroppingATicketEndsTheCallOnlyWhenItsLastCopyGoes) {
  TenantAdmission admission(1);
  auto ticket = admission.Admit(4);
  ASSERT_TRUE(ticket.ok());
  Ticket copy = *ticket;  // a call's ticket shared by its handler and its task
  ticket->reset();
  EXPECT_FALSE(admission.Admit(4).ok()) << "a copy of the ticket still holds the slot";
  copy.reset();
  auto again = admission.Admit(4);
  EXPECT_TRUE(again.ok()) << again.status();
}

TEST(TenantAdmissionTest, ReleasedSlotsCanBeTakenAgainManyTimes) {
  TenantAdmission admission(2);
  for (int round = 0; round < 100; ++round) {
    auto a = admission.Admit(9), b = admission.Admit(9);
    ASSERT_TRUE(a.ok() && b.ok()) << "round " << round;
    ASSERT_FALSE(admission.Admit(9).ok()) << "round " << round;
  }  // both released at the end of each round
}

TEST(TenantAdmissionTest, ALimitOfZeroRefusesEverything) {
  TenantAdmission admission(0);
  EXPECT_EQ(admission.Admit(1).status().code(), absl::StatusCode::kResourceExhausted);
}

// Threads admitting at once: in every round four threads per tenant ask while the admitted ones
// hold their tickets, so exactly one per tenant is refused; no more than the limit is ever held,
// and every ticket is returned (the full limit is admitted again at the end).
TEST(TenantAdmissionTest, ConcurrentCallersNeverExceedTheLimit) {
  constexpr int kLimit = 3, kThreads = 8, kRounds = 200;
  TenantAdmission admission(kLimit);
  std::atomic<int> holding[2] = {0, 0}, most{0}, admitted{0}, refused{0};
  std::barrier round_start(kThreads), round_end(kThreads);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      for (int round = 0; round < kRounds; ++round) {
        round_start.arrive_and_wait();
        const int side = (round + t) % 2;
        auto ticket = admission.Admit(side + 1);
        if (ticket.ok()) {
          admitted.fetch_add(1);
          const int now = holding[side].fetch_add(1) + 1;
          int seen = most.load();
          while (now > seen && !most.compare_exchange_weak(seen, now)) {
          }
        } else {
          refused.fetch_add(1);
        }
        round_end.arrive_and_wait();  // the admitted ones still hold their tickets here
        if (ticket.ok()) holding[side].fetch_sub(1);
      }  // the ticket is released before the next round starts
    });
  }
  for (std::thread& thread : threads) thread.join();
  EXPECT_EQ(most.load(), kLimit);
  EXPECT_EQ(admitted.load(), 2 * kLimit * kRounds);
  EXPECT_EQ(refused.load(), 2 * (kThreads / 2 - kLimit) * kRounds);
  std::vector<Ticket> all;
  for (TenantId tenant : {1, 2}) {
    for (int i = 0; i < kLimit; ++i) {
      auto ticket = admission.Admit(tenant);
      ASSERT_TRUE(ticket.ok()) << "tenant " << tenant << " slot " << i << " leaked: " << ticket.status();
      all.push_back(*std::move(ticket));
    }
  }
}

}  // namespace
}  // namespace tenant_admission_test
}  // namespace mocap
