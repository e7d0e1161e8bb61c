#include "server/grpc_server.h"

#include <fstream>
#include <sstream>
#include <thread>

#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/health_check_service_interface.h>
#include <spdlog/spdlog.h>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "server/metrics_http.h"
#include "server/motion_store_service.h"
#include "server/pose_search_service.h"
#include "server/server_status_service.h"

namespace mocap {
namespace {

absl::StatusOr<std::string> ReadPem(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) return absl::NotFoundError(StrCat("cannot read ", path.string()));
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> Credentials(const ServeOptions& options) {
  if (options.tls_cert.empty() != options.tls_key.empty()) {
    return absl::InvalidArgumentError("give both --tls-cert and --tls-key, or neither");
  }
  if (options.tls_cert.empty()) return grpc::InsecureServerCredentials();
  grpc::SslServerCredentialsOptions ssl;
  MOCAP_ASSIGN_OR_RETURN(std::string cert, ReadPem(options.tls_cert));
  MOCAP_ASSIGN_OR_RETURN(std::string key, ReadPem(options.tls_key));
  ssl.pem_key_cert_pairs.push_back({key, cert});
  return grpc::SslServerCredentials(ssl);
}

}  // namespace

// Declared in the order they must be destroyed in reverse: the server goes first (its calls
// finish), then the workers (queued tasks run), then the connections.
struct MocapServer::State {
  std::unique_ptr<StorePool> stores;
  std::unique_ptr<WorkPool> workers;
  std::unique_ptr<TenantAdmission> admission;
  ServerMetrics metrics;
  std::unique_ptr<ServiceContext> context;
  std::unique_ptr<MotionStoreService> motion_store;
  std::unique_ptr<ServerStatusService> server_status;
  std::unique_ptr<ReconstructionService> reconstruction;
  std::unique_ptr<PoseSearchService> pose_search;  // uses reconstruction's compute pool
  std::unique_ptr<grpc::Server> server;
  std::unique_ptr<MetricsHttpServer> metrics_http;  // reads `metrics`; stopped first
  std::chrono::milliseconds drain_timeout{0};
  std::once_flag shutdown_once;
};

MocapServer::MocapServer(std::unique_ptr<State> state) : state_(std::move(state)) {}

MocapServer::~MocapServer() {
  Shutdown();
  state_->server.reset();
  state_->workers.reset();
}

absl::StatusOr<std::unique_ptr<MocapServer>> MocapServer::Start(const ServeOptions& options) {
  auto state = std::make_unique<State>();
  MOCAP_ASSIGN_OR_RETURN(std::shared_ptr<grpc::ServerCredentials> credentials, Credentials(options));
  MOCAP_ASSIGN_OR_RETURN(state->stores, StorePool::Open(options.store, options.read_only));
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  state->workers = std::make_unique<WorkPool>(options.workers > 0 ? options.workers : std::max(4, 2 * cores),
                                              WorkPool::Priority::kBulk);
  state->admission = std::make_unique<TenantAdmission>(options.limits.max_calls_per_tenant);
  state->context.reset(new ServiceContext{.stores = *state->stores,
                                          .workers = *state->workers,
                                          .admission = *state->admission,
                                          .metrics = state->metrics,
                                          .limits = options.limits});
  state->motion_store = std::make_unique<MotionStoreService>(*state->context);
  state->server_status = std::make_unique<ServerStatusService>(*state->context);
  state->reconstruction = std::make_unique<ReconstructionService>(*state->context, options.reconstruction);
  state->pose_search = std::make_unique<PoseSearchService>(*state->context, state->reconstruction->compute(),
                                                           options.reconstruction.max_cached_databases);
  state->drain_timeout = options.drain_timeout;
  if (!options.metrics_listen.empty()) {
    const ServerMetrics& metrics = state->metrics;
    MOCAP_ASSIGN_OR_RETURN(state->metrics_http, MetricsHttpServer::Start(options.metrics_listen, [&metrics] {
                             return metrics.PrometheusTextWithTenants();
                           }));
  }

  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  int port = 0;
  builder.AddListeningPort(options.listen, credentials, &port);
  builder.SetMaxReceiveMessageSize(options.limits.max_message_bytes);
  builder.SetMaxSendMessageSize(options.limits.max_message_bytes);
  builder.RegisterService(state->motion_store.get());
  builder.RegisterService(state->server_status.get());
  builder.RegisterService(state->reconstruction.get());
  builder.RegisterService(state->pose_search.get());
  state->server = builder.BuildAndStart();
  if (!state->server || port == 0) {
    return absl::UnavailableError(StrCat("cannot listen on ", options.listen));
  }
  const int metrics_port = state->metrics_http ? state->metrics_http->port() : 0;
  auto server = std::unique_ptr<MocapServer>(new MocapServer(std::move(state)));
  server->port_ = port;
  server->metrics_port_ = metrics_port;
  return server;
}

void MocapServer::Shutdown() {
  std::call_once(state_->shutdown_once, [this] {
    spdlog::info("shutting down: draining calls for up to {} ms", state_->drain_timeout.count());
    // The metrics endpoint takes no new scrapes from here on; the ones in progress end while the
    // calls drain (within the socket timeouts, about 2 s).
    if (state_->metrics_http) state_->metrics_http->Stop();
    state_->reconstruction->Drain();
    state_->server->Shutdown(std::chrono::system_clock::now() + state_->drain_timeout);
    if (state_->metrics_http) state_->metrics_http->Wait();
    spdlog::info("all calls finished");
  });
}

void MocapServer::Wait() { state_->server->Wait(); }

}  // namespace mocap
