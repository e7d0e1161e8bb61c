#include "motion/reconstruct/pose_solver.h"

#include <algorithm>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "motion/reconstruct/local_pose_model.h"
#include "tests/support/synthetic_database.h"

namespace mocap {
namespace {

class PoseSolverTest : public ::testing::Test {
 protected:
  void SetUp() override { setup_ = testing::MakeSyntheticReconstructionSetup({}, 40); }

  LocalPoseModel ModelAt(int f) { return testing::LocalModelAtTestFrame(setup_, f); }
  ControlTargets TargetsAt(int f) const {
    const BodyLandmarks& l = setup_.rig.topology.landmarks;
    return {setup_.truth.position(f, l.left_wrist), setup_.truth.position(f, l.right_wrist),
            setup_.truth.position(f, l.left_ankle), setup_.truth.position(f, l.right_ankle)};
  }
  testing::SyntheticReconstructionSetup setup_;
};

TEST_F(PoseSolverTest, ReachesTheControlPointsFromAPerturbedStart) {
  const BodyLandmarks& l = setup_.rig.topology.landmarks;
  for (int f : {5, 12, 27}) {
    const LocalPoseModel model = ModelAt(f);
    SolvedPose initial;
    initial.pose_feature = model.mean;
    initial.pelvis_rotation =
        setup_.truth.rotation(f, l.pelvis) * Eigen::Quaternionf(Eigen::AngleAxisf(0.2f, Eigen::Vector3f::UnitY()));
    initial.pelvis_position = setup_.truth.position(f, l.pelvis) + Eigen::Vector3f(0.08f, -0.05f, 0.06f);
    auto solved = SolvePose(setup_.database->body(), model, TargetsAt(f), initial, nullptr, nullptr, {});
    ASSERT_TRUE(solved.ok()) << solved.status();
    for (int c = 0; c < kNumControlPoints; ++c)
      EXPECT_LT(solved->control_error[c], 0.02f) << "frame " << f << " point " << c;
    EXPECT_LT((solved->pelvis_position - setup_.truth.position(f, l.pelvis)).norm(), 0.03f);
    EXPECT_NEAR(solved->pelvis_rotation.norm(), 1.0f, 1e-5f);
  }
}

TEST_F(PoseSolverTest, SmoothnessPullsTowardsTheHistory) {
  const int f = 12;
  const LocalPoseModel model = ModelAt(f);
  const BodyLandmarks& l = setup_.rig.topology.landmarks;
  SolvedPose history;
  history.pose_feature = model.mean;
  history.pelvis_rotation = setup_.truth.rotation(f, l.pelvis);
  history.pelvis_position = setup_.truth.position(f, l.pelvis) + Eigen::Vector3f(0.0f, 0.0f, 0.10f);
  PoseSolverOptions strong;
  strong.smooth_weight = 100.0f;
  auto free = SolvePose(setup_.database->body(), model, TargetsAt(f), history, nullptr, nullptr, {});
  auto held = SolvePose(setup_.database->body(), model, TargetsAt(f), history, &history, &history, strong);
  ASSERT_TRUE(free.ok() && held.ok());
  EXPECT_LT((held->pelvis_position - history.pelvis_position).norm(),
            (free->pelvis_position - history.pelvis_position).norm());
}

// Hands on the floor (a dancer down on it, a tracker's drift): without E_floor the body folds to
// follow them and a knee goes into the ground; with it the joints it rests on stay above it.
TEST_F(PoseSolverTest, TheFloorTermKeepsTheTrunkAboveTheGround) {
  const int f = 12;
  const LocalPoseModel model = ModelAt(f);
  const BodyLandmarks& l = setup_.rig.topology.landmarks;
  const BodyModel& body = setup_.database->body();
  ASSERT_GE(body.num_floor_joints(), 6);
  ControlTargets on_floor = TargetsAt(f);
  for (const int wrist : {kLeftWrist, kRightWrist}) on_floor[wrist].y() = 0.06f;
  SolvedPose initial;
  initial.pose_feature = model.mean;
  initial.pelvis_rotation = setup_.truth.rotation(f, l.pelvis);
  initial.pelvis_position = setup_.truth.position(f, l.pelvis);
  const auto lowest = [&](const SolvedPose& solved) {
    const BodyPose pose = body.Pose(solved.pelvis_rotation, solved.pelvis_position, solved.pose_feature.data() + 2);
    std::vector<Eigen::Quaternionf> rotations;
    std::vector<Eigen::Vector3f> positions;
    body.WorldTransforms(pose, &rotations, &positions);
    float y = std::numeric_limits<float>::infinity();
    for (const int joint : {l.pelvis, l.head, l.left_shoulder, l.right_shoulder, l.left_elbow, l.right_elbow,
                            l.left_hip, l.right_hip, l.left_knee, l.right_knee}) {
      if (joint >= 0) y = std::min(y, positions[joint].y());
    }
    return y;
  };
  PoseSolverOptions no_floor;
  no_floor.floor_weight = 0.0f;
  auto sinking = SolvePose(body, model, on_floor, initial, nullptr, nullptr, no_floor);
  auto resting = SolvePose(body, model, on_floor, initial, nullptr, nullptr, {});
  ASSERT_TRUE(sinking.ok() && resting.ok());
  EXPECT_LT(lowest(*sinking), -0.02f);
  EXPECT_GT(lowest(*resting), 0.0f);
  // Standing, the term costs nothing: the same solve as without it.
  auto standing = SolvePose(body, model, TargetsAt(f), initial, nullptr, nullptr, {});
  auto standing_free = SolvePose(body, model, TargetsAt(f), initial, nullptr, nullptr, no_floor);
  ASSERT_TRUE(standing.ok() && standing_free.ok());
  EXPECT_GT(lowest(*standing), 0.05f);
  EXPECT_NEAR(standing->cost, standing_free->cost, 1e-4f);
  EXPECT_LT((standing->pelvis_position - standing_free->pelvis_position).norm(), 1e-5f);
}

TEST_F(PoseSolverTest, RefusesNonFiniteTargetsAndMismatchedModels) {
  const LocalPoseModel model = ModelAt(5);
  SolvedPose initial;
  initial.pose_feature = model.mean;
  ControlTargets targets = TargetsAt(5);
  targets[2].x() = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(SolvePose(setup_.database->body(), model, targets, initial, nullptr, nullptr, {}).status().code(),
            absl::StatusCode::kInvalidArgument);
  LocalPoseModel small = model;
  small.mean.conservativeResize(4);
  EXPECT_EQ(SolvePose(setup_.database->body(), small, TargetsAt(5), initial, nullptr, nullptr, {}).status().code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace mocap
