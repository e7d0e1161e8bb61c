// The whole reconstruction pipeline (docs/method.md A2–A7) on the standard split, single thread,
// default options: frames per second and time per stage per frame, whole clip and streamed at a
// fixed lag; plus the resident memory of the loaded database and indices per database frame; and
// one engine serving 1 or 30 interleaved streams (BM_InterleavedSessions); and the longest call of
// a whole-trajectory session, sliced as the server runs it or not (BM_WholeTrajectoryLongestCall).
//   build/benchmarks/mocap_reconstruction_benchmark --benchmark_counters_tabular=true
#include <unistd.h>
#include <chrono>
#include <cmath>
#include <fstream>
#include <memory>
#include <vector>

#include <benchmark/benchmark.h>

#include "eval/evaluation.h"
#include "eval/standard_split.h"
#include "motion/preprocess/clip_labels.h"

namespace mocap {
namespace {

double ResidentBytes() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE));
}

struct Fixture {
  std::shared_ptr<const ReconstructionDatabase> database;
  std::vector<eval::TestClip> tests;
  double bytes_per_frame = 0;
  ReconstructionDatabase::MemoryUse memory;
  double captured_only_bytes = 0;
  bool ok = false;
};

const Fixture& Shared() {
  static const Fixture fixture = [] {
    Fixture f;
    auto split = eval::LoadStandardSplit();
    if (!split.ok()) return f;
    const double before = ResidentBytes();
    auto database = eval::LoadDatabase(split->database_files);
    if (!database.ok()) return f;
    f.database = *database;
    f.bytes_per_frame = (ResidentBytes() - before) / f.database->num_frames();
    f.memory = f.database->memory_use();
    // The same files without the travelling frames played backwards (mocapd --no-reversed-motion).
    auto both = eval::LoadDatabases(split->database_files);
    if (!both.ok()) return f;
    f.captured_only_bytes = static_cast<double>(both->captured->memory_use().total()) / both->captured->num_frames();
    // One held-out walk and one wave, 150 frames each.
    std::vector<std::filesystem::path> files;
    for (const char* content : {"walk", "wave-both-hands"}) {
      for (const auto& file : split->test_files) {
        if (LabelValue(ParseClipLabels(file.filename().string()), "content") == content) {
          files.push_back(file);
          break;
        }
      }
    }
    auto tests = eval::LoadTestClips(files, f.database->rig(), 150, "");
    if (!tests.ok()) return f;
    f.tests = std::move(*tests);
    f.ok = true;
    return f;
  }();
  return fixture;
}

// The shared fixture, or null with the benchmark skipped where the shared data is absent.
const Fixture* SharedOrSkip(benchmark::State& state) {
  const Fixture& f = Shared();
  if (f.ok) return &f;
  state.SkipWithError("shared data unavailable");
  return nullptr;
}

void BM_ReconstructionPipeline(benchmark::State& state) {
  const Fixture* shared = SharedOrSkip(state);
  if (shared == nullptr) return;
  const Fixture& f = *shared;
  ReconstructionOptions options;
  options.method = static_cast<ReconstructionMethod>(state.range(0));
  if (state.range(1) >= 0) {  // streamed as the server does: frame t − lag out when frame t comes in
    options.mode = StreamMode::kFixedLag;
    options.lag = static_cast<int>(state.range(1));
  }
  const BodyLandmarks& l = f.database->rig().topology.landmarks;
  SessionStatistics total;
  long frames = 0;
  for (auto _ : state) {
    for (const eval::TestClip& test : f.tests) {
      auto session = ReconstructionSession::Create(f.database, options);
      std::vector<ReconstructedFrame> out;
      for (int t = 0; t < test.truth.num_frames(); ++t) {
        (void)(*session)->Push(
            {t * f.database->frame_time(), test.truth.position(t, l.left_wrist), test.truth.position(t, l.right_wrist)},
            &out);
      }
      (void)(*session)->Finish(&out);
      const SessionStatistics& s = (*session)->statistics();
      total.cloud_seconds += s.cloud_seconds;
      total.path_seconds += s.path_seconds;
      total.pose_seconds += s.pose_seconds;
      total.post_seconds += s.post_seconds;
      frames += static_cast<long>(out.size());
    }
  }
  state.counters["fps"] = benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
  state.counters["A2A3_ms"] = 1e3 * total.cloud_seconds / frames;
  state.counters["A4_ms"] = 1e3 * total.path_seconds / frames;
  state.counters["A5A6_ms"] = 1e3 * total.pose_seconds / frames;
  state.counters["A7_ms"] = 1e3 * total.post_seconds / frames;
  // Resident memory the load added (allocator slack included), and what the database holds.
  state.counters["db_rss_bytes_per_frame"] = f.bytes_per_frame;
  const double frames_in_db = f.database->num_frames();
  state.counters["db_bytes_per_frame"] = static_cast<double>(f.memory.total()) / frames_in_db;
  state.counters["db_bytes_no_reversed"] = f.captured_only_bytes;
  state.counters["features_B"] = static_cast<double>(f.memory.features) / frames_in_db;
  state.counters["poses_B"] = static_cast<double>(f.memory.pose_features) / frames_in_db;
  state.counters["rows_B"] = static_cast<double>(f.memory.row_maps) / frames_in_db;
  state.counters["A3_index_B"] = static_cast<double>(f.memory.wrist_index) / frames_in_db;
  state.counters["A5_index_B"] = static_cast<double>(f.memory.full_index) / frames_in_db;
}
// Method (0 = full, 1 = wrists-only pose model, 2 = nearest neighbour) and lag in frames (−1 =
// the whole clip at once; 0 and 5 as `mocap-load` and the SDK stream by default).
BENCHMARK(BM_ReconstructionPipeline)
    ->ArgNames({"method", "lag"})
    ->Args({0, -1})
    ->Args({0, 0})
    ->Args({0, 5})
    ->Args({1, -1})
    ->Args({2, -1})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

// Many streams on one engine, as a server's compute thread serves them: `sessions` sessions at
// lag 0, each fed the same held-out walk from its own offset, one frame each in turn (issue #26:
// is a frame dearer when thirty sessions' state shares the caches than when one session runs?).
void BM_InterleavedSessions(benchmark::State& state) {
  const Fixture* shared = SharedOrSkip(state);
  if (shared == nullptr) return;
  const Fixture& f = *shared;
  ReconstructionOptions options;
  options.mode = StreamMode::kFixedLag;
  options.lag = 0;
  const BodyLandmarks& l = f.database->rig().topology.landmarks;
  const eval::TestClip& walk = f.tests.front();
  const int count = static_cast<int>(state.range(0));
  const int length = walk.truth.num_frames();
  long frames = 0;
  for (auto _ : state) {
    std::vector<std::unique_ptr<ReconstructionSession>> sessions;
    for (int i = 0; i < count; ++i) sessions.push_back(*std::move(ReconstructionSession::Create(f.database, options)));
    std::vector<ReconstructedFrame> out;
    for (int t = 0; t < length; ++t) {
      for (int i = 0; i < count; ++i) {
        // Each stream at its own place in the walk, played forwards and back (no jump at its end).
        const int m = (t + i * 7) % (2 * length - 2);
        const int k = m < length ? m : 2 * length - 2 - m;
        out.clear();
        (void)sessions[i]->Push(
            {t * f.database->frame_time(), walk.truth.position(k, l.left_wrist), walk.truth.position(k, l.right_wrist)},
            &out);
        frames += static_cast<long>(out.size());
      }
    }
  }
  state.counters["fps"] = benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_InterleavedSessions)->ArgName("sessions")->Arg(1)->Arg(30)->Unit(benchmark::kMillisecond)->Iterations(1);

// Issue #24: the longest single call of a whole-trajectory session as the server runs it (windows
// of 600 frames), each call given the server's 20 ms slice (SetSliceDeadline; pending frames taken
// by Continue) or not: how long one compute task can hold a thread. 60 s of the held-out walk,
// played forwards and back, one sample per call.
void BM_WholeTrajectoryLongestCall(benchmark::State& state) {
  const Fixture* shared = SharedOrSkip(state);
  if (shared == nullptr) return;
  const Fixture& f = *shared;
  ReconstructionOptions options;
  options.max_window_frames = 600;  // SessionLimits' default
  const bool sliced = state.range(0) != 0;
  const BodyLandmarks& l = f.database->rig().topology.landmarks;
  const eval::TestClip& walk = f.tests.front();
  const int length = walk.truth.num_frames();
  const int samples = static_cast<int>(std::lround(60.0 / f.database->frame_time()));
  double longest = 0;
  long calls = 0, frames = 0;
  std::vector<ReconstructedFrame> out;
  // One call: timed, its deadline set first when sliced.
  auto call = [&](ReconstructionSession& session, auto&& work) {
    const auto start = std::chrono::steady_clock::now();
    if (sliced) session.SetSliceDeadline(start + std::chrono::milliseconds(20));
    (void)work();
    longest =
        std::max(longest, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    ++calls;
  };
  for (auto _ : state) {
    auto session = *ReconstructionSession::Create(f.database, options);
    out.clear();
    for (int t = 0; t < samples; ++t) {
      const int m = t % (2 * length - 2);
      const int k = m < length ? m : 2 * length - 2 - m;
      call(*session, [&] {
        return session->Push(
            {t * f.database->frame_time(), walk.truth.position(k, l.left_wrist), walk.truth.position(k, l.right_wrist)},
            &out);
      });
      while (session->has_pending_frames()) call(*session, [&] { return session->Continue(&out); });
    }
    do {
      call(*session, [&] { return session->Finish(&out); });
    } while (session->has_pending_frames());
    frames += static_cast<long>(out.size());
  }
  state.counters["longest_call_ms"] = longest;
  state.counters["calls"] = static_cast<double>(calls);
  state.counters["frames"] = static_cast<double>(frames);
}
BENCHMARK(BM_WholeTrajectoryLongestCall)
    ->ArgName("sliced")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace
}  // namespace mocap

BENCHMARK_MAIN();
