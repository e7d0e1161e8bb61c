// The operator's metrics endpoint (`mocapd serve --metrics-listen HOST:PORT`): plain HTTP on its own
// address, `GET /metrics` answered in the Prometheus text format (version 0.0.4), any other path
// 404. No authentication: it shows every tenant's counters, so it belongs on a loopback or admin
// address. Served by cpp-httplib on a thread of its own with two workers.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "absl/status/statusor.h"

namespace mocap {

// HOST and PORT of "HOST:PORT" ("127.0.0.1:9464", "localhost:0", "[::1]:9464"); InvalidArgument
// naming `option` otherwise.
struct HostPort {
  std::string host;
  int port = 0;
};
absl::StatusOr<HostPort> ParseHostPort(const std::string& address, const std::string& option);

// Content-Type of the Prometheus text exposition format.
inline constexpr char kPrometheusTextContentType[] = "text/plain; version=0.0.4; charset=utf-8";

class MetricsHttpServer {
 public:
  // Listens on `address` (port 0: a free one, see port()) and answers each scrape with `render()`,
  // called on a worker thread (it must be thread-safe). InvalidArgument for an address that is not
  // HOST:PORT, Unavailable when it cannot be bound (taken, not this machine's).
  static absl::StatusOr<std::unique_ptr<MetricsHttpServer>> Start(const std::string& address,
                                                                  std::function<std::string()> render);
  // Stop() and Wait().
  ~MetricsHttpServer();
  MetricsHttpServer(const MetricsHttpServer&) = delete;
  MetricsHttpServer& operator=(const MetricsHttpServer&) = delete;

  int port() const { return port_; }
  // Stops accepting connections; returns at once. Thread-safe, idempotent.
  void Stop();
  // After Stop: returns when the listening thread and its workers have ended, which a scrape in
  // progress or an idle keep-alive connection delays by at most the socket timeouts (about 2 s).
  void Wait();

 private:
  struct State;
  explicit MetricsHttpServer(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
  int port_ = 0;
};

}  // namespace mocap
