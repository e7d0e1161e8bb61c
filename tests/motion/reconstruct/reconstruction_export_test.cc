#include "motion/reconstruct/reconstruction_export.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "motion/bvh/bvh_reader.h"
#include "motion/bvh/bvh_writer.h"
#include "motion/core/units.h"
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

// Issue #23 item 3: a pelvis under another joint without position channels of its own (cmu-cc's
// CC_Base_Hip under RL_BoneRoot; the synthetic Z-up rig's Hips) gets them in the file and carries
// the motion; the root stays still at its OFFSET, on the floor, instead of moving with the body.
TEST(ReconstructionExportTest, APelvisWithoutPositionChannelsGetsThemAndTheRootStaysStill) {
  const auto setup = testing::MakeSyntheticReconstructionSetup(testing::SyntheticRigFromBits(2), 60);
  const int pelvis = setup.rig.topology.landmarks.pelvis;
  ASSERT_GT(pelvis, 0) << "a root above the pelvis";
  auto position_channels = [](const Joint& joint) {
    return std::count_if(joint.channels.begin(), joint.channels.end(), [](ChannelType c) { return !IsRotation(c); });
  };
  ASSERT_EQ(position_channels(setup.rig.skeleton.joint(pelvis)), 0) << "the case under test";
  ReconstructionOptions options;
  options.ankle_candidates = 40;
  options.pose_neighbours = 30;
  auto frames = ReconstructOffline(setup.database, options, testing::WristSamplesOf(setup));
  ASSERT_TRUE(frames.ok()) << frames.status();
  const BvhClip clip = ReconstructionToBvh(*setup.database, *frames);
  EXPECT_EQ(position_channels(clip.skeleton.joint(pelvis)), 3);
  auto parsed = ParseBvh(FormatBvh(clip), "reconstruction.bvh");
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  ASSERT_EQ(parsed->skeleton.joint(pelvis).name, setup.rig.skeleton.joint(pelvis).name);
  const GlobalPoses poses =
      ForwardKinematics(parsed->skeleton, MotionFromChannels(parsed->skeleton, parsed->channels, parsed->frame_time));
  // In metres, Y up (the file is in the rig's unit and axes).
  const float metres = static_cast<float>(MetresPerUnit(setup.rig.unit));
  auto world = [&](int f, int j) -> Eigen::Vector3f { return setup.rig.to_y_up * (metres * poses.position(f, j)); };
  for (int f = 0; f < poses.num_frames(); ++f) {
    EXPECT_LT((world(f, 0) - world(0, 0)).norm(), 1e-3f) << "root moved at frame " << f;
    EXPECT_GE(world(f, 0).y(), -1e-3f) << "root below the floor at frame " << f;
    EXPECT_GT(world(f, pelvis).y() - world(f, 0).y(), 0.2f) << "pelvis not above the root at frame " << f;
  }
  EXPECT_GT((world(poses.num_frames() - 1, pelvis) - world(0, pelvis)).norm(), 0.3f) << "the pelvis travels";
}

}  // namespace
}  // namespace mocap
