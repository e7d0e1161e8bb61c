#include "motion/reconstruct/body_floor.h"

#include <algorithm>

#include <gtest/gtest.h>

#include "motion/reconstruct/reconstruction_session.h"
#include "tests/support/synthetic_database.h"

namespace mocap {
namespace {

bool Contains(const std::vector<int>& joints, int joint) {
  return std::find(joints.begin(), joints.end(), joint) != joints.end();
}

// Past the ankles and wrists (feet, hands) and above the pelvis nothing bears the body; the trunk,
// head and limbs down to the wrists and knees do.
TEST(FloorBearingJointsTest, AreTheTrunkAndLimbsButNotTheFeetHandsOrRootChain) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 10);
  const Skeleton& skeleton = setup.database->body().skeleton();
  const BodyLandmarks& l = setup.rig.topology.landmarks;
  const std::vector<int> joints = FloorBearingJoints(skeleton, l);
  for (int j : {l.pelvis, l.head, l.left_wrist, l.right_wrist, l.left_knee, l.right_knee, l.left_elbow,
                l.right_elbow}) {
    if (j >= 0) {
      EXPECT_TRUE(Contains(joints, j)) << skeleton.joint(j).name;
    }
  }
  EXPECT_FALSE(Contains(joints, l.left_ankle));
  EXPECT_FALSE(Contains(joints, l.right_ankle));
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    for (int up = skeleton.parent(j); up >= 0; up = skeleton.parent(up)) {
      if (up == l.left_ankle || up == l.right_ankle || up == l.left_wrist || up == l.right_wrist) {
        EXPECT_FALSE(Contains(joints, j)) << skeleton.joint(j).name << " is past a foot or hand";
      }
    }
  }
  for (int up = skeleton.parent(l.pelvis); up >= 0; up = skeleton.parent(up)) EXPECT_FALSE(Contains(joints, up));
}

TEST(FloorLiftTest, IsTheDeepestBearingJointsDepth) {
  const std::vector<Eigen::Vector3f> positions = {
      {0, 0.9f, 0}, {0, -0.17f, 0.3f}, {0, -0.4f, 0}, {0, 0.02f, 0}};
  const std::vector<int> bearing = {0, 1, 3};  // joint 2 (a toe, say) is not
  EXPECT_FLOAT_EQ(FloorLift(positions, bearing), 0.17f);
  EXPECT_EQ(FloorLift(positions, std::vector<int>{0, 3}), 0.0f);
  EXPECT_EQ(FloorLift(positions, std::vector<int>{}), 0.0f);
}

// The walk's hands brought 1.2 m down, to the floor: the solve folds the body to reach them and,
// without the rule, a knee ends 19 cm under the ground. With it no joint that bears the body does
// (the feet's leg IK runs first: the knee it bends down bears the body too).
TEST(BodyAboveFloorTest, HandsBroughtToTheFloorLeaveNoTrunkUnderIt) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 60);
  ReconstructionOptions options;
  options.ankle_candidates = 60;
  options.pose_neighbours = 40;
  auto samples = testing::WristSamplesOf(setup);
  for (size_t i = 10; i < samples.size(); ++i) {
    const float drop = 1.2f * std::min(1.0f, static_cast<float>(i - 10) / 15.0f);
    samples[i].left.y() -= drop;
    samples[i].right.y() -= drop;
  }
  const BodyModel& body = setup.database->body();
  const std::vector<int> bearing = FloorBearingJoints(body.skeleton(), setup.rig.topology.landmarks);
  auto lowest = [&](const ReconstructionOptions& o) {
    auto frames = ReconstructOffline(setup.database, o, samples);
    EXPECT_TRUE(frames.ok()) << frames.status();
    float low = 1e9f;
    std::vector<Eigen::Quaternionf> rotations;
    std::vector<Eigen::Vector3f> positions;
    for (const ReconstructedFrame& frame : frames.ok() ? *frames : std::vector<ReconstructedFrame>{}) {
      body.WorldTransforms(frame.pose, &rotations, &positions);
      for (int j : bearing) low = std::min(low, positions[j].y());
    }
    return low;
  };
  ReconstructionOptions sinking = options;
  sinking.body_above_floor = false;
  const float without = lowest(sinking);
  const float with = lowest(options);
  EXPECT_LT(without, -0.05f);  // the case does put the body under the floor without the rule
  EXPECT_GE(with, -1e-4f);
}

}  // namespace
}  // namespace mocap
