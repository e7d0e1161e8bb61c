// mocap-load end to end: the load generator against a real `mocapd serve` on loopback, and its
// latency percentiles.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "client/load/latency_summary.h"
#include "tests/support/server_fixture.h"

namespace mocap {
namespace {

TEST(LatencySummaryTest, NearestRankPercentiles) {
  std::vector<double> values;
  for (int i = 100; i >= 1; --i) values.push_back(i);  // unsorted on purpose
  const load::LatencySummary summary = load::Summarise(values);
  EXPECT_EQ(summary.count, 100);
  EXPECT_DOUBLE_EQ(summary.p50_ms, 50);
  EXPECT_DOUBLE_EQ(summary.p90_ms, 90);
  EXPECT_DOUBLE_EQ(summary.p99_ms, 99);
  EXPECT_DOUBLE_EQ(summary.max_ms, 100);
  EXPECT_DOUBLE_EQ(summary.mean_ms, 50.5);
  EXPECT_DOUBLE_EQ(load::Summarise({7}).p99_ms, 7);
  EXPECT_EQ(load::Summarise({}).count, 0);
}

TEST(LatencySummaryTest, BySecondOfTheRun) {
  // Seconds 0 and 2 have latencies, 1 has none; a send a little before the start counts in 0.
  const std::vector<load::LatencySummary> by_second = load::SummariseBySecond({3, 5, 40, 7}, {0.2, -0.01, 2.5, 2.9});
  ASSERT_EQ(by_second.size(), 3u);
  EXPECT_EQ(by_second[0].count, 2);
  EXPECT_DOUBLE_EQ(by_second[0].max_ms, 5);
  EXPECT_EQ(by_second[1].count, 0);
  EXPECT_EQ(by_second[2].count, 2);
  EXPECT_DOUBLE_EQ(by_second[2].p99_ms, 40);
  EXPECT_TRUE(load::SummariseBySecond({}, {}).empty());
}

class LoadGeneratorTest : public testing::ServerFixture {
 protected:
  // A server whose tenant "acme" has the database "walks".
  void SetUp() override {
    ServerFixture::SetUp();
    StartServer();
    ImportWalks(*Connect(keys_["acme"]));
  }
  struct Run {
    int exit_code = -1;
    std::string out;
  };
  Run Load(const std::string& key, const std::string& extra) {
    const std::string command = std::string(MOCAP_LOAD_PATH) + " --address " + server_->address() + " --key " + key +
                                " --database walks --bvh " + WriteClip("query.bvh", 60).string() +
                                " --json --k1 60 --k2 40 " + extra + " 2>" + (dir_ / "load.log").string();
    Run run;
    FILE* pipe = popen(command.c_str(), "r");
    char buffer[4096];
    while (size_t n = fread(buffer, 1, sizeof buffer, pipe)) run.out.append(buffer, n);
    const int status = pclose(pipe);
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return run;
  }
};

TEST_F(LoadGeneratorTest, ConcurrentStreamsReturnEveryFrameWithLatencies) {
  const Run run = Load(keys_["acme"], "--streams 3 --seconds 1.5 --lag 2 --ramp-seconds 0.2");
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const nlohmann::json report = nlohmann::json::parse(run.out);
  EXPECT_EQ(report["streams_ok"], 3);
  EXPECT_EQ(report["samples_sent"], 3 * 45);
  EXPECT_EQ(report["frames"], 3 * 45);
  // Every frame but the last `lag` of each stream (completed by the end of input, not a sample)
  // has a latency.
  EXPECT_EQ(report["latency_ms"]["count"], 3 * (45 - 2));
  EXPECT_GT(report["latency_ms"]["p50"].get<double>(), 0.0);
  EXPECT_LE(report["latency_ms"]["p50"].get<double>(), report["latency_ms"]["p99"].get<double>());
  // The same latencies by second of the run (1.5 s of input from a start within 0.2 s + 0.2 s).
  long by_second = 0;
  for (const nlohmann::json& second : report["latency_by_second_ms"]) by_second += second["count"].get<long>();
  EXPECT_EQ(by_second, report["latency_ms"]["count"].get<long>());
  EXPECT_GE(report["latency_by_second_ms"].size(), 2u);
  EXPECT_TRUE(report["errors"].empty());
}

TEST_F(LoadGeneratorTest, ErrorsAreCountedAndFailTheRun) {
  // The other tenant's key does not see "walks": every stream fails with NOT_FOUND.
  const Run run = Load(keys_["other"], "--streams 2 --seconds 0.5");
  EXPECT_EQ(run.exit_code, 1) << run.out;
  const nlohmann::json report = nlohmann::json::parse(run.out);
  EXPECT_EQ(report["streams_ok"], 0);
  ASSERT_EQ(report["errors"].size(), 1u) << report.dump();
  EXPECT_NE(report["errors"].begin().key().find("NOT_FOUND"), std::string::npos);
  EXPECT_EQ(report["errors"].begin().value(), 2);
}

}  // namespace
}  // namespace mocap
