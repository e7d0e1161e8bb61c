#include "motion/reconstruct/grip_offset.h"

#include <vector>

#include <gtest/gtest.h>

#include "motion/reconstruct/reconstruction_session.h"
#include "tests/support/synthetic_database.h"

namespace mocap {
namespace {

constexpr float kGrip = 0.09f;  // a phone in a closed grip

class GripOffsetTest : public ::testing::Test {
 protected:
  void SetUp() override {
    setup_ = testing::MakeSyntheticReconstructionSetup({}, 75);
    options_.ankle_candidates = 60;  // the synthetic database is small
    options_.pose_neighbours = 40;
  }

  Eigen::Vector3f Truth(int frame, int joint) const { return setup_.truth.position(frame, joint); }
  Eigen::Vector3f Forearm(int frame, int side) const {
    const BodyLandmarks& l = setup_.rig.topology.landmarks;
    const int elbow = side == 0 ? l.left_elbow : l.right_elbow, wrist = side == 0 ? l.left_wrist : l.right_wrist;
    return (Truth(frame, wrist) - Truth(frame, elbow)).normalized();
  }
  // The test walk's samples as devices held `grip` beyond the wrists would send them.
  std::vector<WristSample> DeviceSamples(float grip) const {
    std::vector<WristSample> samples = testing::WristSamplesOf(setup_);
    for (size_t f = 0; f < samples.size(); ++f) {
      samples[f].left += grip * Forearm(static_cast<int>(f), 0);
      samples[f].right += grip * Forearm(static_cast<int>(f), 1);
    }
    return samples;
  }
  // Mean distance of the output's wrist joints from the capture's, metres.
  double WristError(const std::vector<ReconstructedFrame>& frames) const {
    const BodyLandmarks& l = setup_.rig.topology.landmarks;
    std::vector<Eigen::Quaternionf> rotations;
    std::vector<Eigen::Vector3f> positions;
    double sum = 0;
    for (const ReconstructedFrame& frame : frames) {
      setup_.database->body().WorldTransforms(frame.pose, &rotations, &positions);
      for (int wrist : {l.left_wrist, l.right_wrist}) {
        sum += (positions[wrist] - Truth(frame.frame_in_segment, wrist)).norm();
      }
    }
    return sum / (2.0 * frames.size());
  }

  testing::SyntheticReconstructionSetup setup_;
  ReconstructionOptions options_;
};

TEST_F(GripOffsetTest, AForearmIsAsLongAsAPersons) {
  const float forearm = ForearmLength(setup_.database->body());
  EXPECT_GT(forearm, 0.1f * EstimatedStature(setup_.database->body()));
  EXPECT_LT(forearm, 0.25f * EstimatedStature(setup_.database->body()));
}

TEST_F(GripOffsetTest, ARowsForearmsAreUnitVectorsAlongItsArms) {
  const ReconstructionDatabase& db = *setup_.database;
  for (int row = 0; row < db.num_rows(); row += 17) {
    const std::array<Eigen::Vector3f, 2> forearms = RowForearms(db, row);
    for (const Eigen::Vector3f& forearm : forearms) EXPECT_NEAR(forearm.norm(), 1.0f, 1e-4f) << "row " << row;
    // A walk's arms hang: the forearms point down more than up.
    EXPECT_LT(forearms[0].y() + forearms[1].y(), 0.0f) << "row " << row;
  }
}

TEST_F(GripOffsetTest, DevicesHeldBeyondTheWristsAreTakenBackAlongTheForearms) {
  const std::vector<WristSample> samples = DeviceSamples(kGrip);
  for (const bool fixed_lag : {false, true}) {
    options_.mode = fixed_lag ? StreamMode::kFixedLag : StreamMode::kSubInterval;
    options_.lag = 5;
    auto as_wrists = ReconstructOffline(setup_.database, options_, samples);
    ASSERT_TRUE(as_wrists.ok()) << as_wrists.status();
    ReconstructionOptions declared = options_;
    declared.grip_offset = kGrip;
    auto gripped = ReconstructOffline(setup_.database, declared, samples);
    ASSERT_TRUE(gripped.ok()) << gripped.status();
    ASSERT_EQ(gripped->size(), as_wrists->size());
    // Read as wrists, the devices pull the wrist joints most of the grip away; declared, the
    // wrists come back to the capture's.
    const double undeclared_error = WristError(*as_wrists), declared_error = WristError(*gripped);
    EXPECT_GT(undeclared_error, 0.6 * kGrip) << (fixed_lag ? "lag 5" : "whole clip");
    EXPECT_LT(declared_error, 0.5 * undeclared_error) << (fixed_lag ? "lag 5" : "whole clip");
    // The body holds each device where it was tracked: the wrist a grip short of it, towards the elbow.
    const BodyLandmarks& l = setup_.rig.topology.landmarks;
    std::vector<Eigen::Quaternionf> rotations;
    std::vector<Eigen::Vector3f> positions;
    for (const ReconstructedFrame& frame : *gripped) {
      setup_.database->body().WorldTransforms(frame.pose, &rotations, &positions);
      const WristSample& sample = samples[frame.frame_in_segment];
      const Eigen::Vector3f left =
          positions[l.left_wrist] + kGrip * (positions[l.left_wrist] - positions[l.left_elbow]).normalized();
      EXPECT_LT((left - sample.left).norm(), 0.03f) << "frame " << frame.frame_in_segment;
      EXPECT_EQ(frame.hand_state[0], TrackingState::kTracked) << "frame " << frame.frame_in_segment;
    }
  }
}

TEST_F(GripOffsetTest, NoGripLeavesTheSessionAsItWas) {
  const std::vector<WristSample> samples = testing::WristSamplesOf(setup_);
  auto plain = ReconstructOffline(setup_.database, options_, samples);
  ReconstructionOptions zero = options_;
  zero.grip_offset = 0.0f;
  auto again = ReconstructOffline(setup_.database, zero, samples);
  ASSERT_TRUE(plain.ok() && again.ok());
  for (size_t f = 0; f < plain->size(); ++f) EXPECT_EQ((*plain)[f].pelvis_position, (*again)[f].pelvis_position);
}

TEST_F(GripOffsetTest, AGripNoHandHoldsIsRefused) {
  for (const float grip : {-0.05f, 0.31f, std::numeric_limits<float>::quiet_NaN()}) {
    ReconstructionOptions options = options_;
    options.grip_offset = grip;
    auto session = ReconstructionSession::Create(setup_.database, options);
    ASSERT_FALSE(session.ok()) << grip;
    EXPECT_EQ(session.status().code(), absl::StatusCode::kInvalidArgument);
    EXPECT_NE(session.status().message().find("grip offset"), std::string::npos) << session.status();
  }
}

}  // namespace
}  // namespace mocap
