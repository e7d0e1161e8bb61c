// docs/method.md A4: cost of one DAG step (K1 x K1 edges) on real ankle clouds. Database = the
// standard split's database clips (bandai-namco-2 takes not ≡ 3 mod 10); query = a held-out walk's
// wrists by FK with σ = 0.5 cm noise; K1 = 1000 (and 200), both slide rules. Reported: time per
// step, for AnkleDagStep and, in the same run, for the scalar reference step it replaced.
#include <random>

#include <benchmark/benchmark.h>

#include "eval/standard_split.h"
#include "motion/bvh/bvh_reader.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/reconstruct/ankle_path.h"
#include "motion/skeleton/forward_kinematics.h"
#include "tests/support/reference_ankle_dag_step.h"

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
    if (!eval::PrepareAll(standard->database_files, *rig, [&](size_t i, PreparedClip&& clip) {
           per_file[i] = std::move(clip.features);
         }).ok()) {
      return c;
    }
    std::vector<FrameFeatures> database;
    for (auto& features : per_file) database.insert(database.end(), features.begin(), features.end());
    WristFeatureIndex index;
    if (!index.Build(database).ok()) return c;
    const std::vector<DatabaseFrame> rows = ToDatabaseFrames(database);
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
        const Eigen::Vector3f n1(noise(random), noise(random), noise(random)),
            n2(noise(random), noise(random), noise(random));
        const SmoothedWrists wrists =
            smoother.Push(poses.position(f, l.left_wrist) + n1, poses.position(f, l.right_wrist) + n2);
        std::vector<AnkleCandidate> cloud;
        if (!FindAnkleCloud(index, rows, {}, wrists, ks[i], &heading, &cloud).ok()) return c;
        c.by_k[i].push_back(std::move(cloud));
      }
    }
    c.ok = true;
    return c;
  }();
  return clouds;
}

using StepFunction = void (*)(const std::vector<AnkleCandidate>&, const std::vector<float>&,
                              const std::vector<AnkleCandidate>&, float, const AnklePathOptions&, std::vector<float>*,
                              std::vector<int>*);

// The DP over the 60 clouds (59 steps), each step fed the path costs of the previous one.
// Arguments: K1, slide rule (0 = contact, 1 = patent).
void RunSteps(benchmark::State& state, StepFunction step) {
  const Clouds& clouds = GetClouds();
  if (!clouds.ok) return state.SkipWithError("shared data unavailable");
  const auto& frames = clouds.by_k[state.range(0) == 1000 ? 0 : 1];
  AnklePathOptions options;
  options.slide_rule = state.range(1) == 0 ? SlideRule::kContact : SlideRule::kPatent;
  const float dt = static_cast<float>(clouds.frame_time);
  std::vector<float> cost, next_cost;
  std::vector<int> from;
  for (auto _ : state) {
    cost.assign(frames[0].size(), 0.0f);
    for (size_t t = 1; t < frames.size(); ++t) {
      step(frames[t - 1], cost, frames[t], dt, options, &next_cost, &from);
      std::swap(cost, next_cost);
    }
    benchmark::DoNotOptimize(cost.data());
  }
  // Milliseconds per step: the inverse of (steps / 1000) per second.
  state.counters["ms_per_step"] =
      benchmark::Counter(1e-3 * static_cast<double>(frames.size() - 1),
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_AnkleDagStep(benchmark::State& state) { RunSteps(state, &AnkleDagStep); }
void BM_ReferenceAnkleDagStep(benchmark::State& state) { RunSteps(state, &testing::ReferenceAnkleDagStep); }
BENCHMARK(BM_AnkleDagStep)->ArgsProduct({{1000, 200}, {0, 1}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReferenceAnkleDagStep)->ArgsProduct({{1000, 200}, {0, 1}})->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mocap

BENCHMARK_MAIN();
