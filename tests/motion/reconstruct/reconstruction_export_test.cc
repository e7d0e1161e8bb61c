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
    for (int f : {0, 17, 39}) {
      setup.database->body().WorldTransforms((*frames)[f].pose, &rotations, &positions);
      for (int j = 0; j < read_back.num_joints(); ++j) {
        EXPECT_LT((read_back.position(f, j) - positions[j]).norm(), 2e-4f) << "rig bits " << bits << " frame " << f << " joint " << j;
      }
    }
  }
}

}  // namespace
}  // namespace mocap
