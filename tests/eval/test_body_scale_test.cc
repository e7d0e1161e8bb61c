// mocap-eval --test-body-scale (eval/evaluation.h LoadTestClips): a test take's performer made
// larger or smaller, every bone and the root's path, the rotations kept — another person's body on
// the database's rig, for measuring the method on people of other sizes on development data.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

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

}  // namespace
}  // namespace mocap::eval
