// mocap-load: N concurrent simulated trackers streaming wrists to a mocapd server in real time
// (30 Hz by default), reporting frame latency p50/p90/p99, throughput and errors. Built on the SDK.
//
//   mocap-load --address 127.0.0.1:50051 --key mk_... --database walks --bvh clip.bvh --streams 20
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <map>
#include <random>
#include <string>
#include <thread>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "client/load/latency_summary.h"
#include "client/load/stream_load.h"
#include "client/wrist_input/wrist_source.h"

namespace mocap::load {
namespace {

struct Options {
  std::string address = "127.0.0.1:50051";
  std::string key;
  bool tls = false;
  std::string database;
  std::string bvh, csv;
  double noise_cm = 0.5;
  unsigned seed = 1;
  int streams = 20;
  double seconds = 30;
  double rate = 30;
  int lag = 0;
  int window = -1;
  int k1 = 0, k2 = 0;
  double ramp_seconds = 1.0;
  bool json = false;
  double max_p99_ms = 0;
  int samples_per_message = 1;
  bool unpaced = false;
  double reopen_after = 0;  // seconds; 0: one session per stream
};

// The clip's samples, one per 1/rate seconds, repeated forwards until `seconds` are filled; each
// repeat is moved on the ground by the clip's own travel (first to last sample, mean of the
// wrists), so a walk goes on as a walk. (Playing it backwards instead would be walking
// backwards, which a database rarely holds and which costs the solver twice as much.)
std::vector<v1::WristSample> Schedule(const std::vector<v1::WristSample>& clip, double rate, double seconds) {
  std::vector<v1::WristSample> out;
  const long count = std::max(1L, static_cast<long>(seconds * rate));
  const size_t n = clip.size();
  const v1::WristSample& first = clip.front();
  const v1::WristSample& last = clip.back();
  const double travel_x = 0.5 * (last.left().x() + last.right().x() - first.left().x() - first.right().x());
  const double travel_z = 0.5 * (last.left().z() + last.right().z() - first.left().z() - first.right().z());
  for (long i = 0; i < count; ++i) {
    const long repeat = i / static_cast<long>(n);
    v1::WristSample sample = clip[static_cast<size_t>(i) % n];
    for (v1::Vec3* wrist : {sample.mutable_left(), sample.mutable_right()}) {
      wrist->set_x(static_cast<float>(wrist->x() + repeat * travel_x));
      wrist->set_z(static_cast<float>(wrist->z() + repeat * travel_z));
    }
    sample.set_time(static_cast<double>(i) / rate);
    out.push_back(std::move(sample));
  }
  return out;
}

v1::SessionConfig Config(const Options& o, int stream) {
  v1::SessionConfig config;
  config.set_database(o.database);
  if (o.window >= 0) {
    config.mutable_sub_interval()->set_window_frames(o.window);
  } else {
    config.mutable_fixed_lag()->set_lag_frames(o.lag);
  }
  if (o.k1 > 0) config.mutable_overrides()->set_ankle_candidates(o.k1);
  if (o.k2 > 0) config.mutable_overrides()->set_pose_neighbours(o.k2);
  config.set_client_label("mocap-load stream " + std::to_string(stream));
  return config;
}

nlohmann::json LatencyBySecondJson(const std::vector<LatencySummary>& by_second) {
  nlohmann::json seconds = nlohmann::json::array();
  for (size_t s = 0; s < by_second.size(); ++s) {
    const LatencySummary& l = by_second[s];
    seconds.push_back({{"second", s}, {"count", l.count}, {"p50", l.p50_ms}, {"p99", l.p99_ms}, {"max", l.max_ms}});
  }
  return seconds;
}

std::string LatencyBySecondText(const std::vector<LatencySummary>& by_second) {
  std::string text;
  for (const LatencySummary& l : by_second) {
    if (!text.empty()) text += " ";
    text += l.count > 0 ? std::to_string(static_cast<long>(std::lround(l.p99_ms))) : "-";
  }
  return text;
}

std::chrono::steady_clock::duration Seconds(double seconds) {
  return std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(seconds));
}

int Run(const Options& o) {
  absl::StatusOr<std::vector<v1::WristSample>> clip =
      !o.csv.empty() ? WristsFromCsv(o.csv) : WristsFromBvh(o.bvh, o.noise_cm, o.seed);
  if (!clip.ok()) {
    spdlog::error("{}", clip.status().ToString());
    return 2;
  }
  // At least one whole message, however short the session.
  const std::vector<v1::WristSample> samples =
      Schedule(*clip, o.rate, std::max(o.seconds, o.samples_per_message / o.rate));
  std::mt19937 random(o.seed);
  std::uniform_real_distribution<double> offset(0.0, o.ramp_seconds);
  const auto start = std::chrono::steady_clock::now() + std::chrono::milliseconds(200);

  std::vector<StreamOutcome> outcomes(o.streams);
  std::vector<std::thread> threads;
  const auto began = std::chrono::steady_clock::now();
  for (int s = 0; s < o.streams; ++s) {
    StreamPlan plan{Config(o, s),
                    samples,
                    start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                std::chrono::duration<double>(offset(random))),
                    o.samples_per_message,
                    !o.unpaced,
                    std::nullopt};
    if (o.reopen_after > 0) plan.cancel_after = Seconds(o.reopen_after);
    threads.emplace_back([&o, &outcomes, s, plan = std::move(plan)]() mutable {
      client::ConnectOptions connect;
      connect.api_key = o.key;
      connect.tls = o.tls;
      auto client = client::Client::Connect(o.address, connect);
      if (!client.ok()) {
        outcomes[s].status = client.status();
        return;
      }
      if (!plan.cancel_after) {
        outcomes[s] = RunStream(**client, plan);
        return;
      }
      // Cancel-and-reopen: sessions of --reopen-after seconds, one after another, for --seconds.
      const auto end = plan.start + Seconds(o.seconds);
      do {
        Accumulate(outcomes[s], RunStream(**client, plan));
        plan.start = std::chrono::steady_clock::now();
      } while (plan.start < end);
    });
  }
  for (std::thread& thread : threads) thread.join();
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();

  std::vector<double> latencies, latency_seconds;  // the latter: when each one's sample was sent
  std::map<std::string, int> errors;
  long frames = 0, sent = 0, rejected = 0, sessions = 0, cancelled = 0;
  double late = 0, server_mean = 0, server_max = 0;
  // The server's own time per frame by stage (each session's mean, averaged over sessions): what
  // the reply time holds besides the pipeline is the service path and waiting for a thread.
  double cloud_ms = 0, path_ms = 0, pose_ms = 0, cleanup_ms = 0;
  int ok = 0;
  for (const StreamOutcome& outcome : outcomes) {
    latencies.insert(latencies.end(), outcome.latencies_ms.begin(), outcome.latencies_ms.end());
    for (const auto sent : outcome.latency_sent)
      latency_seconds.push_back(std::chrono::duration<double>(sent - start).count());
    frames += outcome.frames;
    sent += outcome.samples_sent;
    rejected += outcome.rejected;
    sessions += outcome.sessions;
    cancelled += outcome.cancelled;
    late = std::max(late, outcome.late_send_ms);
    if (outcome.status.ok()) {
      ++ok;
      server_mean += outcome.summary.mean_reply_ms();
      server_max = std::max(server_max, outcome.summary.max_reply_ms());
      cloud_ms += outcome.summary.cloud_ms_per_frame();
      path_ms += outcome.summary.path_ms_per_frame();
      pose_ms += outcome.summary.pose_ms_per_frame();
      cleanup_ms += outcome.summary.cleanup_ms_per_frame();
    } else {
      ++errors[absl::StatusCodeToString(outcome.status.code()) + ": " + std::string(outcome.status.message())];
    }
  }
  if (ok > 0) {
    for (double* mean : {&server_mean, &cloud_ms, &path_ms, &pose_ms, &cleanup_ms}) *mean /= ok;
  }
  const double pipeline_ms = cloud_ms + path_ms + pose_ms + cleanup_ms;
  const std::vector<LatencySummary> by_second = SummariseBySecond(latencies, latency_seconds);
  const LatencySummary latency = Summarise(std::move(latencies));
  const bool p99_ok = o.max_p99_ms <= 0 || latency.p99_ms <= o.max_p99_ms;

  if (o.json) {
    nlohmann::json report = {{"streams", o.streams},
                             {"streams_ok", ok},
                             {"sessions", sessions},
                             {"sessions_cancelled", cancelled},
                             {"seconds", elapsed},
                             {"input_rate", o.rate},
                             {"samples_sent", sent},
                             {"samples_rejected", rejected},
                             {"frames", frames},
                             {"frames_per_second", frames / elapsed},
                             {"latency_ms",
                              {{"count", latency.count},
                               {"mean", latency.mean_ms},
                               {"p50", latency.p50_ms},
                               {"p90", latency.p90_ms},
                               {"p99", latency.p99_ms},
                               {"max", latency.max_ms}}},
                             {"latency_by_second_ms", LatencyBySecondJson(by_second)},
                             {"server_reply_ms", {{"mean", server_mean}, {"max", server_max}}},
                             {"server_stage_ms_per_frame",
                              {{"ankle_cloud", cloud_ms},
                               {"ankle_path", path_ms},
                               {"pose", pose_ms},
                               {"cleanup", cleanup_ms},
                               {"pipeline", pipeline_ms}}},
                             {"worst_late_send_ms", late},
                             {"errors", errors}};
    std::cout << report.dump(2) << "\n";
  } else {
    std::cout << "streams " << ok << "/" << o.streams << " ok, " << elapsed << " s, " << sent << " samples sent ("
              << rejected << " rejected), " << frames << " frames (" << frames / elapsed << " frames/s), " << sessions
              << " sessions (" << cancelled << " cancelled on purpose)\n"
              << "frame latency ms: mean " << latency.mean_ms << "  p50 " << latency.p50_ms << "  p90 "
              << latency.p90_ms << "  p99 " << latency.p99_ms << "  max " << latency.max_ms << "  (" << latency.count
              << " frames)\n"
              << "frame latency p99 ms by second of the run: " << LatencyBySecondText(by_second) << "\n"
              << "server reply ms: mean " << server_mean << "  max " << server_max << "; worst late send " << late
              << " ms\n"
              << "server ms per frame: pipeline " << pipeline_ms << " (A2+A3 ankle cloud " << cloud_ms
              << ", A4 ankle path " << path_ms << ", A5+A6 pose " << pose_ms << ", A7 cleanup " << cleanup_ms << ")\n";
    for (const auto& [error, count] : errors) std::cout << "error x" << count << ": " << error << "\n";
  }
  if (!p99_ok) spdlog::error("p99 latency {:.1f} ms exceeds --max-p99-ms {}", latency.p99_ms, o.max_p99_ms);
  return errors.empty() && p99_ok ? 0 : 1;
}

}  // namespace
}  // namespace mocap::load

int main(int argc, char** argv) {
  spdlog::set_default_logger(spdlog::stderr_color_mt("mocap-load"));
  spdlog::set_pattern("%^%l%$: %v");
  mocap::load::Options o;
  if (const char* key = std::getenv("MOCAP_API_KEY")) o.key = key;
  CLI::App app{"mocap-load — concurrent real-time reconstruction streams against a mocapd server"};
  app.add_option("--address", o.address, "Server (or load balancer) address")->capture_default_str();
  app.add_option("--key", o.key, "API key (default: $MOCAP_API_KEY)");
  app.add_flag("--tls", o.tls, "Connect with TLS (system roots)");
  app.add_option("--database", o.database, "Database to reconstruct from")->required();
  auto* source = app.add_option_group("wrists", "Where the wrists come from");
  source->add_option("--bvh", o.bvh, "A BVH clip: wrists by forward kinematics plus noise")->check(CLI::ExistingFile);
  source->add_option("--csv", o.csv, "A CSV of timestamped samples (mocap reconstruct's format)")
      ->check(CLI::ExistingFile);
  source->require_option(1);
  app.add_option("--noise-cm", o.noise_cm, "Gaussian noise on BVH wrists, cm")->capture_default_str();
  app.add_option("--seed", o.seed, "Noise seed")->capture_default_str();
  app.add_option("--streams", o.streams, "Concurrent sessions")->capture_default_str()->check(CLI::Range(1, 10000));
  app.add_option("--seconds", o.seconds, "Length of each session (the clip is played back and forth)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--rate", o.rate, "Samples per second per stream")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 1000.0));
  app.add_option("--lag", o.lag, "Fixed lag D, frames (0: causal)")->capture_default_str()->check(CLI::Range(0, 600));
  app.add_option("--window", o.window, "Sub-interval mode with windows of L frames instead of fixed lag");
  app.add_option("--k1", o.k1, "Override K1 (ankle candidates)");
  app.add_option("--k2", o.k2, "Override K2 (pose neighbours)");
  app.add_option("--ramp-seconds", o.ramp_seconds, "Streams start at random offsets within this span")
      ->capture_default_str();
  app.add_option("--max-p99-ms", o.max_p99_ms, "Exit 1 when the p99 frame latency exceeds this");
  app.add_option("--samples-per-message", o.samples_per_message, "Samples sent in each message")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  app.add_flag("--unpaced", o.unpaced, "Send every message as soon as the server takes it, not at the input rate");
  app.add_option("--reopen-after", o.reopen_after,
                 "Cancel each session after this many seconds and open a new one, "
                 "until --seconds have passed")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--json", o.json, "Report as JSON on stdout");
  CLI11_PARSE(app, argc, argv);
  return mocap::load::Run(o);
}
