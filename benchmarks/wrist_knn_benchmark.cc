// docs/method.md A3 on the standard split: K1 = 1000 nearest database frames by eq. 2, FLANN kd-tree
// against exact brute force in the same run (speed-up and recall as counters). Database =
// bandai-namco-2 takes not ≡ 3 (mod 10); queries = frames of the held-out takes (≡ 3 mod 10) with
// their wrists' features perturbed as by σ = 0.5 cm position noise (fixed seed).
#include <algorithm>
#include <random>

#include <benchmark/benchmark.h>

#include "eval/standard_split.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/reconstruct/wrist_feature_index.h"

namespace mocap {
namespace {

struct Split {
  std::vector<float> points;  // the features the index was built over (the brute-force reference's)
  WristFeatureIndex index;
  std::vector<std::array<float, kWristFeatureDims>> queries;
  bool ok = false;
};

const Split& GetSplit() {
  static Split split = [] {
    Split s;
    auto standard = eval::LoadStandardSplit();
    if (!standard.ok()) return s;
    std::vector<std::vector<FrameFeatures>> database_features(standard->database_files.size());
    std::vector<std::vector<FrameFeatures>> test_features(standard->test_files.size());
    if (!eval::PrepareAll(standard->database_files, standard->rig,
                          [&](size_t i, PreparedClip&& clip) { database_features[i] = std::move(clip.features); })
             .ok() ||
        !eval::PrepareAll(standard->test_files, standard->rig, [&](size_t i, PreparedClip&& clip) {
           test_features[i] = std::move(clip.features);
         }).ok()) {
      return s;
    }
    std::vector<FrameFeatures> test_frames;
    std::vector<FrameFeatures> database;
    for (auto& f : database_features) database.insert(database.end(), f.begin(), f.end());
    for (auto& f : test_features) test_frames.insert(test_frames.end(), f.begin(), f.end());
    if (!s.index.Build(database).ok()) return s;
    s.points = WristFeatures(database);
    std::mt19937 random(42);
    std::normal_distribution<float> noise(0.0f, 0.005f);
    for (size_t i = 0; i < test_frames.size() && s.queries.size() < 200; i += test_frames.size() / 200 + 1) {
      FrameFeatures q = test_frames[i];
      for (int side = 0; side < 2; ++side) {
        for (int axis = 0; axis < 3; ++axis) q.wrist_position[side][axis] += noise(random);
      }
      std::array<float, kWristFeatureDims> feature;
      WristFeature(q, {}, feature.data());
      s.queries.push_back(feature);
    }
    s.ok = true;
    return s;
  }();
  return split;
}

void BM_WristKnn(benchmark::State& state, bool brute_force) {
  const Split& split = GetSplit();
  if (!split.ok) return state.SkipWithError("shared data unavailable");
  const int k = static_cast<int>(state.range(0));
  size_t q = 0;
  for (auto _ : state) {
    const auto& query = split.queries[q++ % split.queries.size()];
    auto result = brute_force ? BruteForceNearest(split.points, kWristFeatureDims, query.data(), k)
                              : split.index.Search(query.data(), k);
    benchmark::DoNotOptimize(result);
  }
  state.counters["database_frames"] = split.index.size();
  if (!brute_force) {
    // Recall of the exact K set (by distance: ties at the K-th distance count as found).
    double recall = 0;
    for (const auto& query : split.queries) {
      auto fast = split.index.Search(query.data(), k);
      auto exact = BruteForceNearest(split.points, kWristFeatureDims, query.data(), k);
      const float kth = exact->back().distance * (1 + 1e-5f) + 1e-9f;
      recall += static_cast<double>(
                    std::count_if(fast->begin(), fast->end(), [&](const Neighbour& n) { return n.distance <= kth; })) /
                k;
    }
    state.counters["recall"] = recall / split.queries.size();
  }
}
BENCHMARK_CAPTURE(BM_WristKnn, kd_tree, false)->Arg(1000)->Arg(200)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_WristKnn, brute_force, true)->Arg(1000)->Arg(200)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace mocap

BENCHMARK_MAIN();
