#include "motion/reconstruct/footskate_cleanup.h"

#include <cmath>
#include <string>

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

TEST(FootskateCleanupTest, AContactSeenWholeIsPinnedAtTheMeanOfItsEstimateAndApproachedSmoothly) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 40);
  const ReconstructionDatabase& db = *setup.database;
  const int ankle = setup.rig.topology.landmarks.left_ankle;
  const float ground = db.planted_ankle_height();
  const FootskateOptions options;
  const float slow = 0.3f * options.contact_speed * static_cast<float>(db.frame_time());
  const float wander[8] = {-slow, 0, slow, 0.5f * slow, 0, -slow, 0, slow};
  const Eigen::Vector3f right(-0.1f, 0.5f, 0);  // the right estimate stays in the air
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> positions;
  const BodyPose free = PoseOfRow(db, 20);  // the solve puts the ankle at the same place every frame
  db.body().WorldTransforms(free, &rotations, &positions);
  const Eigen::Vector3f solved = positions[ankle];
  const int long_contact = static_cast<int>(std::ceil(options.mean_pin_min_seconds / db.frame_time())) + 2;

  for (const int frames : {long_contact, 6}) {
    // The left estimate swings in high for 6 frames, lands at frame 6 and wanders about z = 0.03
    // for `frames` frames, slowly enough to count as planted, then lifts.
    std::vector<AnklePair> estimates;
    for (int f = 0; f < 6; ++f)
      estimates.push_back({Eigen::Vector3f(0.1f, 0.3f, 0.03f - slow - 0.05f * (5 - f)), right});
    float sum = 0;
    for (int f = 0; f < frames; ++f) {
      estimates.push_back({Eigen::Vector3f(0.1f, ground, 0.03f + wander[f % 8]), right});
      sum += wander[f % 8];
    }
    for (int f = 0; f < 4; ++f) estimates.push_back({Eigen::Vector3f(0.1f, 0.3f, 0.1f * f), right});
    const float mean_offset = sum / static_cast<float>(frames) - wander[0];  // from the landing estimate, along z
    ASSERT_GT(std::abs(mean_offset), 0.1f * slow);

    for (const bool whole : {true, false}) {
      FootskateCleaner cleaner(db.body(), ground, db.frame_time(), options);
      std::vector<float> offsets;  // the foot's z offset from the solve, per frame
      for (size_t f = 0; f < estimates.size(); ++f) {
        BodyPose pose = free;
        // Streaming sees two frames ahead, and the segment goes on; offline sees all of it.
        const std::span<const AnklePair> rest = std::span<const AnklePair>(estimates).subspan(f + 1);
        const AnkleLookahead ahead{.decided = whole ? rest : rest.first(std::min<size_t>(2, rest.size())),
                                   .complete = whole};
        const auto contact = cleaner.Process(estimates[f], nullptr, &pose, nullptr, ahead);
        EXPECT_EQ(contact[0], f >= 6 && f < 6 + static_cast<size_t>(frames)) << f;
        db.body().WorldTransforms(pose, &rotations, &positions);
        offsets.push_back(positions[ankle].z() - solved.z());
      }
      // Pinned at the mean when the whole contact is seen and it is long enough, else where it began.
      const bool at_mean = whole && frames == long_contact;
      const std::string what = (whole ? "offline, " : "streaming, ") + std::to_string(frames) + " frames";
      for (int f = 6; f < 6 + frames; ++f)
        EXPECT_NEAR(offsets[f], at_mean ? mean_offset : 0.0f, 1e-4f) << f << " " << what;
      if (at_mean) {
        // The pin's offset eases in over the release frames before the landing, growing each frame.
        EXPECT_NEAR(offsets[1], 0.0f, 1e-6f);
        for (int f = 2; f < 6; ++f) {
          EXPECT_GT(std::abs(offsets[f]), std::abs(offsets[f - 1])) << f;
          EXPECT_LT(std::abs(offsets[f]), std::abs(mean_offset)) << f;
        }
      } else {
        for (int f = 0; f < 6; ++f) EXPECT_NEAR(offsets[f], 0.0f, 1e-6f) << f << " " << what;
      }
    }
  }
}

}  // namespace
}  // namespace mocap
