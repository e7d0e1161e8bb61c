// ServerMetrics' Prometheus text: the server's series, the operator's view with every tenant's
// labelled by name (escaped), and the format a scraper reads (tests/support/prometheus_text.h).
#include "server/server_metrics.h"

#include <gtest/gtest.h>

#include <string>

#include "server/metrics_http.h"
#include "tests/support/prometheus_text.h"

namespace mocap {
namespace server_metrics_test {
namespace {

using testing::PrometheusTextProblems;

bool HasLine(const std::string& text, const std::string& line) {
  return ("\n" + text).find("\n" + line + "\n") != std::string::npos;
}

TEST(PrometheusLabelValueTest, EscapesBackslashQuoteAndLineFeed) {
  EXPECT_EQ(PrometheusLabelValue("acme"), "acme");
  EXPECT_EQ(PrometheusLabelValue(R"(a"b\c)"), R"(a\"b\\c)");
  EXPECT_EQ(PrometheusLabelValue("two\nlines"), R"(two\nlines)");
  EXPECT_EQ(PrometheusLabelValue("tab\tand ünïcode"), "tab\tand ünïcode");  // kept as they are
  EXPECT_EQ(PrometheusLabelValue(""), "");
}

TEST(ServerMetricsTest, ServerTextIsValidAndHasNoTenants) {
  ServerMetrics metrics;
  metrics.CallStarted();
  metrics.CallFinished("ListDatabases", "OK", 0.25);
  metrics.Rejected("bad_key");
  metrics.ReplyLatency(0.004);
  metrics.ReplyLatency(2.0);
  metrics.OfTenant(2, "acme").CallStarted();
  const std::string text = metrics.PrometheusText();
  EXPECT_TRUE(PrometheusTextProblems(text).empty()) << ::testing::PrintToString(PrometheusTextProblems(text)) << text;
  EXPECT_TRUE(HasLine(text, R"(mocap_calls_total{method="ListDatabases",code="OK"} 1)")) << text;
  EXPECT_TRUE(HasLine(text, R"(mocap_call_seconds_total{method="ListDatabases"} 0.25)")) << text;
  EXPECT_TRUE(HasLine(text, R"(mocap_rejected_total{limit="bad_key"} 1)")) << text;
  EXPECT_TRUE(HasLine(text, R"(mocap_reply_latency_seconds_bucket{le="0.005"} 1)")) << text;
  EXPECT_TRUE(HasLine(text, R"(mocap_reply_latency_seconds_bucket{le="1"} 1)")) << text;
  EXPECT_TRUE(HasLine(text, R"(mocap_reply_latency_seconds_bucket{le="+Inf"} 2)")) << text;
  EXPECT_TRUE(HasLine(text, "mocap_reply_latency_seconds_sum 2.004")) << text;
  EXPECT_TRUE(HasLine(text, "mocap_reply_latency_seconds_count 2")) << text;
  EXPECT_TRUE(HasLine(text, "mocap_calls_in_flight 0")) << text;
  EXPECT_EQ(text.find("tenant"), std::string::npos) << "GetMetrics' text names no tenant";
}

TEST(ServerMetricsTest, OperatorTextLabelsEveryTenantsSeriesByName) {
  ServerMetrics metrics;
  // Two calls of acme, one of a tenant whose name needs escaping (a store can hold any text), one
  // refused before any tenant was known.
  for (int i = 0; i < 2; ++i) {
    MetricsScope call(metrics, &metrics.OfTenant(2, "acme"));
    metrics.CallStarted();
    metrics.OfTenant(2).CallStarted();
    call.CallFinished("ListDatabases", "OK", 0.5);
  }
  ServerMetrics& odd = metrics.OfTenant(3, "we\"ird\\name\nx");
  MetricsScope call(metrics, &odd);
  metrics.CallStarted();
  odd.CallStarted();
  call.CallFinished("ImportBvh", "RESOURCE_EXHAUSTED", 0.125);
  call.Rejected("file_bytes");
  call.ReplyLatency(0.03);
  call.SessionStarted();
  metrics.Rejected("no_key");

  const std::string text = metrics.PrometheusTextWithTenants();
  EXPECT_TRUE(PrometheusTextProblems(text).empty()) << ::testing::PrintToString(PrometheusTextProblems(text)) << text;
  EXPECT_EQ(text.rfind(metrics.PrometheusText(), 0), 0u) << "the server's series first, as GetMetrics gives them";
  // The server's: every call once.
  EXPECT_TRUE(HasLine(text, R"(mocap_calls_total{method="ListDatabases",code="OK"} 2)")) << text;
  EXPECT_TRUE(HasLine(text, R"(mocap_calls_total{method="ImportBvh",code="RESOURCE_EXHAUSTED"} 1)")) << text;
  EXPECT_TRUE(HasLine(text, R"(mocap_rejected_total{limit="no_key"} 1)")) << text;
  EXPECT_TRUE(HasLine(text, "mocap_sessions_active 1")) << text;
  // Each tenant's, labelled first by its name.
  const std::string odd_label = R"(tenant="we\"ird\\name\nx")";
  EXPECT_TRUE(HasLine(text, R"(mocap_tenant_calls_total{tenant="acme",method="ListDatabases",code="OK"} 2)")) << text;
  EXPECT_TRUE(HasLine(text, R"(mocap_tenant_call_seconds_total{tenant="acme",method="ListDatabases"} 1)")) << text;
  EXPECT_TRUE(
      HasLine(text, "mocap_tenant_calls_total{" + odd_label + R"(,method="ImportBvh",code="RESOURCE_EXHAUSTED"} 1)"))
      << text;
  EXPECT_TRUE(HasLine(text, "mocap_tenant_rejected_total{" + odd_label + R"(,limit="file_bytes"} 1)")) << text;
  EXPECT_TRUE(HasLine(text, "mocap_tenant_reply_latency_seconds_bucket{" + odd_label + R"(,le="0.05"} 1)")) << text;
  EXPECT_TRUE(HasLine(text, R"(mocap_tenant_reply_latency_seconds_count{tenant="acme"} 0)")) << text;
  EXPECT_TRUE(HasLine(text, "mocap_tenant_sessions_active{" + odd_label + "} 1")) << text;
  EXPECT_TRUE(HasLine(text, R"(mocap_tenant_sessions_active{tenant="acme"} 0)")) << text;
  EXPECT_TRUE(HasLine(text, R"(mocap_tenant_calls_in_flight{tenant="acme"} 0)")) << text;
  EXPECT_TRUE(HasLine(text, "# TYPE mocap_tenant_calls_total counter")) << text;
  EXPECT_EQ(text.find("limit=\"no_key\"} 1", text.find("mocap_tenant_")), std::string::npos)
      << "a call refused before its tenant was known counts for the server only";
  // A tenant's own text (GetMetrics with its key) holds its counters alone, without any label.
  const std::string own = metrics.OfTenant(2).PrometheusText();
  EXPECT_TRUE(HasLine(own, R"(mocap_calls_total{method="ListDatabases",code="OK"} 2)")) << own;
  EXPECT_EQ(own.find(R"(method="ImportBvh")"), std::string::npos) << own;
  EXPECT_EQ(own.find("tenant"), std::string::npos) << own;
}

TEST(ServerMetricsTest, OperatorTextWithoutTenantsIsTheServers) {
  ServerMetrics metrics;
  metrics.Rejected("bad_key");
  EXPECT_EQ(metrics.PrometheusTextWithTenants(), metrics.PrometheusText());
}

TEST(ParseHostPortTest, TakesHostAndPortAndRefusesTheRest) {
  auto parsed = ParseHostPort("127.0.0.1:9464", "--metrics-listen");
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  EXPECT_EQ(parsed->host, "127.0.0.1");
  EXPECT_EQ(parsed->port, 9464);
  parsed = ParseHostPort("[::1]:0", "--metrics-listen");
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  EXPECT_EQ(parsed->host, "::1");
  EXPECT_EQ(parsed->port, 0);
  for (const char* bad : {"9464", ":9464", "localhost:", "localhost:x", "localhost:65536", "localhost:-1", "::1:9464",
                          "[]:9464", "host:94 64"}) {
    const auto refused = ParseHostPort(bad, "--metrics-listen");
    EXPECT_EQ(refused.status().code(), absl::StatusCode::kInvalidArgument) << bad;
    EXPECT_NE(refused.status().message().find("--metrics-listen"), std::string_view::npos) << refused.status();
  }
}

}  // namespace
}  // namespace server_metrics_test
}  // namespace mocap
