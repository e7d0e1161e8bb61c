#include "motion/reconstruct/unfamiliar_prior.h"

#include <gtest/gtest.h>

#include "motion/reconstruct/local_pose_model.h"
#include "motion/reconstruct/reconstruction_session.h"
#include "tests/support/synthetic_database.h"

namespace mocap {
namespace {

TEST(UnfamiliarPriorFactorTest, RisesLinearlyBetweenItsTwoEnergiesAndNotBeforeAFrame) {
  const UnfamiliarPriorOptions options{.from_log_cost = 3.0f, .to_log_cost = 4.0f, .max_factor = 5.0f};
  EXPECT_EQ(UnfamiliarPriorFactor(options, 10.0f, 0), 1.0f);  // no frame yet: nothing known
  EXPECT_EQ(UnfamiliarPriorFactor(options, 2.0f, 30), 1.0f);
  EXPECT_EQ(UnfamiliarPriorFactor(options, 3.0f, 30), 1.0f);
  EXPECT_FLOAT_EQ(UnfamiliarPriorFactor(options, 3.25f, 30), 2.0f);
  EXPECT_FLOAT_EQ(UnfamiliarPriorFactor(options, 3.5f, 30), 3.0f);
  EXPECT_EQ(UnfamiliarPriorFactor(options, 4.0f, 30), 5.0f);
  EXPECT_EQ(UnfamiliarPriorFactor(options, 40.0f, 30), 5.0f);
  EXPECT_EQ(UnfamiliarPriorFactor({.max_factor = 1.0f}, 40.0f, 30), 1.0f);  // off
  EXPECT_EQ(UnfamiliarPriorFactor({.from_log_cost = 3.0f, .to_log_cost = 3.0f, .max_factor = 5.0f}, 3.5f, 30), 5.0f);
}

class UnfamiliarPriorSolveTest : public ::testing::Test {
 protected:
  void SetUp() override { setup_ = testing::MakeSyntheticReconstructionSetup({}, 40); }
  testing::SyntheticReconstructionSetup setup_;
};

// The solve reports its unweighted E_prior, and the cost at the configured weight it derives from
// a heavier prior's solution is never below the configured weight's own optimum (which minimises
// exactly that energy), while the heavier prior keeps the pose nearer the model's mean.
TEST_F(UnfamiliarPriorSolveTest, AHeavierPriorsCostIsReadAtTheConfiguredWeight) {
  const ReconstructionDatabase& db = *setup_.database;
  const BodyLandmarks& l = setup_.rig.topology.landmarks;
  for (int f : {6, 19, 33}) {
    const LocalPoseModel model = testing::LocalModelAtTestFrame(setup_, f);
    // Targets a body unlike the database's would set: the wrists 12 cm further apart.
    const Eigen::Vector3f apart(0.06f, 0.0f, 0.0f);
    const ControlTargets targets = {setup_.truth.position(f, l.left_wrist) + apart,
                                    setup_.truth.position(f, l.right_wrist) - apart,
                                    setup_.truth.position(f, l.left_ankle), setup_.truth.position(f, l.right_ankle)};
    SolvedPose initial;
    initial.pose_feature = model.mean;
    initial.pelvis_rotation = setup_.truth.rotation(f, l.pelvis);
    initial.pelvis_position = setup_.truth.position(f, l.pelvis);
    const PoseSolverOptions configured;
    PoseSolverOptions heavier = configured;
    heavier.prior_weight *= 4.0f;
    auto plain = SolvePose(db.body(), model, targets, initial, nullptr, nullptr, configured);
    auto leaning = SolvePose(db.body(), model, targets, initial, nullptr, nullptr, heavier);
    ASSERT_TRUE(plain.ok() && leaning.ok());
    EXPECT_NEAR(plain->prior_cost, model.PriorEnergy(model.Project(plain->pose_feature), configured.min_variance),
                1e-3f + 1e-3f * plain->prior_cost);
    EXPECT_GT(plain->prior_cost, 0.0f);
    EXPECT_LT(leaning->prior_cost, plain->prior_cost) << "frame " << f;
    const float read = CostAtConfiguredPrior(*leaning, configured.prior_weight, 4.0f);
    EXPECT_LT(read, leaning->cost);
    EXPECT_GE(read, plain->cost * 0.999f) << "frame " << f;
  }
}

TEST(CostAtConfiguredPriorTest, TakesTheExtraPriorOutAndNeverGoesNegative) {
  SolvedPose solved;
  solved.cost = 10.0f;
  solved.prior_cost = 2.0f;
  EXPECT_FLOAT_EQ(CostAtConfiguredPrior(solved, 1.0f, 1.0f), 10.0f);
  EXPECT_FLOAT_EQ(CostAtConfiguredPrior(solved, 1.0f, 4.0f), 4.0f);
  EXPECT_FLOAT_EQ(CostAtConfiguredPrior(solved, 0.5f, 4.0f), 7.0f);
  solved.prior_cost = 20.0f;
  EXPECT_EQ(CostAtConfiguredPrior(solved, 1.0f, 4.0f), 0.0f);
}

// A session tells its factor per frame: none on the database's own motion; on input a body like
// the database's cannot meet (the hands held 40 cm further apart than the capture's) the solve
// keeps paying, and past the rule's energy the prior weighs more.
TEST(UnfamiliarPriorSessionTest, OnlyASessionUnlikeTheDatabaseLeansOnThePrior) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 75);
  ReconstructionOptions options;
  options.ankle_candidates = 60;
  options.pose_neighbours = 40;
  auto own = ReconstructOffline(setup.database, options, testing::WristSamplesOf(setup));
  ASSERT_TRUE(own.ok()) << own.status();
  float own_highest = 0;
  for (const ReconstructedFrame& frame : *own) {
    EXPECT_EQ(frame.diagnostics.prior_weight_factor, 1.0f) << "frame " << frame.index;
    own_highest = std::max(own_highest, frame.diagnostics.session_log_cost);
  }
  std::vector<WristSample> apart = testing::WristSamplesOf(setup);
  for (WristSample& s : apart) {
    s.left.x() += 0.2f;
    s.right.x() -= 0.2f;
  }
  auto unlike = ReconstructOffline(setup.database, options, apart);
  ASSERT_TRUE(unlike.ok()) << unlike.status();
  EXPECT_GT(unlike->back().diagnostics.session_log_cost, own_highest + 1.0f);
  // Its rule set where this session's energy lies, the factor rises after the first frame.
  options.unfamiliar_prior = {.from_log_cost = own_highest, .to_log_cost = own_highest + 1.0f, .max_factor = 4.0f};
  auto leaning = ReconstructOffline(setup.database, options, apart);
  ASSERT_TRUE(leaning.ok()) << leaning.status();
  EXPECT_EQ(leaning->front().diagnostics.prior_weight_factor, 1.0f);
  EXPECT_GT(leaning->back().diagnostics.prior_weight_factor, 1.0f);
  EXPECT_LE(leaning->back().diagnostics.prior_weight_factor, 4.0f);
}

}  // namespace
}  // namespace mocap
