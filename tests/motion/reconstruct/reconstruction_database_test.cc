#include "motion/reconstruct/reconstruction_database.h"

#include <limits>
#include <numbers>

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
    EXPECT_EQ((*db)->num_rows(), 2 * (90 + 61));  // and every clip backwards
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
    EXPECT_EQ((*db)->pose_feature_size(), 2 + 3 * static_cast<int>((*db)->pose_joints().size()));
    const Eigen::VectorXf m = (*db)->pose_feature(95).transpose();
    // 16-bit fixed point per column: within half a step of the largest magnitude / 32767 (angles
    // of at most π, a pelvis under 2 m here).
    constexpr float kAngleStep = std::numbers::pi_v<float> / 32767.0f, kHeightStep = 2.0f / 32767.0f;
    EXPECT_NEAR(m[0], b.clips[1].features[5].pelvis_tilt, kAngleStep / 2);
    EXPECT_NEAR(m[1], b.clips[1].features[5].pelvis_height, kHeightStep / 2);
    const int stride = EncodedPoseFloats(skeleton.num_joints());
    const int joint = (*db)->pose_joints()[3];
    EXPECT_NEAR(m[2 + 3 * 3 + 1], b.clips[1].encoded_poses[5 * stride + 3 + 3 * joint + 1], kAngleStep / 2);
  }
}

TEST(ReconstructionDatabaseTest, RefusesAPoseThatIsNotANumber) {
  Built b = MakeClips({});
  // The last joint's rotation in frame 0 (a leaf, never on the pelvis chain).
  b.clips[1].encoded_poses[EncodedPoseFloats(b.rig.skeleton.num_joints()) - 1] =
      std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(ReconstructionDatabase::Build(b.rig, b.clips).status().code(), absl::StatusCode::kInvalidArgument);
}

TEST(ReconstructionDatabaseTest, RefusesWeightsNoQueryCanUse) {
  const Built b = MakeClips({});
  for (const WristAnkleWeights bad :
       {WristAnkleWeights{.position_weight = 1.5f}, WristAnkleWeights{.position_weight = -0.1f},
        WristAnkleWeights{.ankle_position_scale = -1.0f}, WristAnkleWeights{.ankle_velocity_scale = std::nanf("")},
        WristAnkleWeights{.ankle_position_scale = std::numeric_limits<float>::infinity()}}) {
    EXPECT_EQ(ReconstructionDatabase::Build(b.rig, b.clips, {.pose_query = bad}).status().code(),
              absl::StatusCode::kInvalidArgument);
  }
  EXPECT_EQ(ReconstructionDatabase::Build(b.rig, b.clips, {.wrist_query = {.position_weight = 2.0f}}).status().code(),
            absl::StatusCode::kInvalidArgument);
  // Each equation keeps the weights it was given.
  const auto db = ReconstructionDatabase::Build(
      b.rig, b.clips, {.wrist_query = {.position_weight = 0.6f}, .pose_query = {.ankle_position_scale = 1.0f}});
  ASSERT_TRUE(db.ok()) << db.status();
  EXPECT_EQ((*db)->wrist_feature_options().position_weight, 0.6f);
  EXPECT_EQ((*db)->wrist_ankle_weights().position_weight, 0.8f);
  EXPECT_EQ((*db)->wrist_ankle_weights().ankle_position_scale, 1.0f);
}

TEST(ReconstructionDatabaseTest, NearestFramesAndALocalModelThatFitsThem) {
  const Built b = MakeClips({});
  auto db = ReconstructionDatabase::Build(b.rig, b.clips);
  ASSERT_TRUE(db.ok());
  float query[kWristAnkleFeatureDims];
  WristAnkleFeature(b.clips[0].features[40], WristAnkleWeights{}, query);  // row 40
  auto neighbours = (*db)->NearestByWristsAndAnkles(query, 40);
  ASSERT_TRUE(neighbours.ok());
  ASSERT_EQ(neighbours->size(), 40u);
  EXPECT_NEAR(neighbours->front().distance, 0.0f, 1e-9f);
  Eigen::MatrixXf examples(neighbours->size(), (*db)->pose_feature_size());
  for (size_t i = 0; i < neighbours->size(); ++i) examples.row(i) = (*db)->pose_feature((*neighbours)[i].row);
  auto model = FitLocalPoseModel(examples, 6);
  ASSERT_TRUE(model.ok());
  const Eigen::VectorXf pose = (*db)->pose_feature(40).transpose();
  // The query's own pose lies close to the 6-D local model of its neighbours (A5).
  EXPECT_LT((model->Reconstruct(model->Project(pose)) - pose).norm(), 0.05f * pose.norm() + 1e-3f);
}

TEST(ReconstructionDatabaseTest, ReversedRowsPlayEveryClipBackwards) {
  const Built b = MakeClips({});
  auto db = ReconstructionDatabase::Build(b.rig, b.clips);
  ASSERT_TRUE(db.ok()) << db.status();
  const int captured = 90 + 61;
  ASSERT_EQ((*db)->num_rows(), 2 * captured);
  // Clip 0 backwards first: its last frame is the first reversed row; clip 1's last follows clip 0's first.
  const int row = captured + (89 - 10);  // clip 0, frame 10
  EXPECT_TRUE((*db)->is_reversed(row));
  EXPECT_FALSE((*db)->is_reversed(10));
  EXPECT_EQ((*db)->clip_of(row), 0);
  EXPECT_EQ((*db)->frame_in_clip(row), 10);
  EXPECT_EQ((*db)->clip_of(captured + 90), 1);
  EXPECT_EQ((*db)->frame_in_clip(captured + 90), 60);
  EXPECT_EQ((*db)->pose_feature(row), (*db)->pose_feature(10));
  const DatabaseFrame& forward = (*db)->frames()[10];
  const DatabaseFrame& backward = (*db)->frames()[row];
  const std::vector<FrameFeatures> played = PlayedBackwards(b.clips[0].features);
  for (int side = 0; side < 2; ++side) {
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_EQ(backward.ankle_position[side][axis], forward.ankle_position[side][axis]);
      // Velocities as the reversed motion measures them (FrameFeaturesTest checks PlayedBackwards).
      EXPECT_EQ(backward.ankle_velocity[side][axis], played[89 - 10].ankle_velocity[side][axis]);
      EXPECT_LT(backward.ankle_velocity[side][axis] * forward.ankle_velocity[side][axis], 1e-6f);  // opposed
    }
  }
  for (int axis = 0; axis < 3; ++axis) EXPECT_EQ(backward.pelvis_position[axis], forward.pelvis_position[axis]);
  // A body walking backwards (the walk's velocities negated) finds the reversed rows, exactly.
  float query[kWristAnkleFeatureDims];
  WristAnkleFeature(played[89 - 10], WristAnkleWeights{}, query);
  auto by_ankles = (*db)->NearestByWristsAndAnkles(query, 1);
  ASSERT_TRUE(by_ankles.ok());
  // That row, or one of another period of the synthetic walk exactly like it.
  EXPECT_TRUE((*db)->is_reversed(by_ankles->front().row));
  EXPECT_NEAR(by_ankles->front().distance, 0.0f, 1e-9f) << "row " << by_ankles->front().row << ", not " << row;
  float wrist_query[kWristFeatureDims];
  WristFeature(played[89 - 10], {}, wrist_query);
  auto by_wrists = (*db)->wrist_index().Search(wrist_query, 1);
  ASSERT_TRUE(by_wrists.ok());
  EXPECT_TRUE((*db)->is_reversed(by_wrists->front().row));
  EXPECT_NEAR(by_wrists->front().distance, 0.0f, 1e-9f);
  // Without the copies: only the captured frames.
  auto plain = ReconstructionDatabase::Build(b.rig, b.clips, {.time_reversed_copies = false});
  ASSERT_TRUE(plain.ok());
  EXPECT_EQ((*plain)->num_rows(), captured);
  EXPECT_EQ((*plain)->num_frames(), captured);
  EXPECT_EQ((*plain)->motion_limits().pelvis_speed_max, (*db)->motion_limits().pelvis_speed_max);
}

TEST(ReconstructionDatabaseTest, OnlyTravellingFramesArePlayedBackwards) {
  // The walk, and the same walk on the spot (the Hips' ground position pinned): only the frames
  // that travel get reversed copies.
  Built b = MakeClips({});
  BvhClip on_the_spot = testing::MakeWalkingClip({}, 61);
  for (int column : {0, 2}) on_the_spot.channels.col(column).setConstant(on_the_spot.channels(0, column));
  auto prepared = PrepareClip(on_the_spot, b.rig, {});
  ASSERT_TRUE(prepared.ok()) << prepared.status();
  b.clips[1] = {prepared->features, EncodePoses(prepared->motion, b.rig)};
  auto db = ReconstructionDatabase::Build(b.rig, b.clips);
  ASSERT_TRUE(db.ok()) << db.status();
  EXPECT_EQ((*db)->num_frames(), 90 + 61);
  EXPECT_EQ((*db)->num_rows(), 90 + 61 + 90);
  for (int row = (*db)->num_frames(); row < (*db)->num_rows(); ++row) EXPECT_EQ((*db)->clip_of(row), 0);
  // A threshold above the walk's speed copies nothing.
  auto none = ReconstructionDatabase::Build(b.rig, b.clips, {.reversed_min_ground_speed = 100.0f});
  ASSERT_TRUE(none.ok());
  EXPECT_EQ((*none)->num_rows(), 90 + 61);
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
