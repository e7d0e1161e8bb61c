// AnkleDagStep (the vectorised, bounded A4 step of docs/method.md) against the scalar reference step it
// replaced: the same path costs and the same best predecessors, except where two predecessors
// tie, on random clouds and on real ankle clouds, for both slide rules.
#include <random>

#include <gtest/gtest.h>

#include "motion/bvh/bvh_reader.h"
#include "motion/preprocess/clip_labels.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/reconstruct/ankle_edge_cost.h"
#include "motion/reconstruct/ankle_path.h"
#include "motion/skeleton/forward_kinematics.h"
#include "tests/support/reference_ankle_dag_step.h"
#include "tests/support/shared_data.h"

namespace mocap {
namespace {

constexpr float kFrameTime = 1.0f / 30.0f;

bool Near(float a, float b) { return std::abs(a - b) <= 1e-6f * std::max(1.0f, std::abs(b)); }

// Runs both steps on the same input and compares them node by node. Returns the reference costs
// (to feed the next step).
std::vector<float> ExpectSameStep(const std::vector<AnkleCandidate>& previous, const std::vector<float>& previous_cost,
                                  const std::vector<AnkleCandidate>& current, const AnklePathOptions& options) {
  std::vector<float> cost, reference_cost;
  std::vector<int> from, reference_from;
  AnkleDagStep(previous, previous_cost, current, kFrameTime, options, &cost, &from);
  testing::ReferenceAnkleDagStep(previous, previous_cost, current, kFrameTime, options, &reference_cost,
                                 &reference_from);
  EXPECT_EQ(cost.size(), current.size());
  EXPECT_EQ(from.size(), current.size());
  int differing = 0;
  for (size_t k = 0; k < current.size(); ++k) {
    EXPECT_TRUE(Near(cost[k], reference_cost[k])) << "node " << k << ": " << cost[k] << " vs " << reference_cost[k];
    if (from[k] == reference_from[k]) continue;
    ++differing;
    // Only a tie may choose another predecessor.
    const float through = previous_cost[from[k]] + AnkleEdgeCost(previous[from[k]], current[k], kFrameTime, options);
    EXPECT_TRUE(Near(through, reference_cost[k])) << "node " << k << " via " << from[k] << ": " << through << " vs "
                                                  << reference_cost[k] << " via " << reference_from[k];
  }
  EXPECT_LE(differing, static_cast<int>(current.size()) / 100);
  return reference_cost;
}

// Ankles scattered around the contact ceiling (so that both planted and lifted feet occur), with
// velocities, in a 40 cm box.
std::vector<AnkleCandidate> RandomCloud(int size, std::mt19937* random) {
  std::uniform_real_distribution<float> across(-0.2f, 0.2f), height(0.06f, 0.2f), speed(-1.0f, 1.0f);
  std::vector<AnkleCandidate> cloud(size);
  for (int i = 0; i < size; ++i) {
    cloud[i].row = i;
    for (int side = 0; side < 2; ++side) {
      cloud[i].position[side] = Eigen::Vector3f(across(*random) + 0.2f * side, height(*random), across(*random) + 3.0f);
      cloud[i].velocity[side] = Eigen::Vector3f(speed(*random), 0.3f * speed(*random), speed(*random));
    }
  }
  return cloud;
}

AnklePathOptions WithRule(SlideRule rule) {
  AnklePathOptions options;
  options.slide_rule = rule;
  return options;
}

class AnkleDagStepTest : public ::testing::TestWithParam<SlideRule> {};

TEST_P(AnkleDagStepTest, MatchesTheReferenceOnRandomClouds) {
  const AnklePathOptions options = WithRule(GetParam());
  for (unsigned seed : {1u, 2u, 3u}) {
    std::mt19937 random(seed);
    for (int size : {1, 7, 64, 65, 300}) {
      std::vector<AnkleCandidate> previous = RandomCloud(size, &random);
      std::vector<float> cost(size, 0.0f);  // a segment's start: every path costs 0 (all tie)
      for (int t = 0; t < 4; ++t) {
        const std::vector<AnkleCandidate> current = RandomCloud(size + t, &random);
        cost = ExpectSameStep(previous, cost, current, options);
        previous = current;
      }
    }
  }
}

TEST_P(AnkleDagStepTest, MatchesTheReferenceWithTiedPathCosts) {
  const AnklePathOptions options = WithRule(GetParam());
  std::mt19937 random(11);
  const std::vector<AnkleCandidate> previous = RandomCloud(200, &random), current = RandomCloud(150, &random);
  std::vector<float> cost(previous.size());
  for (size_t j = 0; j < cost.size(); ++j) cost[j] = static_cast<float>(j % 5);  // many equal path costs
  ExpectSameStep(previous, cost, current, options);
}

TEST_P(AnkleDagStepTest, MatchesTheReferenceOnRealClouds) {
  MOCAP_REQUIRE_SHARED_DATA(folder, "bandai-namco-2");
  const auto files = testing::BvhFilesIn(folder);
  auto first = ReadBvhFile(files.front());
  ASSERT_TRUE(first.ok());
  auto rig = BuildRigModel(*first, {});
  ASSERT_TRUE(rig.ok());
  // A small database (every 8th clip) and one walk not in it.
  std::vector<FrameFeatures> database;
  std::filesystem::path query;
  for (size_t i = 0; i < files.size(); ++i) {
    const std::string name = files[i].filename().string();
    if (query.empty() && i % 8 == 1 && name.find("_walk_") != std::string::npos) {
      query = files[i];
      continue;
    }
    if (i % 8 != 0) continue;
    auto clip = ReadBvhFile(files[i]);
    ASSERT_TRUE(clip.ok()) << clip.status();
    auto prepared = PrepareClip(*clip, *rig, {});
    ASSERT_TRUE(prepared.ok()) << prepared.status();
    database.insert(database.end(), prepared->features.begin(), prepared->features.end());
  }
  ASSERT_FALSE(query.empty());
  WristFeatureIndex index;
  ASSERT_TRUE(index.Build(database).ok());
  const std::vector<DatabaseFrame> rows = ToDatabaseFrames(database);
  auto clip = ReadBvhFile(query);
  ASSERT_TRUE(clip.ok());
  auto prepared = PrepareClip(*clip, *rig, {});
  ASSERT_TRUE(prepared.ok());
  const GlobalPoses poses = ForwardKinematics(prepared->skeleton, prepared->motion);
  const BodyLandmarks& l = rig->topology.landmarks;
  AnklePathOptions options = WithRule(GetParam());
  options.planted_ankle_height = 0.08f;
  WristSmoother smoother({}, kFrameTime);
  float heading = 0.0f;
  std::vector<AnkleCandidate> previous;
  std::vector<float> cost;
  for (int f = 0; f < std::min(40, poses.num_frames()); ++f) {
    const SmoothedWrists wrists = smoother.Push(poses.position(f, l.left_wrist), poses.position(f, l.right_wrist));
    std::vector<AnkleCandidate> cloud;
    ASSERT_TRUE(FindAnkleCloud(index, rows, {}, wrists, 300, &heading, &cloud).ok());
    cost = previous.empty() ? std::vector<float>(cloud.size(), 0.0f) : ExpectSameStep(previous, cost, cloud, options);
    previous = std::move(cloud);
  }
}

INSTANTIATE_TEST_SUITE_P(BothSlideRules, AnkleDagStepTest, ::testing::Values(SlideRule::kContact, SlideRule::kPatent),
                         [](const auto& info) { return info.param == SlideRule::kContact ? "Contact" : "Patent"; });

}  // namespace
}  // namespace mocap
