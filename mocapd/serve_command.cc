// `mocapd serve`: the gRPC server until SIGTERM or SIGINT, which drain the calls, then exit.
#include <pthread.h>
#include <signal.h>

#include <chrono>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <thread>

#include <spdlog/spdlog.h>

#include "mocapd/commands.h"
#include "server/bounded_shutdown.h"
#include "server/grpc_server.h"

namespace mocap {
namespace {

// "host:port" with the port replaced (the chosen one when listening on port 0).
std::string WithPort(const std::string& listen, int port) {
  const size_t colon = listen.rfind(':');
  return (colon == std::string::npos ? listen : listen.substr(0, colon)) + ":" + std::to_string(port);
}

int Serve(const ServeOptions& options) {
  // Signals are taken by one thread with sigwait; every other thread (gRPC's and ours, created
  // after this) has them blocked.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  // A server's log lines carry their time.
  spdlog::set_pattern("%Y-%m-%dT%H:%M:%S.%e %l %v");
  auto server = MocapServer::Start(options);
  if (!server.ok()) return ReportError(server.status());
  // The one line on stdout: scripts and tests read the port from it.
  std::cout << "listening on " << WithPort(options.listen, (*server)->port()) << std::endl;
  spdlog::info("serving store {} on {} ({})", options.store.string(), WithPort(options.listen, (*server)->port()),
               options.tls_cert.empty() ? "plaintext" : "TLS");
  if (!options.metrics_listen.empty()) {
    spdlog::info("serving metrics on http://{}/metrics (Prometheus text; every tenant's counters, no key)",
                 WithPort(options.metrics_listen, (*server)->metrics_port()));
  }

  std::thread waiter([&signals, &server, &options] {
    int signal = 0;
    sigwait(&signals, &signal);
    spdlog::info("received {}", signal == SIGTERM ? "SIGTERM" : "SIGINT");
    // The calls get the drain time and 5 s more to end; a call whose work would not stop, or a
    // second signal, must not keep the process up: committed data is safe in the store whatever
    // is cut short (each import batch is one transaction).
    const auto limit = options.drain_timeout + std::chrono::seconds(5);
    if (!WaitForShutdown([&server] { (*server)->Shutdown(); }, limit, signals)) {
      spdlog::error(
          "shutdown did not end within the drain time + 5 s ({} ms), or a second signal came: exiting with "
          "calls still running (everything committed is in the store)",
          limit.count());
      spdlog::default_logger()->flush();
      std::_Exit(3);
    }
  });
  (*server)->Wait();
  waiter.join();
  server->reset();
  spdlog::info("stopped");
  return 0;
}

}  // namespace

void RegisterServeCommand(CLI::App& app, CommandRegistry& registry) {
  auto options = std::make_shared<ServeOptions>();
  auto drain_seconds = std::make_shared<double>(10.0);
  auto idle_seconds = std::make_shared<double>(30.0);
  CLI::App* command = app.add_subcommand(
      "serve", "Run the gRPC server (MotionStore, Reconstruction, ServerStatus, health, reflection)");
  command->add_option("--store", options->store, "Motion store file (created on first start)")->capture_default_str();
  command->add_flag("--read-only", options->read_only,
                    "Serve an existing store without writing to it (a file rolled out to replicas, a read-only "
                    "mount): imports and deletions answer FAILED_PRECONDITION");
  command->add_option("--listen", options->listen, "Address to listen on; port 0 picks a free port (printed)")
      ->capture_default_str();
  command
      ->add_option("--metrics-listen", options->metrics_listen,
                   "Also serve GET /metrics (Prometheus text: the server's and every tenant's counters, no key) over "
                   "HTTP on this address: keep it on loopback or an admin network; port 0 picks a free port (logged). "
                   "Off by default")
      ->type_name("HOST:PORT");
  auto* cert =
      command->add_option("--tls-cert", options->tls_cert, "TLS certificate chain (PEM)")->check(CLI::ExistingFile);
  auto* key = command->add_option("--tls-key", options->tls_key, "TLS private key (PEM)")->check(CLI::ExistingFile);
  cert->needs(key);
  key->needs(cert);
  command->add_option("--workers", options->workers, "Worker threads for store and parsing work (0: 2 per core, min 4)")
      ->check(CLI::NonNegativeNumber);
  command->add_option("--max-message-bytes", options->limits.max_message_bytes, "Largest message either way")
      ->capture_default_str()
      ->check(CLI::Range(64 << 10, 1 << 30));
  command->add_option("--max-calls-per-tenant", options->limits.max_calls_per_tenant, "Calls in progress per tenant")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command->add_option("--max-file-bytes", options->limits.max_file_bytes, "Largest imported BVH file")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command
      ->add_option("--max-batch-frames", options->limits.max_batch_frames,
                   "Frames an import may hold before its batch commits")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  ReconstructionLimits& reconstruction = options->reconstruction;
  command
      ->add_option("--max-sessions-per-tenant", reconstruction.max_sessions_per_tenant,
                   "Reconstruction streams in progress per tenant")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command
      ->add_option("--idle-seconds", *idle_seconds,
                   "A reconstruction stream silent this long is ended (DEADLINE_EXCEEDED)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command
      ->add_option("--max-session-seconds", reconstruction.session.max_session_seconds,
                   "Longest span of sample timestamps in one session")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command->add_option("--compute-threads", reconstruction.compute_threads, "Reconstruction threads (0: one per core)")
      ->check(CLI::NonNegativeNumber);
  command
      ->add_option("--max-streams", reconstruction.max_streams,
                   "Live reconstruction streams on this server, all tenants; more are refused (RESOURCE_EXHAUSTED) "
                   "(0: 15 per compute thread, what real-time 30 Hz streams keep under 50 ms at p99)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command
      ->add_option("--cached-databases", reconstruction.max_cached_databases,
                   "Reconstruction indices kept in memory (least recently used dropped)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command->add_flag("!--no-prompt-lane", reconstruction.prompt_lane,
                    "No extra compute thread at the transport's priority for a quiet tenant's next task (beside "
                    "another tenant's flood its samples then wait at the pool's lower priority)");
  command
      ->add_option("--tenant-message-rate", reconstruction.message_pacing.messages_per_second,
                   "Where several tenants have keys, each tenant's stream messages are read at most this many a second "
                   "(a tenth of a second's worth at once); beyond it its clients are slowed by flow control (0: no "
                   "limit)")
      ->capture_default_str()
      ->check(CLI::Validator(
          [](const std::string& text) -> std::string {
            double rate = -1;
            if (CLI::detail::lexical_cast(text, rate) && (rate == 0 || rate >= kMinTenantMessageRate)) return "";
            return "0 (no limit) or at least 1000 messages a second";
          },
          "0 or >= 1000"));
  command->add_flag("!--no-reversed-motion", reconstruction.time_reversed_copies,
                    "Do not also search the travelling frames played backwards (saves ~185 bytes per database "
                    "frame of bandai-namco-2; bodies walking backwards then only find forward motion)");
  command
      ->add_option("--drain-seconds", *drain_seconds,
                   "On SIGTERM/SIGINT, how long running calls may finish; the process exits at the latest 5 s later (a "
                   "second signal: at once)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  registry.Add(command, [options, drain_seconds, idle_seconds] {
    options->drain_timeout = std::chrono::milliseconds(static_cast<long>(*drain_seconds * 1000));
    options->reconstruction.idle_timeout = std::chrono::milliseconds(static_cast<long>(*idle_seconds * 1000));
    return Serve(*options);
  });
}

}  // namespace mocap
