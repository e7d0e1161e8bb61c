// METHOD.md A4: cost of one DAG step (K1 x K1 edges) on real ankle clouds. Database = the
// standard split's database clips (bandai-namco-2 takes not ≡ 3 mod 10); query = a held-out walk's
// wrists by FK with σ = 0.5 cm noise; K1 = 1000 (and 200). Reported: time per frame (step).
#include <random>

#include <benchmark/benchmark.h>

#include "motion/bvh/bvh_reader.h"
#include "eval/standard_split.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/reconstruct/ankle_path.h"
#include "motion/skeleton/forward_kinematics.h"

namespace mocap {
namespace {

struct Clouds {
  std::vector<std::vector<AnkleCandidate>> by_k[2];  // K1 = 1000, 200
  double frame_time = 1.0 / 30.0;
  bool ok = false;
};

const Clouds& GetClouds() {
  static Clouds clouds = [] {
    Clouds c;
    auto standard = eval::LoadStandardSplit();
    if (!standard.ok()) return c;
    const RigModel* rig = &standard->rig;
    std::vector<std::vector<FrameFeatures>> per_file(standard->database_files.size());
    if (!eval::PrepareAll(standard->database_files, *rig,
                                [&](size_t i, PreparedClip&& clip) { per_file[i] = std::move(clip.features); }).ok()) {
      return c;
    }
    std::vector<FrameFeatures> database;
    for (auto& features : per_file) database.insert(database.end(), features.begin(), features.end());
    WristFeatureIndex index;
    if (!index.Build(database).ok()) return c;
    auto query = ReadBvhFile(standard->folder / "dataset-2_walk_normal_003.bvh");
    if (!query.ok()) return c;
    auto prepared = PrepareClip(*query, *rig, {});
    const GlobalPoses poses = ForwardKinematics(prepared->skeleton, prepared->motion);
    const BodyLandmarks& l = rig->topology.landmarks;
    std::mt19937 random(7);
    std::normal_distribution<float> noise(0.0f, 0.005f);
    const int ks[2] = {1000, 200};
    for (int i = 0; i < 2; ++i) {
      WristSmoother smoother({}, c.frame_time);
      float heading = 0.0f;
      for (int f = 0; f < std::min(60, poses.num_frames()); ++f) {
        const Eigen::Vector3f n1(noise(random), noise(random), noise(random)), n2(noise(random), noise(random), noise(random));
        const SmoothedWrists wrists = smoother.Push(poses.position(f, l.left_wrist) + n1, poses.position(f, l.right_wrist) + n2);
        std::vector<AnkleCandidate> cloud;
        if (!FindAnkleCloud(index, database, {}, wrists, ks[i], &heading, &cloud).ok()) return c;
        c.by_k[i].push_back(std::move(cloud));
      }
    }
    c.ok = true;
    return c;
  }();
  return clouds;
}

void BM_AnkleDagStep(benchmark::State& state) {
  const Clouds& clouds = GetClouds();
  if (!clouds.ok) return state.SkipWithError("shared data unavailable");
  const auto& frames = clouds.by_k[state.range(0) == 1000 ? 0 : 1];
  for (auto _ : state) {
    auto solved = SolveAnkleWindow(frames, std::nullopt, clouds.frame_time, {});
    benchmark::DoNotOptimize(solved);
  }
  // One iteration solves frames.size() - 1 steps; the counter is seconds per step.
  state.counters["s_per_step"] = benchmark::Counter(static_cast<double>(frames.size() - 1),
                                                    benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_AnkleDagStep)->Arg(1000)->Arg(200)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mocap

BENCHMARK_MAIN();
