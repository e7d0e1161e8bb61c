// mocap_session_memory: the server's memory over one long session and over many short ones
// (issue #14, "bounded memory"). Streams a clip's wrists, looped with time running on, as fast as
// the server takes them, and reads the server's resident set from /proc/PID/status.
//
//   mocap_session_memory --address HOST:PORT --database D --bvh CLIP --server-pid PID
//                        [--samples 200000] [--every 20000] [--sessions 50] [--lag 5]
// Prints one line per `every` frames of the long session (frames, RSS MB, change since its first
// line), then the RSS before and after `sessions` sessions in a row of 2,000 samples each.
// Benchmarks/session_memory.sh runs it against a server of its own.
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>
#include <thread>

#include <CLI/CLI.hpp>

#include "client/wrist_input/wrist_source.h"
#include "mocap/client.h"

namespace {

// VmRSS of `pid`, MB; −1 when unreadable.
double ResidentMegabytes(int pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return -1;
}

// One session of `count` samples from `clip` (looped, 30 Hz clock); `on_frames(total)` after each
// reply that carried frames. False on any error (printed).
bool RunSession(mocap::client::Client& client, const mocap::v1::SessionConfig& config,
                const std::vector<mocap::v1::WristSample>& clip, long count,
                const std::function<void(long)>& on_frames) {
  auto opened = client.OpenReconstruction(config);
  if (!opened.ok()) {
    std::cerr << "open: " << opened.status() << "\n";
    return false;
  }
  mocap::client::ReconstructionStream& stream = **opened;
  std::thread writer([&] {
    constexpr int kPerMessage = 100;
    std::vector<mocap::v1::WristSample> message;
    for (long i = 0; i < count; ++i) {
      message.push_back(clip[i % clip.size()]);
      message.back().set_time(static_cast<double>(i) / 30.0);
      if (static_cast<int>(message.size()) == kPerMessage || i + 1 == count) {
        if (!stream.Write(message).ok()) return;
        message.clear();
      }
    }
    (void)stream.CloseInput();
  });
  long frames = 0;
  while (true) {
    auto reply = stream.Read();
    if (!reply.ok() || !*reply) break;
    if ((*reply)->has_frames() && (*reply)->frames().frames_size() > 0) {
      frames += (*reply)->frames().frames_size();
      on_frames(frames);
    }
  }
  auto summary = stream.Finish();
  writer.join();
  if (!summary.ok()) {
    std::cerr << "session: " << summary.status() << "\n";
    return false;
  }
  if (frames != count) {
    std::cerr << "session: " << frames << " frames for " << count << " samples\n";
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Server memory over one long reconstruction session and many short ones"};
  std::string address, key, database, bvh;
  int pid = 0, sessions = 50, lag = 5;
  long samples = 200'000, every = 20'000;
  app.add_option("--address", address, "Server address")->required();
  app.add_option("--key", key, "API key (default: $MOCAP_API_KEY)");
  app.add_option("--database", database, "Database to reconstruct from")->required();
  app.add_option("--bvh", bvh, "Clip whose wrists are streamed (looped)")->required()->check(CLI::ExistingFile);
  app.add_option("--server-pid", pid, "The server's process id (its RSS is read from /proc)")->required();
  app.add_option("--samples", samples, "Samples in the long session")->check(CLI::PositiveNumber);
  app.add_option("--every", every, "Report the RSS every this many frames")->check(CLI::PositiveNumber);
  app.add_option("--sessions", sessions, "Short sessions in a row afterwards")->check(CLI::NonNegativeNumber);
  app.add_option("--lag", lag, "Fixed lag D, frames")->check(CLI::Range(0, 600));
  CLI11_PARSE(app, argc, argv);
  if (key.empty() && std::getenv("MOCAP_API_KEY") != nullptr) key = std::getenv("MOCAP_API_KEY");

  auto clip = mocap::WristsFromBvh(bvh, 0.5, 1);
  if (!clip.ok() || clip->empty()) {
    std::cerr << bvh << ": " << clip.status() << "\n";
    return 2;
  }
  auto client = mocap::client::Client::Connect(address, {.api_key = key});
  if (!client.ok()) {
    std::cerr << client.status() << "\n";
    return 2;
  }
  mocap::v1::SessionConfig config;
  config.set_database(database);
  config.mutable_fixed_lag()->set_lag_frames(lag);

  // Warm-up: the database's indices are built and the allocator has seen a session.
  if (!RunSession(**client, config, *clip, 2'000, [](long) {})) return 1;
  const double start = ResidentMegabytes(pid);
  std::cout << "long session: " << samples << " samples, fixed lag " << lag << "; server RSS " << start
            << " MB before\n";
  long next_report = every;
  double first = -1;
  const bool long_ok = RunSession(**client, config, *clip, samples, [&](long frames) {
    if (frames < next_report) return;
    next_report += every;
    const double rss = ResidentMegabytes(pid);
    if (first < 0) first = rss;
    std::printf("  %7ld frames: RSS %7.1f MB (%+6.1f MB since the first report)\n", frames, rss, rss - first);
    std::fflush(stdout);
  });
  if (!long_ok) return 1;

  const double before = ResidentMegabytes(pid);
  std::printf("%d sessions of 2,000 samples in a row: server RSS %.1f MB before\n", sessions, before);
  for (int i = 1; i <= sessions; ++i) {
    if (!RunSession(**client, config, *clip, 2'000, [](long) {})) return 1;
    if (i % 10 == 0 || i == sessions) {
      const double rss = ResidentMegabytes(pid);
      std::printf("  after %2d: RSS %7.1f MB (%+6.1f MB)\n", i, rss, rss - before);
    }
  }
  return 0;
}
