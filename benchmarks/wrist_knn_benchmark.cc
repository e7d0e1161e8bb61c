// METHOD.md A3 on the standard split: K1 = 1000 nearest database frames by eq. 2, FLANN kd-tree
// against exact brute force in the same run (speed-up and recall as counters). Database =
// bandai-namco-2 takes not ≡ 3 (mod 10); queries = frames of the held-out takes (≡ 3 mod 10) with
// their wrists' features perturbed as by σ = 0.5 cm position noise (fixed seed).
#include <algorithm>
#include <random>
#include <thread>
#include <unordered_set>

#include <benchmark/benchmark.h>

#include "motion/bvh/bvh_reader.h"
#include "motion/preprocess/clip_labels.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/reconstruct/wrist_feature_index.h"
#include "tests/support/shared_data.h"

namespace mocap {
namespace {

struct Split {
  WristFeatureIndex index;
  std::vector<std::array<float, kWristFeatureDims>> queries;
  bool ok = false;
};

bool IsTestTake(const std::string& file_name) {
  const std::string take = LabelValue(ParseClipLabels(file_name), "take");
  return !take.empty() && std::stoi(take) % 10 == 3;
}

const Split& GetSplit() {
  static Split split = [] {
    Split s;
    std::string why;
    auto folder = testing::SharedDataSet("bandai-namco-2", &why);
    if (!folder) return s;
    const auto files = testing::BvhFilesIn(*folder);
    auto first = ReadBvhFile(files.front());
    if (!first.ok()) return s;
    auto rig = BuildRigModel(*first, {});
    if (!rig.ok()) return s;
    std::vector<std::vector<FrameFeatures>> per_file(files.size());
    std::vector<std::thread> workers;
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    for (unsigned t = 0; t < threads; ++t) {
      workers.emplace_back([&, t] {
        for (size_t i = t; i < files.size(); i += threads) {
          auto clip = ReadBvhFile(files[i]);
          if (!clip.ok()) continue;
          auto prepared = PrepareClip(*clip, *rig, {});
          if (prepared.ok()) per_file[i] = std::move(prepared->features);
        }
      });
    }
    for (auto& worker : workers) worker.join();
    std::vector<FrameFeatures> database;
    std::vector<FrameFeatures> test_frames;
    for (size_t i = 0; i < files.size(); ++i) {
      auto& target = IsTestTake(files[i].filename().string()) ? test_frames : database;
      target.insert(target.end(), per_file[i].begin(), per_file[i].end());
    }
    if (!s.index.Build(database).ok()) return s;
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
    auto result = brute_force ? split.index.SearchBruteForce(query.data(), k) : split.index.Search(query.data(), k);
    benchmark::DoNotOptimize(result);
  }
  state.counters["database_frames"] = split.index.size();
  if (!brute_force) {
    // Recall of the exact K set (by distance: ties at the K-th distance count as found).
    double recall = 0;
    for (const auto& query : split.queries) {
      auto fast = split.index.Search(query.data(), k);
      auto exact = split.index.SearchBruteForce(query.data(), k);
      const float kth = exact->back().distance * (1 + 1e-5f) + 1e-9f;
      recall += static_cast<double>(std::count_if(fast->begin(), fast->end(),
                                                  [&](const Neighbour& n) { return n.distance <= kth; })) / k;
    }
    state.counters["recall"] = recall / split.queries.size();
  }
}
BENCHMARK_CAPTURE(BM_WristKnn, kd_tree, false)->Arg(1000)->Arg(200)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_WristKnn, brute_force, true)->Arg(1000)->Arg(200)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace mocap

BENCHMARK_MAIN();
