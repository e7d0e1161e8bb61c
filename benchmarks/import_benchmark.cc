// Per-stage cost of importing real BVH: parse, local motion, forward kinematics, features (the
// whole PrepareClip), in frames per second, on a sample of bandai-namco-2 (single thread). The end
// to end figure (parallel pipeline + SQLite) comes from `mocapd import`; see docs/evaluation.md.
#include <fstream>
#include <sstream>

#include <benchmark/benchmark.h>

#include "eval/datasets/shared_data.h"
#include "motion/bvh/bvh_reader.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/skeleton/forward_kinematics.h"

namespace mocap {
namespace {

struct Sample {
  std::vector<std::string> texts;
  std::vector<BvhClip> clips;
  RigModel rig;
  long frames = 0;
  bool ok = false;
};

const Sample& GetSample() {
  static Sample sample = [] {
    Sample s;
    std::string why;
    auto folder = datasets::UnpackedSet(datasets::DataLocationFromEnvironment(), "bandai-namco-2", &why);
    if (!folder) return s;
    auto files = datasets::BvhFilesIn(*folder);
    for (size_t i = 0; i < files.size(); i += 26) {  // ~100 files across all contents
      std::ifstream in(files[i]);
      std::stringstream buffer;
      buffer << in.rdbuf();
      s.texts.push_back(buffer.str());
      auto clip = ParseBvh(s.texts.back(), files[i].string());
      if (!clip.ok()) return s;
      s.frames += clip->num_frames();
      s.clips.push_back(std::move(*clip));
    }
    auto rig = BuildRigModel(s.clips.front(), {});
    if (!rig.ok()) return s;
    s.rig = std::move(*rig);
    s.ok = true;
    return s;
  }();
  return sample;
}

void Report(benchmark::State& state, long frames) {
  state.counters["frames/s"] =
      benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_ParseBvh(benchmark::State& state) {
  const Sample& s = GetSample();
  if (!s.ok) return state.SkipWithError("shared data unavailable");
  for (auto _ : state) {
    for (size_t i = 0; i < s.texts.size(); ++i) benchmark::DoNotOptimize(ParseBvh(s.texts[i], "bench"));
  }
  Report(state, s.frames);
}
BENCHMARK(BM_ParseBvh)->Unit(benchmark::kMillisecond);

void BM_MotionFromChannels(benchmark::State& state) {
  const Sample& s = GetSample();
  if (!s.ok) return state.SkipWithError("shared data unavailable");
  for (auto _ : state) {
    for (const BvhClip& clip : s.clips)
      benchmark::DoNotOptimize(MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time));
  }
  Report(state, s.frames);
}
BENCHMARK(BM_MotionFromChannels)->Unit(benchmark::kMillisecond);

void BM_ForwardKinematics(benchmark::State& state) {
  const Sample& s = GetSample();
  if (!s.ok) return state.SkipWithError("shared data unavailable");
  std::vector<LocalMotion> motions;
  for (const BvhClip& clip : s.clips)
    motions.push_back(MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time));
  for (auto _ : state) {
    for (size_t i = 0; i < motions.size(); ++i)
      benchmark::DoNotOptimize(ForwardKinematics(s.clips[i].skeleton, motions[i]));
  }
  Report(state, s.frames);
}
BENCHMARK(BM_ForwardKinematics)->Unit(benchmark::kMillisecond);

void BM_PrepareClip(benchmark::State& state) {
  const Sample& s = GetSample();
  if (!s.ok) return state.SkipWithError("shared data unavailable");
  for (auto _ : state) {
    for (const BvhClip& clip : s.clips) benchmark::DoNotOptimize(PrepareClip(clip, s.rig, {}));
  }
  Report(state, s.frames);
}
BENCHMARK(BM_PrepareClip)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mocap

BENCHMARK_MAIN();
