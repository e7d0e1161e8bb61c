#include "motion/reconstruct/ankle_path.h"

#include <random>

#include <gtest/gtest.h>

namespace mocap {
namespace {

constexpr double kFrameSeconds = 1.0 / 30.0;

// A true candidate (left foot planted, right foot lifting and lowering: consistent positions and
// velocities, no sliding) hidden among distractors scattered around it.
std::vector<std::vector<AnkleCandidate>> CloudsAroundTruth(int frames, int distractors, unsigned seed,
                                                           std::vector<int>* truth_index) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> offset(-0.15f, 0.15f);
  std::uniform_int_distribution<int> slot(0, distractors);
  std::vector<std::vector<AnkleCandidate>> clouds(frames);
  for (int t = 0; t < frames; ++t) {
    AnkleCandidate truth;
    truth.row = -1;
    truth.position[0] = Eigen::Vector3f(0.1f, 0.08f, 0.0f);
    truth.position[1] = Eigen::Vector3f(-0.1f, 0.13f + 0.05f * std::sin(0.3f * t), 0.3f);
    truth.velocity[0] = Eigen::Vector3f::Zero();
    // Forward difference, so that position + Δt·velocity lands exactly on the next frame.
    truth.velocity[1] =
        Eigen::Vector3f(0.0f, 0.05f * (std::sin(0.3f * (t + 1)) - std::sin(0.3f * t)) / kFrameSeconds, 0.0f);
    for (int i = 0; i < distractors; ++i) {
      AnkleCandidate d = truth;
      d.row = i;
      for (int side = 0; side < 2; ++side)
        d.position[side] += Eigen::Vector3f(offset(random), offset(random) * 0.3f, offset(random));
      clouds[t].push_back(d);
    }
    const int at = slot(random);
    clouds[t].insert(clouds[t].begin() + at, truth);
    truth_index->push_back(at);
  }
  return clouds;
}

TEST(AnklePathTest, FollowsTheConsistentCandidate) {
  std::vector<int> truth;
  const auto clouds = CloudsAroundTruth(40, 30, 3, &truth);
  auto solved = SolveAnkleWindow(clouds, std::nullopt, kFrameSeconds, {});
  ASSERT_TRUE(solved.ok()) << solved.status();
  int hits = 0;
  for (int t = 0; t < 40; ++t) hits += solved->nodes[t] == truth[t] ? 1 : 0;
  EXPECT_GE(hits, 38);  // the first frame has no predecessor to tell it apart
}

TEST(AnklePathTest, WindowsCarryTheirLastNode) {
  std::vector<int> truth;
  const auto clouds = CloudsAroundTruth(60, 20, 5, &truth);
  AnklePathOptions options;
  options.smoothing_sigma_frames = 0.0f;
  auto global = SolveAnklePath(clouds, 0, kFrameSeconds, options);
  auto windowed = SolveAnklePath(clouds, 10, kFrameSeconds, options);
  ASSERT_TRUE(global.ok() && windowed.ok());
  ASSERT_EQ(windowed->size(), 60u);
  int same = 0;
  for (int t = 0; t < 60; ++t) same += ((*global)[t][0] - (*windowed)[t][0]).norm() < 1e-6f ? 1 : 0;
  EXPECT_GE(same, 55);
}

TEST(AnklePathTest, SlidingIsPenalised) {
  // From a planted foot, two next candidates equally far from the motion prior: one slides 5 cm
  // along the floor, the other lifts 5 cm.
  AnkleCandidate start;
  start.position[0] = start.position[1] = Eigen::Vector3f(0, 0.08f, 0);
  start.velocity[0] = start.velocity[1] = Eigen::Vector3f::Zero();
  AnkleCandidate slides = start, lifts = start;
  slides.position[0] += Eigen::Vector3f(0, 0, 0.05f);
  lifts.position[0] += Eigen::Vector3f(0, 0.05f, 0);
  auto solved = SolveAnkleWindow({{slides, lifts}}, start, kFrameSeconds, {});
  ASSERT_TRUE(solved.ok());
  EXPECT_EQ(solved->nodes[0], 1);
  AnklePathOptions no_slide_term;
  no_slide_term.prior_weight = 1.0f;
  auto tie = SolveAnkleWindow({{slides, lifts}}, start, kFrameSeconds, no_slide_term);
  EXPECT_NEAR(tie->cost, 0.05f * 0.05f * 1e4f, 1e-3f);  // σ in cm²
}

TEST(AnklePathTest, OnlyTheContactRuleSparesALevelSwingAboveTheGround) {
  AnkleCandidate from;
  from.position[0] = from.position[1] = Eigen::Vector3f(0, 0.25f, 0);  // a swinging foot, well above ground
  from.velocity[0] = from.velocity[1] = Eigen::Vector3f::Zero();
  AnkleCandidate to = from;
  to.position[0].z() += 0.08f;  // 8 cm forward, level
  AnklePathOptions contact, patent;
  contact.prior_weight = patent.prior_weight = 0.0f;  // the slide term alone
  patent.slide_rule = SlideRule::kPatent;
  EXPECT_EQ(SolveAnkleWindow({{to}}, from, kFrameSeconds, contact)->cost, 0.0f);
  EXPECT_GT(SolveAnkleWindow({{to}}, from, kFrameSeconds, patent)->cost, 1.0f);
}

TEST(AnklePathTest, SmoothingKeepsLinesAndDampsJitter) {
  std::vector<AnklePair> line, jitter;
  for (int t = 0; t < 30; ++t) {
    line.push_back({Eigen::Vector3f(0, 0, 0.04f * t), Eigen::Vector3f(1, 0, 0.04f * t)});
    jitter.push_back({Eigen::Vector3f(0, (t % 2) ? 0.01f : -0.01f, 0), Eigen::Vector3f::Zero()});
  }
  const auto smoothed_line = SmoothAnkles(line, 2.0f);
  for (int t = 8; t < 22; ++t) EXPECT_LT((smoothed_line[t][0] - line[t][0]).norm(), 1e-5f);
  const auto smoothed_jitter = SmoothAnkles(jitter, 2.0f);
  for (int t = 8; t < 22; ++t) EXPECT_LT(std::abs(smoothed_jitter[t][0].y()), 0.001f);
}

// A stream's newest frames: the filter reaches past the path's end. A swinging foot (the left,
// 4 cm a frame) is followed there by the local line; a planted foot whose path wobbles by a
// centimetre (the right) keeps the end frame.
TEST(AnklePathTest, EdgeFitFollowsAMovingFootAndHoldsAStillOne) {
  const std::vector<float> kernel = {0.05f, 0.1f, 0.2f, 0.3f, 0.2f, 0.1f, 0.05f};
  std::vector<AnklePair> path;
  for (int t = 0; t < 12; ++t) {
    path.push_back({Eigen::Vector3f(0, 0.1f, 0.04f * t), Eigen::Vector3f(0.2f, 0.08f, (t % 2) ? 0.005f : -0.005f)});
  }
  const int newest = static_cast<int>(path.size()) - 1;
  for (int t = newest - 2; t <= newest; ++t) {
    const AnklePair clamped = SmoothAnkleAt(path, kernel, t, newest + 1);
    const AnklePair fitted = SmoothAnkleAt(path, kernel, t, newest + 1, 0.02f);
    EXPECT_GT((clamped[0] - path[t][0]).norm(), 0.001f) << "frame " << t;  // repeating the end lags it
    EXPECT_LT((fitted[0] - path[t][0]).norm(), 1e-5f) << "frame " << t;    // the line has no lag
    EXPECT_EQ(fitted[1], clamped[1]) << "frame " << t;                     // a still foot is held
  }
  // Inside the path the fit is the Gaussian itself.
  const AnklePair inside = SmoothAnkleAt(path, kernel, 5, newest + 1, 0.02f);
  EXPECT_EQ(inside[0], SmoothAnkleAt(path, kernel, 5, newest + 1)[0]);
  // A segment's first frames, for a foot moving from its start.
  EXPECT_LT((SmoothAnkleAt(path, kernel, 0, newest + 1, 0.02f)[0] - path[0][0]).norm(), 1e-5f);
}

// The line never digs a foot below the heights its frames had (nor lifts it above them).
TEST(AnklePathTest, EdgeFitKeepsHeightsWithinThePath) {
  const std::vector<float> kernel = {0.05f, 0.1f, 0.2f, 0.3f, 0.2f, 0.1f, 0.05f};
  std::vector<AnklePair> path;
  for (int t = 0; t < 8; ++t) {
    // Moving forward, landing: the height drops fast at the end.
    const float height = t < 6 ? 0.2f - 0.01f * t : 0.14f - 0.06f * (t - 5);
    path.push_back({Eigen::Vector3f(0, height, 0.05f * t), Eigen::Vector3f::Zero()});
  }
  for (int t = 5; t < 8; ++t) {
    const float y = SmoothAnkleAt(path, kernel, t, 8, 0.02f)[0].y();
    EXPECT_GE(y, path[7][0].y() - 1e-6f) << "frame " << t;
    EXPECT_LE(y, path[2][0].y() + 1e-6f) << "frame " << t;
  }
}

TEST(AnklePathTest, RejectsEmptyInput) {
  EXPECT_EQ(SolveAnkleWindow({}, std::nullopt, kFrameSeconds, {}).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(SolveAnkleWindow({{}}, std::nullopt, kFrameSeconds, {}).status().code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace mocap
