// `mocapd serve --metrics-listen`: the operator's HTTP /metrics endpoint as the binary runs it (a
// forked mocapd on a temporary store): off by default, logged when on, scraped over HTTP, and a
// start that fails with an error line and exit code 1 when its address is taken.
#include <sys/wait.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <httplib.h>

#include "tests/support/listening_ports.h"
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

namespace mocap {
namespace serve_metrics_test {
namespace {

namespace fs = std::filesystem;

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The log once it holds `pattern` (the server logs right after its stdout line), or as it is after 10 s.
std::string AwaitLog(const fs::path& log, const std::regex& pattern) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  for (;;) {
    const std::string text = ReadFile(log);
    if (std::regex_search(text, pattern) || std::chrono::steady_clock::now() > deadline) return text;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

int PortOf(const std::string& address) { return std::stoi(address.substr(address.rfind(':') + 1)); }

class ServeMetricsTest : public ::testing::Test {
 protected:
  testing::ScopedTempDir temp_;
  const fs::path store_ = temp_.path() / "mocap.db";
  const fs::path log_ = temp_.path() / "server.log";
};

TEST_F(ServeMetricsTest, MetricsListenServesScrapesAndLogsItsAddress) {
  testing::ServerProcess server(MOCAPD_PATH, store_, log_, {"--metrics-listen", "127.0.0.1:0"});
  ASSERT_FALSE(server.address().empty()) << ReadFile(log_);
  const std::regex logged(R"(serving metrics on http://127\.0\.0\.1:(\d+)/metrics)");
  const std::string log = AwaitLog(log_, logged);
  std::smatch match;
  ASSERT_TRUE(std::regex_search(log, match, logged)) << log;
  const int port = std::stoi(match[1].str());
  EXPECT_EQ(testing::ListeningPorts(server.pid()), (std::set<int>{PortOf(server.address()), port}));

  httplib::Client http("127.0.0.1", port);
  http.set_connection_timeout(5);
  http.set_read_timeout(5);
  const auto scraped = http.Get("/metrics");
  ASSERT_TRUE(scraped) << httplib::to_string(scraped.error());
  EXPECT_EQ(scraped->status, 200);
  EXPECT_EQ(scraped->get_header_value("Content-Type"), "text/plain; version=0.0.4; charset=utf-8");
  EXPECT_NE(scraped->body.find("\n# TYPE mocap_calls_total counter\n"), std::string::npos) << scraped->body;
  EXPECT_NE(scraped->body.find("\nmocap_sessions_active 0\n"), std::string::npos) << scraped->body;
  const auto other = http.Get("/");
  ASSERT_TRUE(other);
  EXPECT_EQ(other->status, 404);
  EXPECT_EQ(server.Stop(), 0);
  EXPECT_NE(ReadFile(log_).find("stopped"), std::string::npos);
}

TEST_F(ServeMetricsTest, WithoutTheFlagOnlyTheGrpcPortListens) {
  testing::ServerProcess server(MOCAPD_PATH, store_, log_);
  ASSERT_FALSE(server.address().empty()) << ReadFile(log_);
  const std::string log = AwaitLog(log_, std::regex("serving store"));
  EXPECT_EQ(testing::ListeningPorts(server.pid()), std::set<int>{PortOf(server.address())});
  EXPECT_EQ(log.find("metrics"), std::string::npos) << log;
}

TEST_F(ServeMetricsTest, AnAddressInUseEndsTheStartWithAnError) {
  testing::ServerProcess first(MOCAPD_PATH, store_, log_);
  ASSERT_FALSE(first.address().empty()) << ReadFile(log_);
  // The first server's gRPC port.
  const std::string command = std::string(MOCAPD_PATH) + " serve --store " + store_.string() +
                              " --listen 127.0.0.1:0 --metrics-listen " + first.address() + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) output.append(buffer.data(), n);
  const int status = pclose(pipe);
  ASSERT_TRUE(WIFEXITED(status)) << output;
  EXPECT_EQ(WEXITSTATUS(status), 1) << output;
  EXPECT_NE(output.find("cannot listen for metrics on " + first.address() + " (--metrics-listen)"), std::string::npos)
      << output;
  EXPECT_EQ(output.find("listening on"), std::string::npos) << output;
}

}  // namespace
}  // namespace serve_metrics_test
}  // namespace mocap
