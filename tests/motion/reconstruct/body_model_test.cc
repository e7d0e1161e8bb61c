#include "motion/reconstruct/body_model.h"

#include <gtest/gtest.h>

#include "tests/support/synthetic_database.h"

namespace mocap {
namespace {

TEST(BodyModelTest, ControlPointsMatchTheFullPoseAndThePelvisLandsOnZ) {
  for (bool extra_root : {false, true}) {
    const auto setup = testing::MakeSyntheticReconstructionSetup({.extra_root = extra_root}, 40);
    const ReconstructionDatabase& db = *setup.database;
    const BodyModel& body = db.body();
    for (int row : {0, 17, 100}) {
      const Eigen::VectorXf m = db.pose_feature(row).transpose();
      const Eigen::Quaternionf z_r(Eigen::AngleAxisf(0.7f, Eigen::Vector3f(0.2f, 1.0f, 0.1f).normalized()));
      const Eigen::Vector3f z_p(0.3f, 0.9f, -1.2f);
      const BodyPose pose = body.Pose(z_r, z_p, m.data() + 2);
      std::vector<Eigen::Quaternionf> rotations;
      std::vector<Eigen::Vector3f> positions;
      body.WorldTransforms(pose, &rotations, &positions);
      const BodyLandmarks& l = setup.rig.topology.landmarks;
      EXPECT_LT((positions[l.pelvis] - z_p).norm(), 1e-5f);
      EXPECT_LT(rotations[l.pelvis].angularDistance(z_r), 1e-4f);
      std::array<Eigen::Vector3d, kNumControlPoints> points;
      body.ControlPoints(z_r.cast<double>(), z_p.cast<double>(), m.tail(m.size() - 2), &points);
      const int joints[4] = {l.left_wrist, l.right_wrist, l.left_ankle, l.right_ankle};
      for (int c = 0; c < 4; ++c) EXPECT_LT((points[c].cast<float>() - positions[joints[c]]).norm(), 1e-5f);
    }
  }
}

TEST(BodyModelTest, ADatabaseFrameRebuiltFromItsFeaturesMatchesItsCapture) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 40);
  const ReconstructionDatabase& db = *setup.database;
  // The test clip is a walk like the database's: rebuild its frame 10 from its own pose feature
  // and pelvis, and compare the wrists with the capture.
  const LocalMotion& motion = setup.test_clip.motion;
  const std::vector<float> encoded = EncodePoses(motion, setup.rig);
  const int stride = EncodedPoseFloats(setup.rig.skeleton.num_joints());
  std::vector<float> q;
  for (int j : db.pose_joints()) {
    for (int axis = 0; axis < 3; ++axis) q.push_back(encoded[10 * stride + 3 + 3 * j + axis]);
  }
  const BodyLandmarks& l = setup.rig.topology.landmarks;
  const BodyPose pose =
      db.body().Pose(setup.truth.rotation(10, l.pelvis), setup.truth.position(10, l.pelvis), q.data());
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> positions;
  db.body().WorldTransforms(pose, &rotations, &positions);
  EXPECT_LT((positions[l.left_wrist] - setup.truth.position(10, l.left_wrist)).norm(), 1e-4f);
  EXPECT_LT((positions[l.right_ankle] - setup.truth.position(10, l.right_ankle)).norm(), 1e-4f);
}

TEST(BodyModelTest, RestPoseHeightAndStatureAreTheStandingHeightOnEveryRigVariant) {
  // The synthetic performer stands about 1.7 m tall (floor to the head's end site), whatever the
  // rig's root, up axis, extra joints or unit; told from the legs (EstimatedStature, what the
  // performer would declare as performer_height) it is the same.
  for (int bits : {0, 1, 2, 3, 4, 8, 16, 31}) {
    for (double unit : {1.0, 0.01, 1.0 / 2.54}) {
      testing::SyntheticRigOptions options = testing::SyntheticRigFromBits(bits);
      options.length_scale = unit;
      const auto setup = testing::MakeSyntheticReconstructionSetup(options, 10);
      EXPECT_NEAR(RestPoseHeight(setup.database->body()), 1.7f, 0.15f) << "rig bits " << bits << ", unit " << unit;
      EXPECT_NEAR(EstimatedStature(setup.database->body()), 1.7f, 0.15f) << "rig bits " << bits << ", unit " << unit;
    }
  }
}

}  // namespace
}  // namespace mocap
