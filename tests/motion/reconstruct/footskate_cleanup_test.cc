#include "motion/reconstruct/footskate_cleanup.h"

#include <gtest/gtest.h>

#include "tests/support/synthetic_database.h"

namespace mocap {
namespace {

BodyPose PoseOfRow(const ReconstructionDatabase& db, int row) {
  const Eigen::VectorXf m = db.pose_feature(row).transpose();
  return db.body().Pose(Eigen::Quaternionf::Identity(), Eigen::Vector3f(0, 0.9f, 0), m.data() + 2);
}

TEST(FootskateCleanupTest, LegIkReachesTheTargetAndKeepsTheFootOrientation) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 40);
  const ReconstructionDatabase& db = *setup.database;
  const int ankle = setup.rig.topology.landmarks.left_ankle;
  std::vector<Eigen::Quaternionf> r0, r1;
  std::vector<Eigen::Vector3f> p0, p1;
  for (const Eigen::Vector3f& move : {Eigen::Vector3f(0.05f, 0.0f, 0.0f), Eigen::Vector3f(0.0f, 0.08f, -0.04f)}) {
    BodyPose pose = PoseOfRow(db, 20);
    db.body().WorldTransforms(pose, &r0, &p0);
    const Eigen::Vector3f target = p0[ankle] + move;
    SolveLegIk(db.body(), ankle, target, &pose);
    db.body().WorldTransforms(pose, &r1, &p1);
    EXPECT_LT((p1[ankle] - target).norm(), 1e-4f);
    EXPECT_LT(r1[ankle].angularDistance(r0[ankle]), 1e-3f);
    const int knee = db.body().skeleton().parent(ankle);
    EXPECT_NEAR((p1[knee] - p1[ankle]).norm(), (p0[knee] - p0[ankle]).norm(), 1e-5f);  // bones keep their lengths
    EXPECT_LT((p1[setup.rig.topology.landmarks.right_ankle] - p0[setup.rig.topology.landmarks.right_ankle]).norm(),
              1e-6f);
  }
}

TEST(FootskateCleanupTest, APlantedFootStaysWhereItLandedAndIsReleasedSmoothly) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 40);
  const ReconstructionDatabase& db = *setup.database;
  FootskateCleaner cleaner(db.body(), db.planted_ankle_height(), db.frame_time(), {});
  const int ankle = setup.rig.topology.landmarks.left_ankle;
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> positions;
  // The estimated left ankle rests on the ground while the solved pose drifts forward 1 cm/frame:
  // the cleanup holds the foot at its first planted position.
  std::optional<Eigen::Vector3f> pinned;
  for (int f = 0; f < 10; ++f) {
    BodyPose pose = PoseOfRow(db, 20);
    pose.root_position.z() += 0.01f * f;
    const std::array<Eigen::Vector3f, 2> estimate = {Eigen::Vector3f(0.1f, db.planted_ankle_height(), 0.0f),
                                                     Eigen::Vector3f(-0.1f, 0.5f, 0.0f)};
    const auto contact = cleaner.Process(estimate, nullptr, &pose);
    db.body().WorldTransforms(pose, &rotations, &positions);
    if (f == 0) continue;  // no speed yet
    EXPECT_TRUE(contact[0]);
    EXPECT_FALSE(contact[1]);  // high above the ground
    if (!pinned) pinned = positions[ankle];
    EXPECT_LT((positions[ankle] - *pinned).norm(), 1e-4f) << f;
  }
  // The estimate lifts off: the correction fades over the release frames, without a jump.
  float previous_offset = 1e9f;
  for (int f = 10; f < 16; ++f) {
    BodyPose pose = PoseOfRow(db, 20);
    pose.root_position.z() += 0.01f * f;
    BodyPose free = pose;
    const auto contact =
        cleaner.Process({Eigen::Vector3f(0.1f, 0.4f, 0.0f), Eigen::Vector3f(-0.1f, 0.5f, 0.0f)}, nullptr, &pose);
    EXPECT_FALSE(contact[0]);
    db.body().WorldTransforms(pose, &rotations, &positions);
    std::vector<Eigen::Quaternionf> free_rotations;
    std::vector<Eigen::Vector3f> free_positions;
    db.body().WorldTransforms(free, &free_rotations, &free_positions);
    const float offset = (positions[ankle] - free_positions[ankle]).norm();
    EXPECT_TRUE(offset < previous_offset || offset < 1e-6f) << offset << " after " << previous_offset;
    previous_offset = offset;
  }
  EXPECT_LT(previous_offset, 1e-5f);
}

TEST(FootskateCleanupTest, ContactsCanComeFromTheChosenDatabaseFrame) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 40);
  const ReconstructionDatabase& db = *setup.database;
  const FootskateOptions options;
  // A captured frame whose left foot rests on the ground and whose right foot swings.
  DatabaseFrame frame{};
  frame.ankle_position[0][1] = db.planted_ankle_height();
  frame.ankle_velocity[0][0] = 0.05f;
  frame.ankle_position[1][1] = db.planted_ankle_height() + 0.01f;
  frame.ankle_velocity[1][2] = 1.2f;
  EXPECT_EQ(PlantedFeet(frame, db.planted_ankle_height(), options), (std::array<bool, 2>{true, false}));
  frame.ankle_position[0][1] = db.planted_ankle_height() + options.contact_height + 0.01f;  // lifted
  EXPECT_FALSE(PlantedFeet(frame, db.planted_ankle_height(), options)[0]);
  frame.ankle_position[0][1] = db.planted_ankle_height();

  // The estimate races along (no contact by its own speed), but the database frame says planted:
  // the database source pins the foot, the estimate source does not.
  for (ContactSource source : {ContactSource::kDatabaseFrame, ContactSource::kEstimatedAnkles}) {
    FootskateCleaner cleaner(db.body(), db.planted_ankle_height(), db.frame_time(), {.contact_source = source});
    std::array<bool, 2> contact{};
    for (int f = 0; f < 3; ++f) {
      BodyPose pose = PoseOfRow(db, 20);
      const std::array<Eigen::Vector3f, 2> estimate = {Eigen::Vector3f(0.1f, db.planted_ankle_height(), 0.1f * f),
                                                       Eigen::Vector3f(-0.1f, 0.5f, 0.0f)};
      contact = cleaner.Process(estimate, &frame, &pose);
    }
    EXPECT_EQ(contact[0], source == ContactSource::kDatabaseFrame);
    EXPECT_FALSE(contact[1]);
  }
}

}  // namespace
}  // namespace mocap
