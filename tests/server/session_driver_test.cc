// SessionDriver (server/session_driver.h) in-process on a small synthetic database: a bad config is
// refused naming the field, `started` describes the session, samples become frames as they arrive
// (fixed lag) or at the end (whole trajectory, in replies of at most kFramesPerReply), refused
// samples are answered one by one, and the limits, the cancel flag, the caller's frame and the
// server's counters behave as documented.
#include "server/session_driver.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "motion/reconstruct/body_sizer.h"
#include "tests/support/synthetic_database.h"

namespace mocap {
// Named, so that helpers do not meet other files' in a unity batch.
namespace session_driver_test {
namespace {

constexpr int kTestFrames = 300;

const testing::SyntheticReconstructionSetup& SyntheticSetup() {
  static const auto* setup =
      new testing::SyntheticReconstructionSetup(testing::MakeSyntheticReconstructionSetup({}, kTestFrames));
  return *setup;
}

// The test clip's wrists as wire samples (metres, Y up: the server's own frame), `unit_scale`
// units per metre.
v1::WristSamples WireSamples(int count = kTestFrames, double unit_scale = 1.0) {
  const std::vector<WristSample> samples = testing::WristSamplesOf(SyntheticSetup());
  v1::WristSamples out;
  for (int i = 0; i < count && i < static_cast<int>(samples.size()); ++i) {
    v1::WristSample* sample = out.add_samples();
    sample->set_time(samples[i].time);
    for (auto [from, to] :
         {std::pair{&samples[i].left, sample->mutable_left()}, std::pair{&samples[i].right, sample->mutable_right()}}) {
      to->set_x(from->x() * unit_scale);
      to->set_y(from->y() * unit_scale);
      to->set_z(from->z() * unit_scale);
    }
  }
  return out;
}

// A cheap session: small K1 and K2 (the fuzz target's), fixed lag `lag` or (lag < 0) the whole
// trajectory.
v1::SessionConfig Config(int lag) {
  v1::SessionConfig config;
  config.set_database("synthetic");
  if (lag >= 0) {
    config.mutable_fixed_lag()->set_lag_frames(lag);
  } else {
    config.mutable_sub_interval()->set_window_frames(0);
  }
  config.mutable_overrides()->set_ankle_candidates(32);
  config.mutable_overrides()->set_pose_neighbours(16);
  return config;
}

double Metric(const ServerMetrics& metrics, const std::string& name) {
  std::istringstream lines(metrics.PrometheusText());
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind(name + " ", 0) == 0) return std::stod(line.substr(name.size() + 1));
  }
  ADD_FAILURE() << "no metric " << name;
  return -1;
}

// What a list of replies holds, by kind.
struct Replies {
  std::vector<v1::Frame> frames;
  std::vector<int> batch_sizes;
  std::vector<v1::SampleRejected> rejected;
  int input_reports = 0;
  std::vector<v1::SessionSummary> summaries;
  int other = 0;
};
Replies Sort(const std::vector<v1::ReconstructResponse>& replies) {
  Replies out;
  for (const v1::ReconstructResponse& reply : replies) {
    switch (reply.kind_case()) {
      case v1::ReconstructResponse::kFrames:
        out.batch_sizes.push_back(reply.frames().frames_size());
        for (const v1::Frame& frame : reply.frames().frames()) out.frames.push_back(frame);
        break;
      case v1::ReconstructResponse::kRejected:
        out.rejected.push_back(reply.rejected());
        break;
      case v1::ReconstructResponse::kInputReport:
        ++out.input_reports;
        break;
      case v1::ReconstructResponse::kSummary:
        out.summaries.push_back(reply.summary());
        break;
      default:
        ++out.other;
    }
  }
  return out;
}

class SessionDriverTest : public ::testing::Test {
 protected:
  absl::StatusOr<std::unique_ptr<SessionDriver>> Create(const v1::SessionConfig& config,
                                                        const SessionLimits& limits = {},
                                                        const std::atomic<bool>* cancel = nullptr) {
    return SessionDriver::Create(config, SyntheticSetup().database, "s-1", limits, metrics_, cancel);
  }
  ServerMetrics metrics_;
};

TEST_F(SessionDriverTest, ABadConfigIsRefusedNamingTheField) {
  struct Case {
    std::string named;
    std::function<void(v1::SessionConfig&)> edit;
  };
  const std::vector<Case> cases = {
      {"overrides.ankle_candidates", [](auto& c) { c.mutable_overrides()->set_ankle_candidates(0); }},
      {"overrides.ankle_candidates",
       [](auto& c) { c.mutable_overrides()->set_ankle_candidates(kMaxAnkleCandidates + 1); }},
      {"fixed_lag.lag_frames", [](auto& c) { c.mutable_fixed_lag()->set_lag_frames(601); }},
      {"sub_interval.window_frames", [](auto& c) { c.mutable_sub_interval()->set_window_frames(-1); }},
      {"min_confidence", [](auto& c) { c.set_min_confidence(-0.5f); }},
      {"performer_height", [](auto& c) { c.set_performer_height(40.0f); }},  // 40 m
      {"performer_height", [](auto& c) { c.set_performer_height(-1.7f); }},
  };
  for (const Case& c : cases) {
    v1::SessionConfig config = Config(0);
    c.edit(config);
    auto driver = Create(config);
    ASSERT_FALSE(driver.ok()) << c.named;
    EXPECT_EQ(driver.status().code(), absl::StatusCode::kInvalidArgument) << c.named << ": " << driver.status();
    EXPECT_NE(driver.status().message().find(c.named), std::string::npos) << driver.status();
  }
  v1::SessionConfig bad_frame = Config(0);
  bad_frame.mutable_input_frame()->set_unit(static_cast<v1::LengthUnit>(77));
  EXPECT_EQ(Create(bad_frame).status().code(), absl::StatusCode::kInvalidArgument);
  // A refused session was never counted as one.
  EXPECT_EQ(Metric(metrics_, "mocap_sessions_total"), 0);
  EXPECT_EQ(Metric(metrics_, "mocap_sessions_active"), 0);
}

// A session refused for its target_rig (INVALID_ARGUMENT, never started) is not counted in
// mocap_sessions_total ("Reconstruction sessions started"): it was, when the rig was analysed after
// the count.
TEST_F(SessionDriverTest, ASessionRefusedForItsTargetRigIsNotCounted) {
  v1::SessionConfig config = Config(0);
  config.mutable_target_rig()->set_unit("cm");  // neither bvh nor joints
  auto driver = Create(config);
  ASSERT_FALSE(driver.ok());
  EXPECT_EQ(driver.status().code(), absl::StatusCode::kInvalidArgument) << driver.status();
  EXPECT_NE(driver.status().message().find("target_rig"), std::string::npos) << driver.status();
  EXPECT_EQ(Metric(metrics_, "mocap_sessions_active"), 0);
  EXPECT_EQ(Metric(metrics_, "mocap_sessions_total"), 0);
}

TEST_F(SessionDriverTest, StartedDescribesTheSessionAndTheCountersFollowIt) {
  v1::SessionConfig config = Config(3);
  {
    auto driver = Create(config);
    ASSERT_TRUE(driver.ok()) << driver.status();
    const v1::SessionStarted& started = (*driver)->started();
    const ReconstructionDatabase& database = *SyntheticSetup().database;
    EXPECT_EQ(started.session_id(), "s-1");
    EXPECT_EQ(started.latency_frames(), 3);
    EXPECT_NEAR(started.frame_rate(), 30.0, 1e-9);
    EXPECT_EQ(started.database_frames(), database.num_frames());
    EXPECT_GT(started.database_height(), 1.0f);
    EXPECT_EQ(started.skeleton().joints_size(), database.body().skeleton().num_joints());
    EXPECT_EQ(started.config().overrides().ankle_candidates(), 32);
    EXPECT_TRUE(started.config().overrides().has_joint_smoothing_frames());  // filled in
    EXPECT_EQ(Metric(metrics_, "mocap_sessions_active"), 1);
  }
  EXPECT_EQ(Metric(metrics_, "mocap_sessions_active"), 0);
  EXPECT_EQ(Metric(metrics_, "mocap_sessions_total"), 1);
}

TEST_F(SessionDriverTest, FixedLagSessionsAnswerEachSampleAfterTheLag) {
  constexpr int kLag = 2, kSamples = 40;
  auto driver = Create(Config(kLag));
  ASSERT_TRUE(driver.ok()) << driver.status();
  const v1::WristSamples samples = WireSamples(kSamples);
  std::vector<v1::ReconstructResponse> replies;
  for (int i = 0; i < kSamples; ++i) {
    ASSERT_TRUE((*driver)->Push(samples, i, i + 1, &replies).ok()) << "sample " << i;
    // Frame t - lag is decided when sample t arrives.
    EXPECT_EQ((*driver)->frames_emitted(), std::max(0, i + 1 - kLag)) << "after sample " << i;
  }
  ASSERT_TRUE((*driver)->Finish(&replies).ok());
  const Replies sorted = Sort(replies);
  ASSERT_EQ(sorted.frames.size(), static_cast<size_t>(kSamples));
  for (int i = 0; i < kSamples; ++i) {
    EXPECT_EQ(sorted.frames[i].index(), i);
    EXPECT_NEAR(sorted.frames[i].time(), samples.samples(i).time(), 1e-9);
    EXPECT_EQ(sorted.frames[i].rotations_size(), SyntheticSetup().database->body().skeleton().num_joints());
  }
  ASSERT_EQ(sorted.summaries.size(), 1u);
  EXPECT_EQ(replies.back().kind_case(), v1::ReconstructResponse::kSummary);  // the summary is last
  EXPECT_EQ(sorted.summaries[0].frames(), kSamples);
  EXPECT_EQ(sorted.summaries[0].samples(), kSamples);
  EXPECT_EQ(sorted.summaries[0].rejected_samples(), 0);
  EXPECT_EQ(sorted.input_reports, 1);  // after the first second of input, once
  EXPECT_EQ(sorted.other, 0);
  EXPECT_EQ(Metric(metrics_, "mocap_frames_reconstructed_total"), kSamples);
}

TEST_F(SessionDriverTest, FinishEmitsTheWholeTrajectoryInRepliesOfAtMostTheBatchSize) {
  // One slice for the whole end (slicing is AWindowsFramesAreSolvedASliceAtATimeWithTheSameFrames's).
  auto driver = Create(Config(-1), SessionLimits{.slice_budget = std::chrono::hours(1)});
  ASSERT_TRUE(driver.ok()) << driver.status();
  const v1::WristSamples samples = WireSamples(kTestFrames);
  std::vector<v1::ReconstructResponse> replies;
  ASSERT_TRUE((*driver)->Push(samples, &replies).ok());
  EXPECT_EQ((*driver)->frames_emitted(), 0) << "a whole-trajectory session answered before its end";
  EXPECT_TRUE(Sort(replies).frames.empty());
  (*driver)->RecordReplyLatency(2.0);
  (*driver)->RecordReplyLatency(4.0);
  replies.clear();
  ASSERT_TRUE((*driver)->Finish(&replies).ok());
  const Replies sorted = Sort(replies);
  EXPECT_EQ(sorted.batch_sizes,
            (std::vector<int>{SessionDriver::kFramesPerReply, kTestFrames - SessionDriver::kFramesPerReply}));
  ASSERT_EQ(sorted.frames.size(), static_cast<size_t>(kTestFrames));
  for (int i = 0; i < kTestFrames; ++i) ASSERT_EQ(sorted.frames[i].index(), i);
  ASSERT_EQ(sorted.summaries.size(), 1u);
  EXPECT_EQ(replies.back().kind_case(), v1::ReconstructResponse::kSummary);
  EXPECT_EQ(sorted.summaries[0].frames(), kTestFrames);
  EXPECT_DOUBLE_EQ(sorted.summaries[0].mean_reply_ms(), 3.0);
  EXPECT_DOUBLE_EQ(sorted.summaries[0].max_reply_ms(), 4.0);
  // The frames follow the walk: the solved wrists land near the tracked ones.
  const std::vector<WristSample> truth = testing::WristSamplesOf(SyntheticSetup());
  for (int i = 0; i < kTestFrames; i += 25) {
    const v1::Vec3& wrist = sorted.frames[i].left_wrist();
    EXPECT_LT((Eigen::Vector3f(wrist.x(), wrist.y(), wrist.z()) - truth[i].left).norm(), 0.1f) << "frame " << i;
  }
}

TEST_F(SessionDriverTest, NonFiniteSamplesAreRefusedOneByOneAndTheSessionGoesOn) {
  auto driver = Create(Config(0));
  ASSERT_TRUE(driver.ok()) << driver.status();
  v1::WristSamples samples = WireSamples(60);
  samples.mutable_samples(5)->mutable_left()->set_x(std::numeric_limits<double>::quiet_NaN());
  samples.mutable_samples(9)->set_time(std::numeric_limits<double>::infinity());
  samples.mutable_samples(20)->set_time(samples.samples(19).time() - 0.01);  // backwards: the session refuses it
  std::vector<v1::ReconstructResponse> replies;
  ASSERT_TRUE((*driver)->Push(samples, &replies).ok());
  ASSERT_TRUE((*driver)->Finish(&replies).ok());
  const Replies sorted = Sort(replies);
  ASSERT_EQ(sorted.rejected.size(), 3u);
  EXPECT_EQ(sorted.rejected[0].sample_index(), 5);
  EXPECT_NE(sorted.rejected[0].reason().find("finite"), std::string::npos) << sorted.rejected[0].reason();
  EXPECT_EQ(sorted.rejected[1].sample_index(), 9);
  EXPECT_EQ(sorted.rejected[2].sample_index(), 20);
  EXPECT_FALSE(sorted.rejected[2].reason().empty());
  EXPECT_EQ((*driver)->samples_rejected(), 3);
  ASSERT_EQ(sorted.summaries.size(), 1u);
  EXPECT_EQ(sorted.summaries[0].samples(), 60);
  EXPECT_EQ(sorted.summaries[0].rejected_samples(), 3);
  EXPECT_EQ(sorted.frames.size(), 60u);  // the gaps are bridged on the 30 Hz grid
  for (const v1::Frame& frame : sorted.frames) {
    EXPECT_TRUE(std::isfinite(frame.root_position().x()) && std::isfinite(frame.root_position().y())) << frame.index();
  }
  EXPECT_EQ(Metric(metrics_, "mocap_samples_rejected_total"), 3);
}

TEST_F(SessionDriverTest, AHandBelowMinConfidenceIsLostAndTheBodyGoesOnFromTheOther) {
  v1::SessionConfig config = Config(0);
  config.set_min_confidence(0.5f);
  config.set_include_diagnostics(true);
  auto driver = Create(config);
  ASSERT_TRUE(driver.ok()) << driver.status();
  v1::WristSamples samples = WireSamples(60);
  for (int i = 10; i < 40; ++i) {  // the right tracker lost for 1 s: what it sends is not read
    samples.mutable_samples(i)->set_right_confidence(0.1f);
    samples.mutable_samples(i)->mutable_right()->set_x(std::numeric_limits<double>::quiet_NaN());
  }
  for (int i : {50, 51}) {  // both below: a dropout, bridged
    samples.mutable_samples(i)->set_left_confidence(0.2f);
    samples.mutable_samples(i)->set_right_confidence(0.2f);
  }
  std::vector<v1::ReconstructResponse> replies;
  ASSERT_TRUE((*driver)->Push(samples, &replies).ok());
  ASSERT_TRUE((*driver)->Finish(&replies).ok());
  const Replies sorted = Sort(replies);
  ASSERT_EQ(sorted.frames.size(), 60u);  // no frame missing, one segment
  int predicted = 0;
  for (const v1::Frame& frame : sorted.frames) {
    EXPECT_EQ(frame.segment(), 0);
    EXPECT_TRUE(std::isfinite(frame.root_position().x()) && std::isfinite(frame.right_wrist().x())) << frame.index();
    const bool lost = frame.index() >= 10 && frame.index() < 40;
    const bool dropout = frame.index() == 50 || frame.index() == 51;
    EXPECT_EQ(frame.left_hand_state() == v1::TRACKING_STATE_PREDICTED, dropout) << frame.index();
    if (lost) {
      EXPECT_EQ(frame.right_hand_state(), v1::TRACKING_STATE_PREDICTED) << frame.index();  // under max_gap (2 s)
      EXPECT_GT(frame.diagnostics().right_untracked_seconds(), 0.0f);
      EXPECT_GT(frame.expected_error().right_wrist(), 2 * frame.expected_error().left_wrist()) << frame.index();
      ++predicted;
    } else if (!dropout) {
      EXPECT_EQ(frame.right_hand_state(), v1::TRACKING_STATE_TRACKED) << frame.index();  // its return is no jump
    }
  }
  EXPECT_EQ(predicted, 30);
  ASSERT_EQ(sorted.rejected.size(), 2u);  // the dropout's samples are answered as such
  EXPECT_EQ(sorted.rejected[0].sample_index(), 50);
  EXPECT_NE(sorted.rejected[0].reason().find("dropout"), std::string::npos) << sorted.rejected[0].reason();
}

TEST_F(SessionDriverTest, StrictSessionsEndAtTheFirstRefusedSample) {
  v1::SessionConfig config = Config(0);
  config.set_strict(true);
  auto driver = Create(config);
  ASSERT_TRUE(driver.ok()) << driver.status();
  v1::WristSamples samples = WireSamples(20);
  samples.mutable_samples(7)->mutable_right()->set_y(std::numeric_limits<double>::infinity());
  std::vector<v1::ReconstructResponse> replies;
  const absl::Status status = (*driver)->Push(samples, &replies);
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument) << status;
  EXPECT_NE(status.message().find("sample 7"), std::string::npos) << status;
  EXPECT_TRUE(Sort(replies).rejected.empty());
}

TEST_F(SessionDriverTest, SamplesSpanningMoreThanTheSessionLimitEndIt) {
  SessionLimits limits;
  limits.max_session_seconds = 1.0;
  auto driver = Create(Config(0), limits);
  ASSERT_TRUE(driver.ok()) << driver.status();
  const v1::WristSamples samples = WireSamples(60);  // 2 s at 30 Hz
  std::vector<v1::ReconstructResponse> replies;
  ASSERT_TRUE((*driver)->Push(samples, 0, 30, &replies).ok());  // 0–0.97 s: within the limit
  const absl::Status status = (*driver)->Push(samples, 30, 60, &replies);
  EXPECT_EQ(status.code(), absl::StatusCode::kResourceExhausted) << status;
  EXPECT_NE(status.message().find("session length limit"), std::string::npos) << status;
}

TEST_F(SessionDriverTest, ACancelledSessionStopsWithCancelled) {
  std::atomic<bool> cancel{false};
  auto driver = Create(Config(0), {}, &cancel);
  ASSERT_TRUE(driver.ok()) << driver.status();
  const v1::WristSamples samples = WireSamples(60);
  std::vector<v1::ReconstructResponse> replies;
  ASSERT_TRUE((*driver)->Push(samples, 0, 10, &replies).ok());
  const long before = (*driver)->frames_emitted();
  EXPECT_GT(before, 0);
  cancel.store(true);
  absl::Status status = (*driver)->Push(samples, 10, 60, &replies);
  if (status.ok()) status = (*driver)->Finish(&replies);
  EXPECT_EQ(status.code(), absl::StatusCode::kCancelled) << status;
  EXPECT_LE((*driver)->frames_emitted(), before + 1) << "the session went on computing after the cancel";
}

TEST_F(SessionDriverTest, RepliesComeBackInTheCallersFrameUnlessTheServersIsAsked) {
  const v1::WristSamples metres = WireSamples(45);
  const v1::WristSamples centimetres = WireSamples(45, 100.0);
  auto run = [&](const v1::WristSamples& samples, bool centimetre_input, v1::OutputFrame output) {
    v1::SessionConfig config = Config(0);
    if (centimetre_input) config.mutable_input_frame()->set_unit(v1::LENGTH_UNIT_CENTIMETRE);
    config.set_output_frame(output);
    auto driver = Create(config);
    EXPECT_TRUE(driver.ok()) << driver.status();
    std::vector<v1::ReconstructResponse> replies;
    EXPECT_TRUE((*driver)->Push(samples, &replies).ok());
    EXPECT_TRUE((*driver)->Finish(&replies).ok());
    return std::pair{(*driver)->started(), Sort(replies).frames};
  };
  const auto [native_started, native] = run(metres, false, v1::OUTPUT_FRAME_INPUT);
  const auto [cm_started, in_cm] = run(centimetres, true, v1::OUTPUT_FRAME_INPUT);
  const auto [server_started, in_server] = run(centimetres, true, v1::OUTPUT_FRAME_SERVER);
  ASSERT_EQ(native.size(), 45u);
  ASSERT_EQ(in_cm.size(), 45u);
  ASSERT_EQ(in_server.size(), 45u);
  for (size_t i = 0; i < native.size(); i += 11) {
    EXPECT_NEAR(in_cm[i].pelvis_position().y(), 100.0 * native[i].pelvis_position().y(), 0.5) << i;
    EXPECT_NEAR(in_server[i].pelvis_position().y(), native[i].pelvis_position().y(), 0.005) << i;
  }
  const int hips = 0;
  EXPECT_NEAR(cm_started.skeleton().joints(hips).offset().y(),
              100.0 * native_started.skeleton().joints(hips).offset().y(), 1e-3);
  EXPECT_NEAR(server_started.skeleton().joints(hips).offset().y(), native_started.skeleton().joints(hips).offset().y(),
              1e-6);
}

TEST_F(SessionDriverTest, ATallerPerformerGetsAScaledSkeleton) {
  auto plain = Create(Config(0));
  ASSERT_TRUE(plain.ok()) << plain.status();
  v1::SessionConfig config = Config(0);
  config.set_performer_height(1.5f * (*plain)->started().database_height());
  auto tall = Create(config);
  ASSERT_TRUE(tall.ok()) << tall.status();
  const v1::Skeleton& a = (*plain)->started().skeleton();
  const v1::Skeleton& b = (*tall)->started().skeleton();
  ASSERT_EQ(a.joints_size(), b.joints_size());
  for (int j = 0; j < a.joints_size(); ++j) {
    EXPECT_NEAR(b.joints(j).offset().x(), 1.5f * a.joints(j).offset().x(), 1e-5f) << j;
    EXPECT_NEAR(b.joints(j).offset().y(), 1.5f * a.joints(j).offset().y(), 1e-5f) << j;
  }
  EXPECT_EQ((*tall)->started().database_height(), (*plain)->started().database_height());
}

// estimate_performer_height (issue #22): a whole trajectory from a body larger than the
// database's is answered by a body sized by the wrists' reach, its skeleton on the first frames
// reply and its height in the summary; the database's own input keeps the database's body.
TEST_F(SessionDriverTest, AWholeTrajectoryIsSizedByTheWristsReach) {
  v1::SessionConfig config = Config(-1);
  config.set_estimate_performer_height(true);
  for (const double size : {1.0, 1.3}) {
    auto driver = Create(config);
    ASSERT_TRUE(driver.ok()) << driver.status();
    std::vector<v1::ReconstructResponse> replies;
    ASSERT_TRUE((*driver)->Push(WireSamples(kTestFrames, size), &replies).ok());
    EXPECT_TRUE(replies.empty() || !replies.front().has_frames());  // frames only at the end
    ASSERT_TRUE((*driver)->Finish(&replies).ok());
    const Replies sorted = Sort(replies);
    ASSERT_EQ(sorted.summaries.size(), 1u);
    ASSERT_EQ(sorted.frames.size(), static_cast<size_t>(kTestFrames));
    const v1::SessionSummary& summary = sorted.summaries.front();
    const float database_height = (*driver)->started().database_height();
    const v1::ReconstructedFrames* first = nullptr;
    for (const v1::ReconstructResponse& reply : replies) {
      if (!reply.has_frames()) continue;
      if (first == nullptr) {
        first = &reply.frames();
      } else {
        EXPECT_FALSE(reply.frames().has_skeleton());  // told once
      }
    }
    ASSERT_NE(first, nullptr);
    EXPECT_FLOAT_EQ(summary.reach_height(), summary.performer_height());  // what it was sized by
    if (size == 1.0) {
      EXPECT_FALSE(summary.performer_height_estimated());
      EXPECT_FLOAT_EQ(summary.performer_height(), database_height);
      EXPECT_FALSE(first->has_skeleton());
      continue;
    }
    // The quantile of a stretched input is at most the stretched farthest: at most 1.3 times.
    EXPECT_TRUE(summary.performer_height_estimated());
    EXPECT_GT(summary.performer_height(), 1.05f * database_height);
    EXPECT_LE(summary.performer_height(), 1.3f * database_height * 1.001f);
    ASSERT_TRUE(first->has_skeleton());
    const float ratio = summary.performer_height() / database_height;
    const v1::Skeleton& started = (*driver)->started().skeleton();
    ASSERT_EQ(first->skeleton().joints_size(), started.joints_size());
    for (int j = 0; j < started.joints_size(); ++j)
      EXPECT_NEAR(first->skeleton().joints(j).offset().y(), ratio * started.joints(j).offset().y(), 1e-4f) << j;
  }
}

// A long input is not held to its end: past max_reach_hold_seconds the body is sized on what is
// held, and the rest streams on as any whole trajectory does (in windows of max_window_frames).
TEST_F(SessionDriverTest, ALongInputIsSizedOnItsFirstPartAndStreamsOn) {
  v1::SessionConfig config = Config(-1);
  config.set_estimate_performer_height(true);
  // One slice for all held samples: a 20 ms slice on a loaded machine may end before the first
  // window is out (slicing is HeldSamplesGoIntoTheSessionASliceAtATimeWithTheSameFrames's).
  auto driver = Create(
      config,
      SessionLimits{.max_window_frames = 50, .max_reach_hold_seconds = 3.0, .slice_budget = std::chrono::hours(1)});
  ASSERT_TRUE(driver.ok()) << driver.status();
  std::vector<v1::ReconstructResponse> replies;
  ASSERT_TRUE((*driver)->Push(WireSamples(kTestFrames, 1.3), &replies).ok());
  EXPECT_FALSE((*driver)->has_backlog());
  const size_t before_finish = Sort(replies).frames.size();
  EXPECT_GT(before_finish, 0u);  // not held to the end
  ASSERT_TRUE((*driver)->Finish(&replies).ok());
  const Replies sorted = Sort(replies);
  EXPECT_EQ(sorted.frames.size(), static_cast<size_t>(kTestFrames));
  ASSERT_EQ(sorted.summaries.size(), 1u);
  EXPECT_TRUE(sorted.summaries.front().performer_height_estimated());
  for (const v1::ReconstructResponse& reply : replies) {
    if (!reply.has_frames()) continue;
    EXPECT_TRUE(reply.frames().has_skeleton());  // the first frames reply carries it
    break;
  }
}

// Held samples go into the session a slice at a time (issue #24: minutes of them were one task),
// with the same frames as all at once: at the end of a sized whole trajectory (FinishStep) and
// past the hold limit mid-stream (Continue before the next Push).
std::vector<std::string> FramesOf(const std::vector<v1::ReconstructResponse>& replies) {
  std::vector<std::string> out;
  for (const v1::Frame& frame : Sort(replies).frames) out.push_back(frame.SerializeAsString());
  return out;
}

TEST_F(SessionDriverTest, HeldSamplesGoIntoTheSessionASliceAtATimeWithTheSameFrames) {
  v1::SessionConfig config = Config(-1);
  config.set_estimate_performer_height(true);
  for (const double hold_seconds : {600.0, 3.0}) {
    SCOPED_TRACE(hold_seconds);
    auto at_once = Create(config, SessionLimits{.max_window_frames = 50,
                                                .max_reach_hold_seconds = hold_seconds,
                                                .slice_budget = std::chrono::hours(1)});
    auto sliced = Create(config, SessionLimits{.max_window_frames = 50,
                                               .max_reach_hold_seconds = hold_seconds,
                                               .slice_budget = std::chrono::microseconds(0)});
    ASSERT_TRUE(at_once.ok() && sliced.ok());
    std::vector<v1::ReconstructResponse> whole, steps;
    ASSERT_TRUE((*at_once)->Push(WireSamples(kTestFrames, 1.3), &whole).ok());
    EXPECT_FALSE((*at_once)->has_backlog());
    ASSERT_TRUE((*at_once)->Finish(&whole).ok());

    ASSERT_TRUE((*sliced)->Push(WireSamples(kTestFrames, 1.3), &steps).ok());
    int continues = 0;
    while ((*sliced)->has_backlog()) {
      ASSERT_TRUE((*sliced)->Continue(&steps).ok());
      ++continues;
    }
    // Past the hold limit the held samples wait, a sample a step at this budget; under it nothing
    // is pushed before the end.
    if (hold_seconds < 10) {
      EXPECT_GT(continues, 100);
    } else {
      EXPECT_EQ(continues, 0);
    }
    int finish_steps = 0;
    for (bool done = false; !done; ++finish_steps) ASSERT_TRUE((*sliced)->FinishStep(&steps, &done).ok());
    if (hold_seconds > 10) {
      EXPECT_GT(finish_steps, kTestFrames / 2);  // every held sample its own step
    }
    EXPECT_EQ(Sort(steps).summaries.size(), 1u);
    const std::vector<std::string> expected = FramesOf(whole), got = FramesOf(steps);
    ASSERT_EQ(got.size(), static_cast<size_t>(kTestFrames));
    EXPECT_TRUE(got == expected) << "the frames differ from those pushed at once";
  }
}

// A window's frames are solved a slice at a time too (issue #24: a 600-frame window was one task
// of ~0.4 s): the sample that completes a window leaves most of its frames, and the samples after
// it, as backlog; Continue and FinishStep take them in order, with the frames of one call.
TEST_F(SessionDriverTest, AWindowsFramesAreSolvedASliceAtATimeWithTheSameFrames) {
  for (const int window : {0, 40}) {  // 0: the whole trajectory, in windows of max_window_frames
    SCOPED_TRACE(window);
    v1::SessionConfig config = Config(-1);
    config.mutable_sub_interval()->set_window_frames(window);
    // 300 frames: the last window (20 frames) is decided at the end of the input.
    auto at_once = Create(config, SessionLimits{.max_window_frames = 70, .slice_budget = std::chrono::hours(1)});
    auto sliced = Create(config, SessionLimits{.max_window_frames = 70, .slice_budget = std::chrono::microseconds(0)});
    ASSERT_TRUE(at_once.ok() && sliced.ok());
    std::vector<v1::ReconstructResponse> whole, steps;
    ASSERT_TRUE((*at_once)->Push(WireSamples(kTestFrames, 1.0), &whole).ok());
    EXPECT_FALSE((*at_once)->has_backlog());
    ASSERT_TRUE((*at_once)->Finish(&whole).ok());

    ASSERT_TRUE((*sliced)->Push(WireSamples(kTestFrames, 1.0), &steps).ok());
    EXPECT_TRUE((*sliced)->has_backlog());
    EXPECT_LT(Sort(steps).frames.size(), 5u);  // a frame a slice at this budget
    int continues = 0;
    for (; (*sliced)->has_backlog(); ++continues) ASSERT_TRUE((*sliced)->Continue(&steps).ok());
    EXPECT_GT(continues, kTestFrames / 2);
    int finish_steps = 0;
    for (bool done = false; !done; ++finish_steps) ASSERT_TRUE((*sliced)->FinishStep(&steps, &done).ok());
    EXPECT_GT(finish_steps, 5);  // the last window's frames, a few a step
    EXPECT_EQ(Sort(steps).summaries.size(), 1u);
    const std::vector<std::string> expected = FramesOf(whole), got = FramesOf(steps);
    ASSERT_EQ(got.size(), static_cast<size_t>(kTestFrames));
    EXPECT_TRUE(got == expected) << "the frames differ from those solved at once";
  }
}

// A stream's message of many samples is taken a sample a slice when the slice is over (its time
// spent, or another tenant's work waiting for the thread): the rest are held for the next task,
// and the frames are those taken at once.
TEST_F(SessionDriverTest, AMessagesSamplesAreTakenASliceAtATimeWithTheSameFrames) {
  auto at_once = Create(Config(5), SessionLimits{.slice_budget = std::chrono::hours(1)});
  auto sliced = Create(Config(5), SessionLimits{.slice_budget = std::chrono::microseconds(0)});
  ASSERT_TRUE(at_once.ok() && sliced.ok());
  std::vector<v1::ReconstructResponse> whole, steps;
  ASSERT_TRUE((*at_once)->Push(WireSamples(kTestFrames), &whole).ok());
  EXPECT_FALSE((*at_once)->has_backlog());
  ASSERT_TRUE((*at_once)->Finish(&whole).ok());

  ASSERT_TRUE((*sliced)->Push(WireSamples(kTestFrames), &steps).ok());
  EXPECT_TRUE((*sliced)->has_backlog()) << "every sample went in at once";
  int continues = 0;
  for (; (*sliced)->has_backlog(); ++continues) ASSERT_TRUE((*sliced)->Continue(&steps).ok());
  EXPECT_GT(continues, kTestFrames / 2);  // about a sample a slice
  ASSERT_TRUE((*sliced)->Finish(&steps).ok());
  const std::vector<std::string> expected = FramesOf(whole), got = FramesOf(steps);
  ASSERT_EQ(got.size(), static_cast<size_t>(kTestFrames));
  EXPECT_TRUE(got == expected) << "the frames differ from those taken at once";
}

// Without estimate_performer_height a stream keeps its size, but its summary tells how large a
// body the wrists needed.
TEST_F(SessionDriverTest, AStreamsSummaryTellsTheHeightItsReachShows) {
  for (const double size : {1.0, 1.3}) {
    auto driver = Create(Config(5));
    ASSERT_TRUE(driver.ok()) << driver.status();
    std::vector<v1::ReconstructResponse> replies;
    ASSERT_TRUE((*driver)->Push(WireSamples(kTestFrames, size), &replies).ok());
    ASSERT_TRUE((*driver)->Finish(&replies).ok());
    const Replies sorted = Sort(replies);
    ASSERT_EQ(sorted.summaries.size(), 1u);
    const v1::SessionSummary& summary = sorted.summaries.front();
    const float database_height = (*driver)->started().database_height();
    EXPECT_FALSE(summary.performer_height_estimated());
    EXPECT_FLOAT_EQ(summary.performer_height(), database_height);
    if (size == 1.0) {
      EXPECT_FLOAT_EQ(summary.reach_height(), database_height);
    } else {
      EXPECT_GT(summary.reach_height(), 1.05f * database_height);
      EXPECT_LE(summary.reach_height(), 1.3f * database_height * 1.001f);
    }
  }
}

// In the streaming modes the body starts at the database's size and grows as the wrists' reach
// shows it: each frame's body_scale against the started skeleton, never more than the ease allows
// between frames, its positions without a jump, and the summary the height reached. Input the
// database's size keeps it untouched.
TEST_F(SessionDriverTest, AStreamGrowsItsBodyAsTheWristsReachShowsIt) {
  v1::SessionConfig windows = Config(-1);
  windows.mutable_sub_interval()->set_window_frames(50);
  for (v1::SessionConfig config : {Config(0), Config(5), windows}) {
    config.set_estimate_performer_height(true);
    for (const double size : {1.0, 1.3}) {
      auto driver = Create(config);
      ASSERT_TRUE(driver.ok()) << driver.status();
      std::vector<v1::ReconstructResponse> replies;
      const v1::WristSamples samples = WireSamples(kTestFrames, size);
      ASSERT_TRUE((*driver)->Push(samples, &replies).ok());
      ASSERT_TRUE((*driver)->Finish(&replies).ok());
      const Replies sorted = Sort(replies);
      ASSERT_EQ(sorted.summaries.size(), 1u);
      const v1::SessionSummary& summary = sorted.summaries.front();
      const float database_height = (*driver)->started().database_height();
      ASSERT_GT(sorted.frames.size(), 100u);
      float previous = 1.0f;
      for (const v1::Frame& frame : sorted.frames) {
        const float scale = frame.body_scale() == 0.0f ? 1.0f : frame.body_scale();
        if (size == 1.0) {
          EXPECT_EQ(frame.body_scale(), 0.0f) << frame.index();
        }
        // Never a pop: at most the ease's share of the whole change per frame (30 fps).
        const BodySizerOptions sizing;
        EXPECT_LE(std::abs(scale - previous), 0.3f / static_cast<float>(30.0 * sizing.ramp_seconds) + 1e-3f)
            << frame.index();
        if (frame.time() < samples.samples(0).time() + sizing.reach.min_seconds) {
          EXPECT_EQ(scale, 1.0f) << frame.index();  // too little input to say anything yet
        }
        previous = scale;
      }
      EXPECT_FALSE(std::any_of(replies.begin(), replies.end(),
                               [](const v1::ReconstructResponse& r) { return r.frames().has_skeleton(); }));
      if (size == 1.0) {
        EXPECT_FALSE(summary.performer_height_estimated());
        EXPECT_FLOAT_EQ(summary.performer_height(), database_height);
        continue;
      }
      EXPECT_TRUE(summary.performer_height_estimated());
      EXPECT_GT(summary.performer_height(), 1.05f * database_height);
      EXPECT_NEAR(summary.performer_height(), summary.reach_height(), 0.02f * summary.reach_height());
      EXPECT_NEAR(previous, summary.performer_height() / database_height, 1e-3f);  // the last frames' size
    }
  }
}

TEST_F(SessionDriverTest, SizingByReachGivesWayToADeclaredHeight) {
  // A declared height is the performer's: no estimate, whatever the input.
  v1::SessionConfig declared = Config(-1);
  declared.set_estimate_performer_height(true);
  auto probe = Create(Config(-1));
  ASSERT_TRUE(probe.ok());
  declared.set_performer_height(1.1f * (*probe)->started().database_height());
  auto driver = Create(declared);
  ASSERT_TRUE(driver.ok()) << driver.status();
  std::vector<v1::ReconstructResponse> replies;
  ASSERT_TRUE((*driver)->Push(WireSamples(kTestFrames, 1.3), &replies).ok());
  ASSERT_TRUE((*driver)->Finish(&replies).ok());
  const Replies sorted = Sort(replies);
  ASSERT_EQ(sorted.summaries.size(), 1u);
  EXPECT_FALSE(sorted.summaries.front().performer_height_estimated());
  EXPECT_NEAR(sorted.summaries.front().performer_height(), declared.performer_height(), 1e-4f);
}

}  // namespace
}  // namespace session_driver_test
}  // namespace mocap
