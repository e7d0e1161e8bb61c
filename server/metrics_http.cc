#include "server/metrics_http.h"

#include <sys/socket.h>

#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstring>
#include <exception>
#include <mutex>

#include <httplib.h>
#include <spdlog/spdlog.h>

#include "motion/core/str_cat.h"

namespace mocap {
namespace {

// A scrape is one small request on loopback: these bound how long a slow or idle connection keeps
// a worker, and so how long Wait() can take after Stop().
constexpr int kReadTimeoutSeconds = 2;
constexpr int kWriteTimeoutSeconds = 2;
constexpr int kKeepAliveSeconds = 1;
constexpr int kWorkers = 2;
// How long Start waits for the listening thread to be up.
constexpr auto kStartTimeout = std::chrono::seconds(10);

}  // namespace

absl::StatusOr<HostPort> ParseHostPort(const std::string& address, const std::string& option) {
  auto invalid = [&](const std::string& why) {
    return absl::InvalidArgumentError(
        StrCat(option, " ", address, ": ", why, "; expected HOST:PORT, e.g. 127.0.0.1:9464 or [::1]:9464"));
  };
  const size_t colon = address.rfind(':');
  if (colon == std::string::npos) return invalid("no colon between host and port");
  HostPort parsed;
  parsed.host = address.substr(0, colon);
  if (parsed.host.size() >= 2 && parsed.host.front() == '[' && parsed.host.back() == ']') {
    parsed.host = parsed.host.substr(1, parsed.host.size() - 2);
  } else if (parsed.host.find(':') != std::string::npos) {
    return invalid("an IPv6 host goes in brackets");
  }
  if (parsed.host.empty()) return invalid("no host");
  const std::string port = address.substr(colon + 1);
  const auto [end, error] = std::from_chars(port.data(), port.data() + port.size(), parsed.port);
  if (port.empty() || error != std::errc() || end != port.data() + port.size() || parsed.port < 0 ||
      parsed.port > 65535) {
    return invalid("the port is not a number from 0 to 65535");
  }
  return parsed;
}

struct MetricsHttpServer::State {
  httplib::Server http;
  std::thread thread;
  std::atomic<bool> thread_ended{false};
  std::once_flag stop_once;
  std::once_flag wait_once;
};

MetricsHttpServer::MetricsHttpServer(std::unique_ptr<State> state) : state_(std::move(state)) {}

MetricsHttpServer::~MetricsHttpServer() {
  Stop();
  Wait();
}

absl::StatusOr<std::unique_ptr<MetricsHttpServer>> MetricsHttpServer::Start(const std::string& address,
                                                                            std::function<std::string()> render) {
  constexpr char kOption[] = "--metrics-listen";
  auto parsed = ParseHostPort(address, kOption);
  if (!parsed.ok()) return parsed.status();
  auto state = std::make_unique<State>();
  httplib::Server& http = state->http;
  http.new_task_queue = [] { return new httplib::ThreadPool(kWorkers); };
  // SO_REUSEADDR only (a restart binds again at once). cpp-httplib's default also sets
  // SO_REUSEPORT, with which a second process, or gRPC's own listener (which sets it too), could
  // share the port and take some of its connections instead of failing to bind.
  http.set_socket_options([](socket_t socket) {
    const int yes = 1;
    setsockopt(socket, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
  });
  http.set_read_timeout(kReadTimeoutSeconds, 0);
  http.set_write_timeout(kWriteTimeoutSeconds, 0);
  http.set_keep_alive_timeout(kKeepAliveSeconds);
  http.set_payload_max_length(64 << 10);
  http.Get("/metrics", [render = std::move(render)](const httplib::Request&, httplib::Response& response) {
    response.set_content(render(), kPrometheusTextContentType);
  });
  http.set_error_handler([](const httplib::Request&, httplib::Response& response) {
    if (response.status == 404) {
      response.set_content("not found: this server answers GET /metrics only\n", "text/plain; charset=utf-8");
    }
  });
  http.set_exception_handler([](const httplib::Request&, httplib::Response& response, std::exception_ptr error) {
    std::string what = "unknown exception";
    try {
      if (error) std::rethrow_exception(error);
    } catch (const std::exception& caught) {
      what = caught.what();
    } catch (...) {
    }
    spdlog::error("metrics endpoint: rendering the metrics failed: {}", what);
    response.status = 500;
    response.set_content("internal error\n", "text/plain; charset=utf-8");
  });

  errno = 0;
  const int port = parsed->port == 0 ? http.bind_to_any_port(parsed->host)
                                     : (http.bind_to_port(parsed->host, parsed->port) ? parsed->port : -1);
  if (port <= 0) {
    const int error = errno;  // bind's, or getaddrinfo's (then often 0)
    return absl::UnavailableError(StrCat(
        "cannot listen for metrics on ", address, " (", kOption,
        "): ", error != 0 ? std::strerror(error) : "is the port taken, or the host not an address of this machine?"));
  }
  State* raw = state.get();
  state->thread = std::thread([raw] {
    raw->http.listen_after_bind();
    raw->thread_ended = true;
  });
  // stop() only acts on a server that runs: wait until it does, so that a Stop() right after Start
  // is never lost.
  const auto deadline = std::chrono::steady_clock::now() + kStartTimeout;
  while (!state->http.is_running() && !state->thread_ended && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  auto server = std::unique_ptr<MetricsHttpServer>(new MetricsHttpServer(std::move(state)));
  server->port_ = port;
  if (!server->state_->http.is_running()) {
    return absl::UnavailableError(StrCat("the metrics endpoint on ", address, " did not start"));
  }
  return server;
}

void MetricsHttpServer::Stop() {
  std::call_once(state_->stop_once, [this] { state_->http.stop(); });
}

void MetricsHttpServer::Wait() {
  std::call_once(state_->wait_once, [this] {
    if (state_->thread.joinable()) state_->thread.join();
  });
}

}  // namespace mocap
