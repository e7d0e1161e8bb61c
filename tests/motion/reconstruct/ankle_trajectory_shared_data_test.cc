// A2–A4 on real data: ankles estimated from noisy wrists of held-out walks (standard split of
// shared/data/README: database = bandai-namco-2 takes not ≡ 3 mod 10, here every 3rd such clip
// to keep the test short; queries = takes ≡ 3 mod 10; wrists by FK plus σ = 0.5 cm noise). The
// DAG path must be at least as accurate as a plain nearest-neighbour lookup and far smoother.
#include <iostream>
#include <random>

#include <gtest/gtest.h>

#include "motion/bvh/bvh_reader.h"
#include "motion/preprocess/clip_labels.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/reconstruct/ankle_path.h"
#include "motion/skeleton/forward_kinematics.h"
#include "tests/support/shared_data.h"

namespace mocap {
namespace {

int TakeOf(const std::string& file_name) {
  const std::string take = LabelValue(ParseClipLabels(file_name), "take");
  return take.empty() ? -1 : std::stoi(take);
}

float Jitter(const std::vector<AnklePair>& path) {
  float sum = 0.0f;
  int count = 0;
  for (size_t t = 3; t < path.size(); ++t) {
    for (int side = 0; side < 2; ++side) {
      sum += (path[t][side] - 3 * path[t - 1][side] + 3 * path[t - 2][side] - path[t - 3][side]).norm();
      ++count;
    }
  }
  return count ? sum / count : 0.0f;
}

TEST(AnkleTrajectorySharedDataTest, DagBeatsNearestNeighbourOnHeldOutWalks) {
  MOCAP_REQUIRE_SHARED_DATA(folder, "bandai-namco-2");
  const auto files = testing::BvhFilesIn(folder);
  auto first = ReadBvhFile(files.front());
  ASSERT_TRUE(first.ok());
  auto rig = BuildRigModel(*first, {});
  ASSERT_TRUE(rig.ok());
  std::vector<FrameFeatures> database;
  std::vector<std::filesystem::path> queries;
  int kept = 0;
  for (const auto& file : files) {
    const std::string name = file.filename().string();
    if (TakeOf(name) % 10 == 3) {
      if (name.find("_walk_") != std::string::npos && queries.size() < 3) queries.push_back(file);
      continue;
    }
    if (kept++ % 3 != 0) continue;
    auto clip = ReadBvhFile(file);
    ASSERT_TRUE(clip.ok()) << clip.status();
    auto prepared = PrepareClip(*clip, *rig, {});
    ASSERT_TRUE(prepared.ok()) << prepared.status();
    database.insert(database.end(), prepared->features.begin(), prepared->features.end());
  }
  WristFeatureIndex index;
  ASSERT_TRUE(index.Build(database).ok());
  const std::vector<DatabaseFrame> rows = ToDatabaseFrames(database);
  ASSERT_EQ(queries.size(), 3u);

  const BodyLandmarks& l = rig->topology.landmarks;
  std::mt19937 random(2024);
  std::normal_distribution<float> noise(0.0f, 0.005f);
  double dag_error = 0, nn_error = 0, dag_jitter = 0, nn_jitter = 0, truth_jitter = 0;
  for (const auto& file : queries) {
    auto clip = ReadBvhFile(file);
    auto prepared = PrepareClip(*clip, *rig, {});
    ASSERT_TRUE(prepared.ok());
    const GlobalPoses poses = ForwardKinematics(prepared->skeleton, prepared->motion);
    const double dt = prepared->motion.frame_time;
    WristSmoother smoother({}, dt);
    float heading = 0.0f;
    std::vector<std::vector<AnkleCandidate>> clouds;
    std::vector<AnklePair> truth, nearest;
    for (int f = 0; f < poses.num_frames(); ++f) {
      const Eigen::Vector3f jitter_left(noise(random), noise(random), noise(random));
      const Eigen::Vector3f jitter_right(noise(random), noise(random), noise(random));
      const SmoothedWrists wrists =
          smoother.Push(poses.position(f, l.left_wrist) + jitter_left, poses.position(f, l.right_wrist) + jitter_right);
      std::vector<AnkleCandidate> cloud;
      ASSERT_TRUE(FindAnkleCloud(index, rows, {}, wrists, 200, &heading, &cloud).ok());
      nearest.push_back({cloud[0].position[0], cloud[0].position[1]});
      clouds.push_back(std::move(cloud));
      truth.push_back({poses.position(f, l.left_ankle), poses.position(f, l.right_ankle)});
    }
    auto path = SolveAnklePath(clouds, 0, dt, {});
    ASSERT_TRUE(path.ok()) << path.status();
    double clip_dag = 0, clip_nn = 0;
    for (size_t t = 0; t < truth.size(); ++t) {
      for (int side = 0; side < 2; ++side) {
        clip_dag += ((*path)[t][side] - truth[t][side]).norm();
        clip_nn += (nearest[t][side] - truth[t][side]).norm();
      }
    }
    dag_error += clip_dag / (2 * truth.size()) / queries.size();
    nn_error += clip_nn / (2 * truth.size()) / queries.size();
    dag_jitter += Jitter(*path) / queries.size();
    nn_jitter += Jitter(nearest) / queries.size();
    truth_jitter += Jitter(truth) / queries.size();
  }
  std::cout << "[ ankles ] database " << database.size() << " frames; mean ankle error: DAG " << dag_error * 100
            << " cm, nearest neighbour " << nn_error * 100 << " cm; jitter (m/frame^3): DAG " << dag_jitter
            << ", nearest neighbour " << nn_jitter << ", ground truth " << truth_jitter << "\n";
  RecordProperty("dag_ankle_error_cm", std::to_string(dag_error * 100));
  RecordProperty("nn_ankle_error_cm", std::to_string(nn_error * 100));
  EXPECT_LE(dag_error, nn_error * 1.05);
  EXPECT_LT(dag_jitter, 0.5 * nn_jitter);
}

}  // namespace
}  // namespace mocap
