#include "motion/reconstruct/reconstruction_database.h"

#include <gtest/gtest.h>

#include "motion/reconstruct/local_pose_model.h"
#include "tests/support/synthetic_clip.h"

namespace mocap {
namespace {

struct Built {
  RigModel rig;
  std::vector<DatabaseClip> clips;
};

Built MakeClips(const testing::SyntheticRigOptions& options) {
  Built built;
  const BvhClip first = testing::MakeWalkingClip(options, 90);
  built.rig = *BuildRigModel(first, {});
  for (int frames : {90, 61}) {
    auto prepared = PrepareClip(testing::MakeWalkingClip(options, frames), built.rig, {});
    EXPECT_TRUE(prepared.ok());
    built.clips.push_back({prepared->features, EncodePoses(prepared->motion, built.rig)});
  }
  return built;
}

TEST(ReconstructionDatabaseTest, HoldsFeaturesPosesAndClipBoundaries) {
  for (bool extra_root : {false, true}) {
    const Built b = MakeClips({.extra_root = extra_root});
    auto db = ReconstructionDatabase::Build(b.rig, b.clips);
    ASSERT_TRUE(db.ok()) << db.status();
    EXPECT_EQ((*db)->num_frames(), 90 + 61);
    EXPECT_EQ((*db)->clip_of(89), 0);
    EXPECT_EQ((*db)->clip_of(90), 1);
    EXPECT_EQ((*db)->frame_in_clip(95), 5);
    // q leaves out the root-to-pelvis chain (the solver's pelvis orientation).
    const Skeleton& skeleton = b.rig.skeleton;
    for (int j : (*db)->pose_joints()) {
      EXPECT_NE(skeleton.joint(j).name, "Hips");
      EXPECT_NE(skeleton.joint(j).name, "Root");
    }
    EXPECT_EQ((*db)->pose_joints().size(), static_cast<size_t>(skeleton.num_joints() - (extra_root ? 2 : 1)));
    const auto& m = (*db)->pose_features();
    EXPECT_EQ(m.cols(), 2 + 3 * static_cast<int>((*db)->pose_joints().size()));
    EXPECT_FLOAT_EQ(m(95, 0), b.clips[1].features[5].pelvis_tilt);
    EXPECT_FLOAT_EQ(m(95, 1), b.clips[1].features[5].pelvis_height);
    const int stride = EncodedPoseFloats(skeleton.num_joints());
    const int joint = (*db)->pose_joints()[3];
    EXPECT_FLOAT_EQ(m(95, 2 + 3 * 3 + 1), b.clips[1].encoded_poses[5 * stride + 3 + 3 * joint + 1]);
  }
}

TEST(ReconstructionDatabaseTest, NearestFramesAndALocalModelThatFitsThem) {
  const Built b = MakeClips({});
  auto db = ReconstructionDatabase::Build(b.rig, b.clips);
  ASSERT_TRUE(db.ok());
  float query[kWristAnkleFeatureDims];
  WristAnkleFeature((*db)->frames()[40], 0.8f, query);
  auto neighbours = (*db)->NearestByWristsAndAnkles(query, 40);
  ASSERT_TRUE(neighbours.ok());
  ASSERT_EQ(neighbours->size(), 40u);
  EXPECT_NEAR(neighbours->front().distance, 0.0f, 1e-9f);
  Eigen::MatrixXf examples(neighbours->size(), (*db)->pose_features().cols());
  for (size_t i = 0; i < neighbours->size(); ++i) examples.row(i) = (*db)->pose_features().row((*neighbours)[i].row);
  auto model = FitLocalPoseModel(examples, 6);
  ASSERT_TRUE(model.ok());
  const Eigen::VectorXf pose = (*db)->pose_features().row(40).transpose();
  // The query's own pose lies close to the 6-D local model of its neighbours (A5).
  EXPECT_LT((model->Reconstruct(model->Project(pose)) - pose).norm(), 0.05f * pose.norm() + 1e-3f);
}

TEST(ReconstructionDatabaseTest, RejectsInconsistentInput) {
  Built b = MakeClips({});
  EXPECT_EQ(ReconstructionDatabase::Build(b.rig, {}).status().code(), absl::StatusCode::kFailedPrecondition);
  b.clips[1].encoded_poses.pop_back();
  EXPECT_EQ(ReconstructionDatabase::Build(b.rig, b.clips).status().code(), absl::StatusCode::kInvalidArgument);
  b = MakeClips({});
  auto db = ReconstructionDatabase::Build(b.rig, b.clips);
  float query[kWristAnkleFeatureDims] = {};
  query[5] = std::nanf("");
  EXPECT_EQ((*db)->NearestByWristsAndAnkles(query, 3).status().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace mocap
