#include "motion/reconstruct/reconstruction_export.h"

#include <gtest/gtest.h>

#include "motion/bvh/bvh_reader.h"
#include "motion/bvh/bvh_writer.h"
#include "tests/support/synthetic_database.h"

namespace mocap {
namespace {

// The exported file, read back and prepared like any imported clip, puts every joint where the
// reconstruction did — for rigs authored Z-up, in inches, or with an extra root.
TEST(ReconstructionExportTest, TheBvhReadsBackAsTheReconstructedMotion) {
  for (int bits : {0, 1, 2, 16}) {
    testing::SyntheticRigOptions rig_options = testing::SyntheticRigFromBits(bits);
    if (bits == 2) rig_options.length_scale = 1.0 / 2.54;
    const auto setup = testing::MakeSyntheticReconstructionSetup(rig_options, 40);
    ReconstructionOptions options;
    options.ankle_candidates = 40;
    options.pose_neighbours = 30;
    auto frames = ReconstructOffline(setup.database, options, testing::WristSamplesOf(setup));
    ASSERT_TRUE(frames.ok()) << frames.status();
    const BvhClip clip = ReconstructionToBvh(*setup.database, *frames);
    auto parsed = ParseBvh(FormatBvh(clip), "reconstruction.bvh");
    ASSERT_TRUE(parsed.ok()) << parsed.status();
    auto prepared = PrepareClip(*parsed, setup.rig, {});
    ASSERT_TRUE(prepared.ok()) << prepared.status();
    ASSERT_EQ(prepared->num_frames(), static_cast<int>(frames->size()));
    const GlobalPoses read_back = ForwardKinematics(prepared->skeleton, prepared->motion);
    std::vector<Eigen::Quaternionf> rotations;
    std::vector<Eigen::Vector3f> positions;
    // Every body joint; nodes above the pelvis are held still (see the next test).
    std::vector<bool> above_pelvis(read_back.num_joints(), false);
    for (int j = setup.rig.skeleton.parent(setup.rig.topology.landmarks.pelvis); j >= 0;
         j = setup.rig.skeleton.parent(j)) {
      above_pelvis[j] = true;
    }
    for (int f : {0, 17, 39}) {
      setup.database->body().WorldTransforms((*frames)[f].pose, &rotations, &positions);
      for (int j = 0; j < read_back.num_joints(); ++j) {
        if (above_pelvis[j]) continue;
        EXPECT_LT((read_back.position(f, j) - positions[j]).norm(), 2e-4f)
            << "rig bits " << bits << " frame " << f << " joint " << j;
      }
    }
  }
}

// Issue #10: the root above the pelvis (Bandai's joint_Root) stays where the capture keeps it, at
// its OFFSET with its rest rotation, instead of wandering metres away and under the floor; the
// pelvis carries the motion in its position channels.
TEST(ReconstructionExportTest, AStaticRootStaysStillAndAboveTheFloor) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({.extra_root = true}, 60);
  ReconstructionOptions options;
  options.ankle_candidates = 40;
  options.pose_neighbours = 30;
  auto frames = ReconstructOffline(setup.database, options, testing::WristSamplesOf(setup));
  ASSERT_TRUE(frames.ok()) << frames.status();
  const BvhClip clip = ReconstructionToBvh(*setup.database, *frames);
  ASSERT_EQ(clip.skeleton.joint(0).name, "Root");
  const int root_channels = static_cast<int>(clip.skeleton.joint(0).channels.size());
  for (int f = 0; f < clip.num_frames(); ++f) {
    for (int c = 0; c < root_channels; ++c)
      EXPECT_NEAR(clip.channels(f, c), 0.0f, 1e-3f) << "frame " << f << " channel " << c;
  }
  auto parsed = ParseBvh(FormatBvh(clip), "reconstruction.bvh");
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  const GlobalPoses poses =
      ForwardKinematics(parsed->skeleton, MotionFromChannels(parsed->skeleton, parsed->channels, parsed->frame_time));
  for (int f = 0; f < poses.num_frames(); ++f) {
    EXPECT_GE(poses.position(f, 0).y(), -1e-3f) << "root below the floor at frame " << f;
    EXPECT_GT(poses.position(f, 1).y(), 0.2f) << "pelvis not above the root at frame " << f;
  }
}

}  // namespace
}  // namespace mocap
