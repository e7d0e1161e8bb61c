// Rigs stored before issue #11 kept no shoulder / hip landmarks: their chains find them by the
// length rule (UpperSegmentStart). On the rigs of all three shared sets that rule picks the joints
// the analysis finds from the motion, so such databases give the same points as re-imported ones.
#include <gtest/gtest.h>

#include "motion/bvh/bvh_reader.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/similarity/body_points.h"
#include "motion/skeleton/forward_kinematics.h"
#include "tests/support/shared_data.h"

namespace mocap {
namespace {

TEST(LimbSectionsSharedDataTest, StoredRigsWithoutShouldersAndHipsGiveTheSamePoints) {
  for (const char* set : {"bandai-namco-2", "bandai-namco-1", "cmu-cc"}) {
    MOCAP_REQUIRE_SHARED_DATA(folder, set);
    const std::vector<std::filesystem::path> files = testing::BvhFilesIn(folder);
    ASSERT_FALSE(files.empty()) << set;
    absl::StatusOr<BvhClip> clip = ReadBvhFile(files.front());
    ASSERT_TRUE(clip.ok()) << clip.status();
    absl::StatusOr<RigModel> rig = BuildRigModel(*clip, {});
    ASSERT_TRUE(rig.ok()) << rig.status();
    const BodyLandmarks& l = rig->topology.landmarks;
    for (int joint : {l.left_shoulder, l.right_shoulder, l.left_hip, l.right_hip}) ASSERT_GE(joint, 0) << set;
    absl::StatusOr<PreparedClip> prepared = PrepareClip(*clip, *rig, {});
    ASSERT_TRUE(prepared.ok()) << prepared.status();
    const GlobalPoses poses = ForwardKinematics(prepared->skeleton, prepared->motion);

    BodyTopology old_topology = rig->topology;
    old_topology.landmarks.left_shoulder = old_topology.landmarks.right_shoulder = -1;
    old_topology.landmarks.left_hip = old_topology.landmarks.right_hip = -1;
    const BodyPointMatrix analysed = BodyPointsOfClip(poses, MakeBodyChains(rig->skeleton, rig->topology), {});
    const BodyPointMatrix by_length = BodyPointsOfClip(poses, MakeBodyChains(rig->skeleton, old_topology), {});
    EXPECT_LT((analysed - by_length).cwiseAbs().maxCoeff(), 1e-6f) << set << ": " << files.front().filename();
  }
}

}  // namespace
}  // namespace mocap
