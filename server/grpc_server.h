// MocapServer: the gRPC server of `mocapd serve` — MotionStore, Reconstruction, PoseSearch and ServerStatus services,
// health checking, reflection, TLS, limits — over one store file, and the operator's HTTP metrics endpoint.
#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "server/reconstruction_service.h"
#include "server/service_context.h"

namespace mocap {

struct ServeOptions {
  std::filesystem::path store = "var/mocap.db";  // created on first start
  bool read_only = false;                        // serve an existing store without writing
  std::string listen = "127.0.0.1:50051";        // host:port; port 0 picks a free one
  std::filesystem::path tls_cert;                // PEM; with tls_key, serve TLS only
  std::filesystem::path tls_key;
  int workers = 0;  // store/parse threads; 0: 2 per core (min 4)
  ServerLimits limits;
  ReconstructionLimits reconstruction;
  std::chrono::milliseconds drain_timeout{10000};  // on shutdown, calls get this long to finish
  // host:port of the operator's HTTP endpoint GET /metrics (every tenant's counters, no key:
  // loopback or an admin network); port 0 picks a free one; empty: none (the default).
  std::string metrics_listen;
};

class MocapServer {
 public:
  // Opens the store (creating it) and starts listening.
  static absl::StatusOr<std::unique_ptr<MocapServer>> Start(const ServeOptions& options);
  ~MocapServer();

  int port() const { return port_; }
  // The metrics endpoint's port; 0 when ServeOptions::metrics_listen is empty.
  int metrics_port() const { return metrics_port_; }
  // Stops accepting calls, lets running ones finish until the drain timeout, cancels the rest.
  // Thread-safe; returns when every call has finished.
  void Shutdown();
  // Blocks until Shutdown has finished.
  void Wait();

 private:
  struct State;
  explicit MocapServer(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
  int port_ = 0;
  int metrics_port_ = 0;
};

}  // namespace mocap
