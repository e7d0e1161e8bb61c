// Cross-rig retrieval on real captures (issue #5): cmu-cc walking and running frames (CC rig,
// ~100 joints, 60 fps; some files Z-up under RL_BoneRoot) queried against a bandai-namco-2
// database (22 joints, 30 fps) retrieve walking and running clips. Reports precision@10 by
// content label with window 1 and window 5.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "motion/bvh/bvh_reader.h"
#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/preprocess/clip_labels.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/similarity/pose_index.h"
#include "motion/skeleton/forward_kinematics.h"
#include "tests/support/clip_points.h"
#include "tests/support/shared_data.h"

namespace mocap {
namespace {

using testing::ChainScalingTestName;
using testing::PointsOf;

// One in kSharedDatabaseStride clips of each content, to keep the test to a few seconds.
constexpr int kSharedDatabaseStride = 8;
const std::set<std::string> kDatabaseContents = {"walk",
                                                 "run",
                                                 "wave-both-hands",
                                                 "wave-left-hand",
                                                 "wave-right-hand",
                                                 "raise-up-both-hands",
                                                 "raise-up-left-hand",
                                                 "raise-up-right-hand"};

struct Database {
  PoseIndex index;
  std::vector<std::string> content;  // per clip
  double seconds = 0.0;
  std::string error;
};

// Built once per point sampling and scaling for all tests of this file.
const Database& GetDatabase(const std::filesystem::path& folder, const BodyPointOptions& options) {
  static std::map<std::pair<PointSampling, ChainScaling>, std::unique_ptr<Database>> cache;
  std::unique_ptr<Database>& database = cache[{options.sampling, options.scaling}];
  if (!database)
    database = [&] {
      auto db = std::make_unique<Database>();
      db->index = PoseIndex(options);
      const auto start = std::chrono::steady_clock::now();
      std::map<std::string, int> seen;
      std::unique_ptr<RigModel> rig;
      for (const std::filesystem::path& file : testing::BvhFilesIn(folder)) {
        const std::string content = LabelValue(ParseClipLabels(file.filename().string()), "content");
        if (!kDatabaseContents.count(content) || seen[content]++ % kSharedDatabaseStride != 0) continue;
        absl::StatusOr<BvhClip> clip = ReadBvhFile(file);
        if (!clip.ok()) {
          db->error = clip.status().ToString();
          break;
        }
        if (!rig) {
          absl::StatusOr<RigModel> built = BuildRigModel(*clip, {});
          if (!built.ok()) {
            db->error = built.status().ToString();
            break;
          }
          rig = std::make_unique<RigModel>(*std::move(built));
        }
        absl::StatusOr<ClipPoints> points = PointsOf(*clip, *rig, options);
        if (!points.ok()) {
          db->error = StrCat(file.filename().string(), ": ", points.status().ToString());
          break;
        }
        points->name = file.filename().string();
        db->index.AddClip(*std::move(points));
        db->content.push_back(content);
      }
      if (db->error.empty()) {
        if (absl::Status built = db->index.Build(); !built.ok()) db->error = built.ToString();
      }
      db->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return db;
    }();
  return *database;
}

struct Query {
  std::string file;
  std::string label;  // "walk" or "run"
  ClipPoints points;
};

// cmu-cc clips described as walking or running, each with its own rig model.
std::vector<Query> LoadQueries(const std::filesystem::path& folder, const BodyPointOptions& options,
                               std::string* error) {
  const std::map<std::string, std::string> descriptions = ReadTrialDescriptions(folder / "cmu-descriptions.csv");
  std::vector<Query> queries;
  for (const std::filesystem::path& file : testing::BvhFilesIn(folder)) {
    const auto it = descriptions.find(TrialKey(ParseClipLabels(file.filename().string())));
    if (it == descriptions.end()) continue;
    std::string label;
    if (it->second == "walk") label = "walk";
    if (it->second == "run/jog") label = "run";
    if (label.empty()) continue;
    absl::StatusOr<BvhClip> clip = ReadBvhFile(file);
    absl::StatusOr<RigModel> rig = clip.ok() ? BuildRigModel(*clip, {}) : absl::StatusOr<RigModel>(clip.status());
    absl::StatusOr<ClipPoints> points =
        rig.ok() ? PointsOf(*clip, *rig, options) : absl::StatusOr<ClipPoints>(rig.status());
    if (!points.ok()) {
      *error = StrCat(file.filename().string(), ": ", points.status().ToString());
      return {};
    }
    queries.push_back(Query{file.filename().string(), label, *std::move(points)});
  }
  return queries;
}

struct Precision {
  double sum = 0.0;
  int queries = 0;
  double mean() const { return queries > 0 ? sum / queries : 0.0; }
};

// (window, point sampling, scaling): issue #5 asked to measure resampled chains against the seed's
// rule, issue #11 per-chain scaling against the seed's body scale.
class SharedDataSimilarityTest : public ::testing::TestWithParam<std::tuple<int, PointSampling, ChainScaling>> {};

TEST_P(SharedDataSimilarityTest, CmuWalksAndRunsFindBandaiWalksAndRuns) {
  const int window = std::get<0>(GetParam());
  const BodyPointOptions point_options{.sampling = std::get<1>(GetParam()), .scaling = std::get<2>(GetParam())};
  const std::string sampling_name =
      StrCat(point_options.sampling == PointSampling::kResampleChains ? "resample " : "drop ",
             ChainScalingName(point_options.scaling));
  MOCAP_REQUIRE_SHARED_DATA(bandai, "bandai-namco-2");
  MOCAP_REQUIRE_SHARED_DATA(cmu, "cmu-cc");
  const Database& db = GetDatabase(bandai, point_options);
  ASSERT_TRUE(db.error.empty()) << db.error;
  ASSERT_GT(db.index.num_clips(), 100);
  std::string error;
  const std::vector<Query> queries = LoadQueries(cmu, point_options, &error);
  ASSERT_TRUE(error.empty()) << error;
  ASSERT_FALSE(queries.empty());

  std::map<std::string, Precision> by_label;
  std::map<std::string, Precision> by_file;
  for (const Query& q : queries) {
    // Every 4th frame of the walks; every frame of the one short run (43 frames at 30 fps).
    const int step = q.label == "run" ? 1 : 4;
    for (int f = 2; f < q.points.points.rows() - 2; f += step) {
      PoseSearchOptions options;
      options.top_k = 10;
      options.window = window;
      options.suppress_within_frames = 15;  // ten different moments, not one frame's neighbours
      absl::StatusOr<std::vector<PoseMatch>> matches = db.index.Search(q.points, f, options);
      ASSERT_TRUE(matches.ok()) << matches.status();
      ASSERT_EQ(matches->size(), 10u);
      int relevant = 0;
      for (const PoseMatch& m : *matches) relevant += db.content[m.clip] == q.label ? 1 : 0;
      for (Precision* p : {&by_label[q.label], &by_file[q.file]}) {
        p->sum += relevant / 10.0;
        ++p->queries;
      }
    }
  }

  std::cout << "[ similarity ] database: " << db.index.num_clips() << " bandai-namco-2 clips, " << db.index.num_frames()
            << " frames, loaded in " << std::fixed << std::setprecision(2) << db.seconds << " s\n";
  for (const auto& [label, p] : by_label) {
    std::cout << "[ similarity ] " << sampling_name << ", window " << window << ": precision@10 for cmu-cc " << label
              << " queries = " << std::setprecision(3) << p.mean() << " (" << p.queries << " query frames)\n";
    RecordProperty(StrCat("precision_at_10_", label), StrCat(p.mean()));
  }
  for (const auto& [file, p] : by_file) {
    std::cout << "[ similarity ]   " << file << ": " << std::setprecision(3) << p.mean() << "\n";
  }
  std::cout << std::defaultfloat;

  ASSERT_EQ(by_label.size(), 2u);
  // Chance is the database's share of each label (walk 7%, run 13% of the clips). Measured with
  // the first implementation (fast path, uniform weights, resample, body scale): walk 0.960
  // (window 1) / 0.962 (window 5), run 0.908 / 1.000; per-chain scaling: walk 0.934 / 0.952, run
  // 0.910 / 1.000. Bone directions (issue #11, the default): walk 0.981 / 0.988, run 0.995 / 1.000.
  // Issue #11 asks no lower than the body scale's 0.96 / 0.91 at window 1.
  if (point_options.sampling == PointSampling::kResampleChains &&
      point_options.scaling == ChainScaling::kBoneDirections && window == 1) {
    EXPECT_GE(by_label["walk"].mean(), 0.96);
    EXPECT_GE(by_label["run"].mean(), 0.91);
  }
  EXPECT_GE(by_label["walk"].mean(), 0.75);
  EXPECT_GE(by_label["run"].mean(), 0.5);
}

INSTANTIATE_TEST_SUITE_P(WindowsAndSamplings, SharedDataSimilarityTest,
                         ::testing::Combine(::testing::Values(1, 5),
                                            ::testing::Values(PointSampling::kResampleChains,
                                                              PointSampling::kDropNearestEndEffector),
                                            ::testing::Values(ChainScaling::kBoneDirections, ChainScaling::kPerChain,
                                                              ChainScaling::kBodyScale)),
                         [](const auto& info) {
                           return "Window" + std::to_string(std::get<0>(info.param)) +
                                  (std::get<1>(info.param) == PointSampling::kResampleChains ? "Resample" : "Drop") +
                                  ChainScalingTestName(std::get<2>(info.param));
                         });

}  // namespace
}  // namespace mocap

namespace mocap {
namespace {

// "Nothing here is like this" (issue #25): against the Bandai walks, runs, waves and raises, the
// frames of CMU walks and runs (another rig, other people) have similar poses, those of swordplay,
// bending over and a playground climb do not.
TEST(SharedDataNoveltyTest, PosesUnlikeTheDatabaseAreFlaggedAndOtherRigsWalksAreNot) {
  MOCAP_REQUIRE_SHARED_DATA(bandai, "bandai-namco-2");
  MOCAP_REQUIRE_SHARED_DATA(cmu, "cmu-cc");
  const BodyPointOptions options;
  const Database& database = GetDatabase(bandai, options);
  ASSERT_TRUE(database.error.empty()) << database.error;
  const PoseSearchOptions search;
  absl::StatusOr<NeighbourDistances> reference = database.index.NeighbourReference(search);
  ASSERT_TRUE(reference.ok()) << reference.status();
  EXPECT_EQ(reference->frames, kNeighbourReferenceFrames);
  EXPECT_GT(reference->isolated, reference->median);
  std::cout << "[ novelty ] Bandai database: frames' distance to their nearest pose in another clip, median "
            << reference->median << ", 95th percentile " << reference->isolated << " body scales\n";
  // Share of each query's frames (every 5th) whose best match is beyond kNoSimilarPoseNovelty.
  const auto flagged_share = [&](const ClipPoints& query) {
    int flagged = 0, frames = 0;
    for (int f = 0; f < query.points.rows(); f += 5, ++frames) {
      absl::StatusOr<std::vector<PoseMatch>> best = database.index.Search(query, f, search);
      EXPECT_TRUE(best.ok() && !best->empty());
      if (best.ok() && !best->empty())
        flagged += best->front().distance.total > kNoSimilarPoseNovelty * reference->isolated;
    }
    return frames > 0 ? static_cast<double>(flagged) / frames : 0.0;
  };
  std::string error;
  const std::vector<Query> walks_and_runs = LoadQueries(cmu, options, &error);
  ASSERT_TRUE(error.empty()) << error;
  ASSERT_FALSE(walks_and_runs.empty());
  for (const Query& query : walks_and_runs) {
    const double share = flagged_share(query.points);
    std::cout << "[ novelty ] " << query.file << " (" << query.label << "): " << share * 100 << "% of frames flagged\n";
    EXPECT_LT(share, 0.1) << query.file;
  }
  // The bend starts and ends upright (poses the database has): about half its frames are new.
  for (const auto& [file, least_share] :
       std::vector<std::pair<std::string, double>>{{"002_06.bvh", 0.4}, {"002_07.bvh", 0.8}, {"001_14.bvh", 0.6}}) {
    absl::StatusOr<BvhClip> clip = ReadBvhFile(cmu / file);
    ASSERT_TRUE(clip.ok()) << clip.status();
    absl::StatusOr<RigModel> rig = BuildRigModel(*clip, {});
    ASSERT_TRUE(rig.ok()) << rig.status();
    absl::StatusOr<ClipPoints> points = PointsOf(*clip, *rig, options);
    ASSERT_TRUE(points.ok()) << points.status();
    const double share = flagged_share(*points);
    std::cout << "[ novelty ] " << file << " (bend over, swordplay, playground): " << share * 100
              << "% of frames flagged\n";
    EXPECT_GE(share, least_share) << file;
  }
}

}  // namespace
}  // namespace mocap
