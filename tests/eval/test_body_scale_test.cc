// mocap-eval --test-body-scale (eval/evaluation.h LoadTestClips): a test take's performer made
// larger or smaller, every bone and the root's path, the rotations kept — another person's body on
// the database's rig, for measuring the method on people of other sizes on development data; and
// the same for clips scored on their landmarks (eval/cross_dataset.h LoadLandmarkTests).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "eval/cross_dataset.h"
#include "eval/evaluation.h"
#include "motion/bvh/bvh_writer.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "tests/support/synthetic_clip.h"

namespace mocap::eval {
namespace {

TEST(TestBodyScaleTest, EveryJointAndFeatureScalesAboutTheOriginAndTheRotationsStay) {
  const BvhClip walk = testing::MakeWalkingClip({}, 40);
  const std::filesystem::path file = std::filesystem::path(::testing::TempDir()) / "test_body_scale_walk.bvh";
  ASSERT_TRUE(WriteBvhFile(walk, file).ok());
  const absl::StatusOr<RigModel> rig = BuildRigModel(walk, {});
  ASSERT_TRUE(rig.ok()) << rig.status();
  const absl::StatusOr<std::vector<TestClip>> same = LoadTestClips({file}, *rig, 0, "", 1.0f);
  const absl::StatusOr<std::vector<TestClip>> larger = LoadTestClips({file}, *rig, 0, "", 1.12f);
  std::filesystem::remove(file);
  ASSERT_TRUE(same.ok() && larger.ok());
  const GlobalPoses &a = (*same)[0].truth, &b = (*larger)[0].truth;
  ASSERT_EQ(a.num_frames(), b.num_frames());
  ASSERT_EQ(a.num_joints(), b.num_joints());
  for (int f = 0; f < a.num_frames(); ++f) {
    for (int j = 0; j < a.num_joints(); ++j) {
      EXPECT_TRUE(b.position(f, j).isApprox(1.12f * a.position(f, j), 1e-4f)) << "frame " << f << " joint " << j;
      EXPECT_NEAR(b.qw(f, j), a.qw(f, j), 1e-6f);
    }
  }
  const FrameFeatures &fa = (*same)[0].clip.features[20], &fb = (*larger)[0].clip.features[20];
  EXPECT_NEAR(fb.pelvis_height, 1.12f * fa.pelvis_height, 1e-4f);
  EXPECT_NEAR(fb.wrist_position[0][1], 1.12f * fa.wrist_position[0][1], 1e-4f);
  EXPECT_NEAR(fb.pelvis_tilt, fa.pelvis_tilt, 1e-5f);
}

TEST(TestBodyScaleTest, LandmarkTestsScaleEveryLandmarkAboutTheOrigin) {
  const BvhClip walk = testing::MakeWalkingClip({}, 40);
  const std::filesystem::path file = std::filesystem::path(::testing::TempDir()) / "test_body_scale_landmarks.bvh";
  ASSERT_TRUE(WriteBvhFile(walk, file).ok());
  const absl::StatusOr<LandmarkTestSet> same = LoadLandmarkTests({file}, 0);
  const absl::StatusOr<LandmarkTestSet> larger = LoadLandmarkTests({file}, 0, 1.12f);
  std::filesystem::remove(file);
  ASSERT_TRUE(same.ok()) << same.status();
  ASSERT_TRUE(larger.ok()) << larger.status();
  ASSERT_EQ(same->clips.size(), 1u) << (same->left_out.empty() ? "" : same->left_out.front());
  ASSERT_EQ(larger->clips.size(), 1u);
  const LandmarkTruth &a = same->clips[0].truth, &b = larger->clips[0].truth;
  ASSERT_EQ(a.num_frames(), b.num_frames());
  EXPECT_EQ(a.frame_time, b.frame_time);  // the same motion at the same times, in a larger body
  for (int f = 0; f < a.num_frames(); ++f) {
    for (int k = 0; k < kNumScoredLandmarks; ++k) {
      EXPECT_TRUE(b.positions[f][k].isApprox(1.12f * a.positions[f][k], 1e-5f)) << "frame " << f << " landmark " << k;
    }
  }
}

}  // namespace
}  // namespace mocap::eval
