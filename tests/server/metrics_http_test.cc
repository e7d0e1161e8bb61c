// The operator's metrics endpoint (`mocapd serve --metrics-listen`): a real MocapServer in this
// process on loopback, calls made as two tenants through the SDK, /metrics scraped over plain HTTP
// (cpp-httplib's client) and read as a scraper reads it; and what a tenant's key still sees
// (ServerStatus.GetMetrics: its own counters, no other tenant's, no labels).
#include <gtest/gtest.h>
#include <httplib.h>
#include <sqlite3.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>

#include "mocap/client.h"
#include "server/grpc_server.h"
#include "server/metrics_http.h"
#include "storage/motion_store.h"
#include "storage/tenant_directory.h"
#include "tests/support/listening_ports.h"
#include "tests/support/prometheus_text.h"
#include "tests/support/temp_dir.h"

namespace mocap {
namespace metrics_http_test {
namespace {

namespace fs = std::filesystem;
using client::Client;

// A tenant name no `mocapd tenant create` accepts, as a store written by other means could hold:
// the endpoint must escape it.
constexpr char kOddTenant[] = "we\"ird\\name\nx";
constexpr char kOddLabel[] = R"(tenant="we\"ird\\name\nx")";

bool HasLine(const std::string& text, const std::string& line) {
  return ("\n" + text).find("\n" + line + "\n") != std::string::npos;
}

class MetricsHttpTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = temp_.path() / "mocap.db";
    auto store = MotionStore::Open(store_);
    ASSERT_TRUE(store.ok()) << store.status();
    TenantDirectory tenants(**store);
    for (const char* name : {"acme", "other"}) {
      auto tenant = tenants.CreateTenant(name);
      ASSERT_TRUE(tenant.ok()) << tenant.status();
      auto key = tenants.AddKey(tenant->id);
      ASSERT_TRUE(key.ok()) << key.status();
      keys_[name] = key->key;
    }
    auto operator_key = tenants.AddKey(kDefaultTenantId);
    ASSERT_TRUE(operator_key.ok()) << operator_key.status();
    keys_["default"] = operator_key->key;
    ASSERT_NO_FATAL_FAILURE(InsertTenant(kOddTenant));
    auto odd = tenants.FindTenant(kOddTenant);
    ASSERT_TRUE(odd.ok()) << odd.status();
    auto key = tenants.AddKey(odd->id);
    ASSERT_TRUE(key.ok()) << key.status();
    keys_[kOddTenant] = key->key;
  }
  void TearDown() override {
    if (server_) server_->Shutdown();
  }

  // Past TenantDirectory's name check, straight into the file.
  void InsertTenant(const std::string& name) {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(store_.c_str(), &db), SQLITE_OK);
    sqlite3_stmt* insert = nullptr;
    ASSERT_EQ(sqlite3_prepare_v2(db, "INSERT INTO tenants (name) VALUES (?)", -1, &insert, nullptr), SQLITE_OK)
        << sqlite3_errmsg(db);
    sqlite3_bind_text(insert, 1, name.c_str(), static_cast<int>(name.size()), SQLITE_TRANSIENT);
    EXPECT_EQ(sqlite3_step(insert), SQLITE_DONE) << sqlite3_errmsg(db);
    sqlite3_finalize(insert);
    sqlite3_close(db);
  }

  ServeOptions Options(const std::string& metrics_listen) const {
    ServeOptions options;
    options.store = store_;
    options.listen = "127.0.0.1:0";
    options.workers = 2;
    options.reconstruction.compute_threads = 1;
    options.drain_timeout = std::chrono::seconds(5);
    options.metrics_listen = metrics_listen;
    return options;
  }
  void Start(const std::string& metrics_listen) {
    auto server = MocapServer::Start(Options(metrics_listen));
    ASSERT_TRUE(server.ok()) << server.status();
    server_ = *std::move(server);
  }
  std::unique_ptr<Client> Connect(const std::string& key) {
    auto client = Client::Connect("127.0.0.1:" + std::to_string(server_->port()), {.api_key = key});
    EXPECT_TRUE(client.ok()) << client.status();
    return client.ok() ? *std::move(client) : nullptr;
  }
  void ListDatabases(const std::string& tenant, int times) {
    auto client = Connect(keys_[tenant]);
    ASSERT_NE(client, nullptr);
    for (int i = 0; i < times; ++i) ASSERT_TRUE(client->ListDatabases().ok()) << tenant;
  }

  testing::ScopedTempDir temp_;
  fs::path store_;
  std::map<std::string, std::string> keys_;
  std::unique_ptr<MocapServer> server_;
};

TEST_F(MetricsHttpTest, ScrapeShowsTheServersAndEachTenantsSeriesLabelled) {
  ASSERT_NO_FATAL_FAILURE(Start("127.0.0.1:0"));
  ASSERT_GT(server_->metrics_port(), 0);
  EXPECT_NE(server_->metrics_port(), server_->port());
  ASSERT_NO_FATAL_FAILURE(ListDatabases("acme", 1));
  ASSERT_NO_FATAL_FAILURE(ListDatabases("other", 2));
  ASSERT_NO_FATAL_FAILURE(ListDatabases(kOddTenant, 1));
  auto forger = Connect("mk_00000000_" + std::string(48, '0'));
  EXPECT_EQ(forger->ListDatabases().status().code(), absl::StatusCode::kUnauthenticated);

  httplib::Client http("127.0.0.1", server_->metrics_port());
  http.set_connection_timeout(5);
  http.set_read_timeout(5);
  const auto scraped = http.Get("/metrics");
  ASSERT_TRUE(scraped) << httplib::to_string(scraped.error());
  EXPECT_EQ(scraped->status, 200);
  EXPECT_EQ(scraped->get_header_value("Content-Type"), "text/plain; version=0.0.4; charset=utf-8");
  const std::string& text = scraped->body;
  const auto problems = testing::PrometheusTextProblems(text);
  EXPECT_TRUE(problems.empty()) << ::testing::PrintToString(problems) << text;

  // The server's series: every call once.
  EXPECT_TRUE(HasLine(text, R"(mocap_calls_total{method="ListDatabases",code="OK"} 4)")) << text;
  EXPECT_TRUE(HasLine(text, R"(mocap_calls_total{method="ListDatabases",code="UNAUTHENTICATED"} 1)")) << text;
  EXPECT_TRUE(HasLine(text, R"(mocap_rejected_total{limit="bad_key"} 1)")) << text;
  EXPECT_TRUE(HasLine(text, "mocap_calls_in_flight 0")) << text;
  EXPECT_TRUE(HasLine(text, "# TYPE mocap_reply_latency_seconds histogram")) << text;
  // Each tenant's, labelled by name (escaped).
  EXPECT_TRUE(HasLine(text, R"(mocap_tenant_calls_total{tenant="acme",method="ListDatabases",code="OK"} 1)")) << text;
  EXPECT_TRUE(HasLine(text, R"(mocap_tenant_calls_total{tenant="other",method="ListDatabases",code="OK"} 2)")) << text;
  EXPECT_TRUE(
      HasLine(text, "mocap_tenant_calls_total{" + std::string(kOddLabel) + R"(,method="ListDatabases",code="OK"} 1)"))
      << text;
  EXPECT_TRUE(HasLine(text, R"(mocap_tenant_sessions_total{tenant="acme"} 0)")) << text;
  EXPECT_EQ(text.find(R"(tenant="default")"), std::string::npos) << "the operator made no call";

  // Anything but /metrics: 404.
  for (const char* path : {"/", "/metrics/", "/metricsx", "/health", "/metrics/../x"}) {
    const auto other = http.Get(path);
    ASSERT_TRUE(other) << path;
    EXPECT_EQ(other->status, 404) << path;
  }
  const auto posted = http.Post("/metrics", "x", "text/plain");
  ASSERT_TRUE(posted);
  EXPECT_EQ(posted->status, 404);
}

TEST_F(MetricsHttpTest, GetMetricsStillGivesATenantItsOwnCountersOnly) {
  ASSERT_NO_FATAL_FAILURE(Start("127.0.0.1:0"));
  ASSERT_NO_FATAL_FAILURE(ListDatabases("acme", 1));
  ASSERT_NO_FATAL_FAILURE(ListDatabases("other", 3));
  ASSERT_NO_FATAL_FAILURE(ListDatabases(kOddTenant, 1));
  for (const char* tenant : {"acme", "other", "default"}) {
    auto metrics = Connect(keys_[tenant])->GetMetrics();
    ASSERT_TRUE(metrics.ok()) << metrics.status();
    EXPECT_TRUE(testing::PrometheusTextProblems(*metrics).empty()) << *metrics;
    // No tenant's series, name or label through any key, the operator's default one included.
    EXPECT_EQ(metrics->find("mocap_tenant_"), std::string::npos) << tenant << ":\n" << *metrics;
    EXPECT_EQ(metrics->find("tenant="), std::string::npos) << tenant << ":\n" << *metrics;
    for (const char* name : {"acme", "other", "weird"}) EXPECT_EQ(metrics->find(name), std::string::npos) << tenant;
  }
  auto acme = Connect(keys_["acme"])->GetMetrics();
  ASSERT_TRUE(acme.ok());
  EXPECT_TRUE(HasLine(*acme, R"(mocap_calls_total{method="ListDatabases",code="OK"} 1)")) << *acme;
  auto other = Connect(keys_["other"])->GetMetrics();
  ASSERT_TRUE(other.ok());
  EXPECT_TRUE(HasLine(*other, R"(mocap_calls_total{method="ListDatabases",code="OK"} 3)")) << *other;
  auto server_wide = Connect(keys_["default"])->GetMetrics();
  ASSERT_TRUE(server_wide.ok());
  EXPECT_TRUE(HasLine(*server_wide, R"(mocap_calls_total{method="ListDatabases",code="OK"} 5)")) << *server_wide;
}

TEST_F(MetricsHttpTest, WithoutTheOptionNothingMoreListens) {
  const std::set<int> before = testing::ListeningPorts();
  ASSERT_NO_FATAL_FAILURE(Start(""));
  EXPECT_EQ(server_->metrics_port(), 0);
  std::set<int> opened = testing::ListeningPorts();
  for (int port : before) opened.erase(port);
  EXPECT_EQ(opened, std::set<int>{server_->port()}) << "the gRPC port alone";
  server_->Shutdown();
  server_.reset();

  ASSERT_NO_FATAL_FAILURE(Start("127.0.0.1:0"));
  opened = testing::ListeningPorts();
  for (int port : before) opened.erase(port);
  EXPECT_EQ(opened, (std::set<int>{server_->port(), server_->metrics_port()}));
}

TEST_F(MetricsHttpTest, AnAddressThatCannotBeBoundFailsTheStart) {
  ASSERT_NO_FATAL_FAILURE(Start(""));
  // Another server's gRPC port (gRPC listens with SO_REUSEPORT; the endpoint must not share it).
  const std::string taken = "127.0.0.1:" + std::to_string(server_->port());
  const auto before = testing::ListeningPorts();
  auto refused = MocapServer::Start(Options(taken));
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), absl::StatusCode::kUnavailable);
  EXPECT_NE(refused.status().message().find("cannot listen for metrics on " + taken), std::string_view::npos)
      << refused.status();
  EXPECT_EQ(testing::ListeningPorts(), before) << "nothing left listening";
  auto malformed = MocapServer::Start(Options("127.0.0.1"));
  EXPECT_EQ(malformed.status().code(), absl::StatusCode::kInvalidArgument) << malformed.status();
  // The gRPC server still answers.
  EXPECT_TRUE(Connect(keys_["acme"])->ListDatabases().ok());
}

TEST_F(MetricsHttpTest, ShutdownStopsTheEndpointWithinTheDrainTime) {
  ASSERT_NO_FATAL_FAILURE(Start("127.0.0.1:0"));
  const int port = server_->metrics_port();
  // A scraper that keeps its connection open between scrapes.
  httplib::Client http("127.0.0.1", port);
  http.set_keep_alive(true);
  http.set_connection_timeout(2);
  http.set_read_timeout(2);
  ASSERT_TRUE(http.Get("/metrics"));
  const auto start = std::chrono::steady_clock::now();
  server_->Shutdown();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 3.0) << "drain time 5 s; the endpoint's threads end within the socket timeouts";
  EXPECT_EQ(testing::ListeningPorts().count(port), 0u);
  httplib::Client after("127.0.0.1", port);
  after.set_connection_timeout(1);
  EXPECT_FALSE(after.Get("/metrics")) << "nothing answers once the server is shut down";
}

}  // namespace
}  // namespace metrics_http_test
}  // namespace mocap
