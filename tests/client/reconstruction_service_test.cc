// The Reconstruction service end to end: a real `mocapd serve` on loopback over a real store
// holding synthetic walks, driven through the SDK (and the raw stub where a test must misbehave).
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <thread>

#include "client/wrist_input/wrist_source.h"
#include "mocap/v1/reconstruction.grpc.pb.h"
#include "motion/bvh/bvh_writer.h"
#include "tests/support/raw_reconstruct.h"
#include "tests/support/server_fixture.h"
#include "tests/support/stream_events.h"
#include "tests/support/synthetic_clip.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;
using client::Client;
using client::ReconstructionStream;

class ReconstructionServiceTest : public testing::ServerFixture {
 protected:
  // The wrists of another walk (60 frames at 30 Hz), as a tracker would send them.
  std::vector<v1::WristSample> QueryWrists(int frames = 60) {
    auto samples = WristsFromBvh(WriteClip("query.bvh", frames), 0.0, 1);
    EXPECT_TRUE(samples.ok()) << samples.status();
    return std::move(samples).value();
  }
  static v1::SessionConfig Config(int lag = -1) {
    v1::SessionConfig config;
    config.set_database("walks");
    if (lag >= 0) config.mutable_fixed_lag()->set_lag_frames(lag);
    config.mutable_overrides()->set_ankle_candidates(60);
    config.mutable_overrides()->set_pose_neighbours(40);
    config.set_include_diagnostics(true);
    return config;
  }
  // Streams every sample (one per message) and collects the frames.
  struct Streamed {
    v1::SessionStarted started;
    std::vector<v1::Frame> frames;
    std::vector<v1::SampleRejected> rejected;
    absl::StatusOr<v1::SessionSummary> summary = absl::UnknownError("not finished");
  };
  static Streamed Stream(Client& client, const v1::SessionConfig& config, const std::vector<v1::WristSample>& samples) {
    Streamed out;
    auto stream = client.OpenReconstruction(config);
    if (!stream.ok()) {
      out.summary = stream.status();
      return out;
    }
    out.started = (*stream)->started();
    for (const v1::WristSample& sample : samples) {
      if (!(*stream)->Write({sample}).ok()) break;
      // Replies arrive while we write: read what the server has decided so far (fixed lag).
    }
    out.summary = (*stream)->Finish([&](const v1::ReconstructResponse& reply) {
      for (const v1::Frame& frame : reply.frames().frames()) out.frames.push_back(frame);
      if (reply.has_rejected()) out.rejected.push_back(reply.rejected());
    });
    return out;
  }
  static double Distance(const v1::Vec3& a, const v1::Vec3& b) {
    return std::sqrt((a.x() - b.x()) * (a.x() - b.x()) + (a.y() - b.y()) * (a.y() - b.y()) +
                     (a.z() - b.z()) * (a.z() - b.z()));
  }
};

TEST_F(ReconstructionServiceTest, StreamReconstructsEveryFrameAndMatchesTheUnaryCall) {
  StartServer();
  auto client = Connect(keys_["acme"]);
  ImportWalks(*client);
  const std::vector<v1::WristSample> samples = QueryWrists();

  v1::SessionConfig config = Config(/*lag=*/4);
  config.mutable_overrides()->set_wrist_fit_frames(0);  // the patent's A2, which the loop below replays
  Streamed streamed = Stream(*client, config, samples);
  ASSERT_TRUE(streamed.summary.ok()) << streamed.summary.status();
  EXPECT_FALSE(streamed.started.session_id().empty());
  EXPECT_EQ(streamed.started.skeleton().joints_size(), 22);
  EXPECT_DOUBLE_EQ(streamed.started.frame_rate(), 30.0);
  EXPECT_EQ(streamed.started.latency_frames(), 4);
  EXPECT_EQ(streamed.started.database_frames(), 90 + 120 + 150);
  EXPECT_NEAR(streamed.started.database_height(), 1.8, 0.3);  // the synthetic rig stands ~1.7 m
  EXPECT_EQ(streamed.started.config().overrides().ankle_candidates(), 60);
  EXPECT_EQ(streamed.started.config().overrides().joint_smoothing_frames(), 1.0f);  // a default, filled in
  ASSERT_EQ(streamed.frames.size(), samples.size());
  EXPECT_EQ(streamed.summary->frames(), static_cast<long>(samples.size()));
  EXPECT_EQ(streamed.summary->samples(), static_cast<long>(samples.size()));
  EXPECT_EQ(streamed.summary->rejected_samples(), 0);
  EXPECT_GT(streamed.summary->path_ms_per_frame(), 0.0);
  v1::Vec3 smoothed = samples[0].left();  // A2: x̃ = s·x + (1 − s)·x̃ₜ₋₁ with s = 0.5
  for (size_t i = 0; i < streamed.frames.size(); ++i) {
    const v1::Frame& frame = streamed.frames[i];
    ASSERT_EQ(frame.index(), static_cast<int>(i));
    EXPECT_NEAR(frame.time(), samples[i].time(), 1e-6);
    ASSERT_EQ(frame.rotations_size(), 22);
    // The solved wrists land near the tracked ones (the database holds walks like this one).
    EXPECT_LT(frame.diagnostics().left_wrist_error(), 0.10) << "frame " << i;
    // The frame reports the smoothed wrists it was solved for.
    const v1::Vec3& x = samples[i].left();
    smoothed.set_x(0.5 * x.x() + 0.5 * smoothed.x());
    smoothed.set_y(0.5 * x.y() + 0.5 * smoothed.y());
    smoothed.set_z(0.5 * x.z() + 0.5 * smoothed.z());
    EXPECT_LT(Distance(frame.left_wrist(), smoothed), 0.002) << "frame " << i;
    // Every frame says how sure it is of each landmark (docs/method.md "Confidence"): in metres,
    // the wrists, which the input holds, surer than the ankles, which it does not.
    ASSERT_TRUE(frame.has_expected_error()) << "frame " << i;
    EXPECT_GT(frame.expected_error().left_wrist(), 0.0f);
    EXPECT_LT(frame.expected_error().left_wrist(), frame.expected_error().left_ankle()) << "frame " << i;
    EXPECT_LT(frame.expected_error().right_ankle(), 1.0f) << "frame " << i;
  }
  EXPECT_GT(streamed.started.skeleton().landmarks().left_knee(), 0);

  auto unary = client->ReconstructTrajectory(config, samples);
  ASSERT_TRUE(unary.ok()) << unary.status();
  ASSERT_EQ(unary->frames_size(), static_cast<int>(samples.size()));
  for (size_t i = 0; i < samples.size(); ++i) {
    EXPECT_LT(Distance(unary->frames(static_cast<int>(i)).root_position(), streamed.frames[i].root_position()), 1e-5);
  }
}

TEST_F(ReconstructionServiceTest, RefusedSamplesAreReportedAndTheSessionGoesOn) {
  StartServer();
  auto client = Connect(keys_["acme"]);
  ImportWalks(*client);
  std::vector<v1::WristSample> samples = QueryWrists(30);
  samples[10].mutable_left()->set_x(std::numeric_limits<float>::quiet_NaN());
  samples[20].set_time(samples[19].time() - 0.01);  // backwards
  Streamed streamed = Stream(*client, Config(0), samples);
  ASSERT_TRUE(streamed.summary.ok()) << streamed.summary.status();
  ASSERT_EQ(streamed.rejected.size(), 2u);
  EXPECT_EQ(streamed.rejected[0].sample_index(), 10);
  EXPECT_EQ(streamed.rejected[1].sample_index(), 20);
  EXPECT_EQ(streamed.summary->rejected_samples(), 2);
  EXPECT_EQ(streamed.frames.size(), samples.size());  // the two gaps are bridged on the 30 Hz grid

  v1::SessionConfig strict = Config(0);
  strict.set_strict(true);
  Streamed refused = Stream(*client, strict, samples);
  EXPECT_EQ(refused.summary.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(refused.summary.status().message().find("sample 10"), std::string::npos) << refused.summary.status();
}

// A tracker that did not update sends its last positions again: the summary counts them, and at
// lag 0 every frame still comes out by the end (those that waited for the next new position too).
TEST_F(ReconstructionServiceTest, RepeatedSamplesAreCountedAndEveryFrameComes) {
  StartServer();
  auto client = Connect(keys_["acme"]);
  ImportWalks(*client);
  std::vector<v1::WristSample> samples = QueryWrists(30);
  for (int i : {5, 6, 17, 29}) *samples[i].mutable_left() = samples[i - 1].left();  // 29: the last
  *samples[12].mutable_right() = samples[11].right();
  Streamed streamed = Stream(*client, Config(0), samples);
  ASSERT_TRUE(streamed.summary.ok()) << streamed.summary.status();
  EXPECT_EQ(streamed.summary->repeated_hand_samples(), 5);
  EXPECT_EQ(streamed.summary->rejected_samples(), 0);
  ASSERT_EQ(streamed.frames.size(), samples.size());
  for (size_t f = 0; f < streamed.frames.size(); ++f) EXPECT_EQ(streamed.frames[f].frame_in_segment(), f);
}

TEST_F(ReconstructionServiceTest, BadSessionsGetClearErrors) {
  StartServer();
  auto acme = Connect(keys_["acme"]);
  ImportWalks(*acme);
  ASSERT_TRUE(acme->CreateDatabase("empty").ok());
  auto other = Connect(keys_["other"]);
  v1::SessionConfig config = Config();

  EXPECT_EQ(other->OpenReconstruction(config).status().code(), absl::StatusCode::kNotFound);  // another tenant's
  auto nobody = Client::Connect(server_->address(), {});
  EXPECT_EQ((*nobody)->OpenReconstruction(config).status().code(), absl::StatusCode::kUnauthenticated);
  config.set_database("missing");
  EXPECT_EQ(acme->OpenReconstruction(config).status().code(), absl::StatusCode::kNotFound);
  config.set_database("empty");
  EXPECT_EQ(acme->OpenReconstruction(config).status().code(), absl::StatusCode::kFailedPrecondition);
  config = Config();
  config.mutable_overrides()->set_ankle_candidates(0);
  auto bad = acme->OpenReconstruction(config);
  EXPECT_EQ(bad.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(bad.status().message().find("ankle_candidates"), std::string::npos) << bad.status();
  config = Config();
  config.set_performer_height(-1);
  EXPECT_EQ(acme->OpenReconstruction(config).status().code(), absl::StatusCode::kInvalidArgument);

  // Samples before the config, on the raw stub.
  const grpc::Status status = testing::SamplesBeforeConfig(server_->address(), keys_["acme"], QueryWrists(2).front());
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("config"), std::string::npos) << status.error_message();
}

// The server reads messages as bytes (server/samples_reader.h): samples in the form protobuf
// merges (a second samples field) are all taken, and a malformed sample ends the call naming it.
TEST_F(ReconstructionServiceTest, SamplesAreTakenInEveryWireFormAndAMalformedOneIsNamed) {
  StartServer();
  auto client = Connect(keys_["acme"]);
  ImportWalks(*client);
  const std::vector<v1::WristSample> wrists = QueryWrists(30);
  v1::ReconstructRequest config;
  *config.mutable_config() = Config(0);

  // 20 samples as the message's field, the last 10 in a second samples field after it.
  v1::ReconstructRequest split;
  for (int i = 0; i < 20; ++i) *split.mutable_samples()->add_samples() = wrists[i];
  v1::WristSamples rest;
  for (int i = 20; i < 30; ++i) *rest.add_samples() = wrists[i];
  split.GetReflection()->MutableUnknownFields(&split)->AddLengthDelimited(v1::ReconstructRequest::kSamplesFieldNumber,
                                                                          rest.SerializeAsString());
  const testing::RawOutcome merged = testing::SendRaw(server_->address(), keys_["acme"], {config, split});
  ASSERT_TRUE(merged.status.ok()) << merged.status.error_message();
  EXPECT_EQ(merged.frames, 30);

  // Five samples, then one whose bytes are no WristSample (a group's tag).
  v1::ReconstructRequest bad;
  for (int i = 0; i < 5; ++i) *bad.mutable_samples()->add_samples() = wrists[i];
  v1::WristSamples* samples = bad.mutable_samples();
  samples->GetReflection()->MutableUnknownFields(samples)->AddLengthDelimited(v1::WristSamples::kSamplesFieldNumber,
                                                                              "\x0b");
  const testing::RawOutcome malformed = testing::SendRaw(server_->address(), keys_["acme"], {config, bad});
  EXPECT_EQ(malformed.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(malformed.status.error_message().find("malformed at its sample 5"), std::string::npos)
      << malformed.status.error_message();

  // A message of no bytes at all: no field set.
  const testing::RawOutcome empty = testing::SendRaw(server_->address(), keys_["acme"], {config, {}});
  EXPECT_EQ(empty.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(empty.status.error_message().find("empty request"), std::string::npos) << empty.status.error_message();
}

// ReconstructTrajectory is read as bytes too: a request in the wire form protobuf merges (samples
// in two fields) is taken whole, and bytes that are no request end the call with INVALID_ARGUMENT
// naming what they should have been (before, gRPC's own parse failed it with a bare INTERNAL).
TEST_F(ReconstructionServiceTest, AWholeTrajectoryIsReadAsBytesAndAMalformedOneIsNamed) {
  StartServer();
  auto client = Connect(keys_["acme"]);
  ImportWalks(*client);
  const std::vector<v1::WristSample> wrists = QueryWrists(30);
  v1::ReconstructTrajectoryRequest request;
  *request.mutable_config() = Config(0);
  for (int i = 0; i < 20; ++i) *request.add_samples() = wrists[i];
  std::string bytes = request.SerializeAsString();
  v1::ReconstructTrajectoryRequest rest;
  for (int i = 20; i < 30; ++i) *rest.add_samples() = wrists[i];
  bytes += rest.SerializeAsString();  // a second run of the repeated field: protobuf appends it
  v1::ReconstructTrajectoryResponse answer;
  const grpc::Status merged = testing::CallTrajectoryRaw(server_->address(), keys_["acme"], bytes, &answer);
  ASSERT_TRUE(merged.ok()) << merged.error_message();
  EXPECT_EQ(answer.frames_size(), 30);
  EXPECT_TRUE(answer.has_summary());

  const grpc::Status malformed = testing::CallTrajectoryRaw(server_->address(), keys_["acme"], bytes + "\x0b", &answer);
  EXPECT_EQ(malformed.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(malformed.error_message().find("ReconstructTrajectoryRequest"), std::string::npos)
      << malformed.error_message();
  // Nobody's key: refused before a byte of the request is read.
  EXPECT_EQ(testing::CallTrajectoryRaw(server_->address(), "", bytes + "\x0b", &answer).error_code(),
            grpc::StatusCode::UNAUTHENTICATED);
}

TEST_F(ReconstructionServiceTest, LimitsOnSessionsAndIdleTime) {
  StartServer({"--max-sessions-per-tenant", "1", "--idle-seconds", "0.5"});
  auto client = Connect(keys_["acme"]);
  ImportWalks(*client);
  const auto opened_at = std::chrono::steady_clock::now();
  auto first = client->OpenReconstruction(Config(0));
  ASSERT_TRUE(first.ok()) << first.status();
  auto second = client->OpenReconstruction(Config(0));
  EXPECT_EQ(second.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_NE(second.status().message().find("reconstruction sessions"), std::string::npos) << second.status();
  // The first one says nothing: the server ends it once the idle limit has passed. Wait for that
  // end itself (not a sleep guessing how long the server takes), and check it was not earlier.
  EXPECT_EQ(testing::RepliesUntilTheCallEnds(**first), 0) << "a silent session was not ended by the server";
  EXPECT_GE(std::chrono::steady_clock::now() - opened_at, std::chrono::milliseconds(500));
  auto summary = (*first)->Finish();
  EXPECT_EQ(summary.status().code(), absl::StatusCode::kDeadlineExceeded) << summary.status();
  // Its place is free again.
  auto third = client->OpenReconstruction(Config(0));
  ASSERT_TRUE(third.ok()) << third.status();
  EXPECT_TRUE((*third)->Finish().ok());
}

// The server's `mocap_frames_reconstructed_total` counter.
long FramesReconstructed(Client& client) {
  auto metrics = client.GetMetrics();
  if (!metrics.ok()) return -1;
  const std::string name = "mocap_frames_reconstructed_total ";
  const size_t at = metrics->find("\n" + name);
  return at == std::string::npos ? -1 : std::stol(metrics->substr(at + 1 + name.size()));
}

TEST_F(ReconstructionServiceTest, AClientThatDoesNotReadHoldsTheSessionBack) {
  StartServer();
  auto client = Connect(keys_["acme"]);
  ImportWalks(*client);
  const std::vector<v1::WristSample> walk = QueryWrists(60);
  auto stream = client->OpenReconstruction(Config(0));
  ASSERT_TRUE(stream.ok()) << stream.status();
  // 40,000 samples in messages of 100 (~2 MB: the transport takes them all), each answered by a
  // frame (~28 MB of replies), and the client does not read. The server reads the next message
  // only once its replies are written, so it stops working once the reply windows are full,
  // instead of reconstructing everything into memory.
  constexpr int kMessages = 400, kPerMessage = 100;
  std::atomic<int> written{0};
  std::thread writer([&] {
    for (int m = 0; m < kMessages; ++m) {
      std::vector<v1::WristSample> samples;
      for (int i = m * kPerMessage; i < (m + 1) * kPerMessage; ++i) {
        samples.push_back(walk[i % walk.size()]);
        samples.back().set_time(i / 30.0);
      }
      if (!(*stream)->Write(samples).ok()) return;
      ++written;
    }
  });
  long frames_before = -1, frames_held = FramesReconstructed(*client);
  for (int second = 0; second < 30 && frames_held != frames_before; ++second) {  // until it settles
    // A sleep on purpose: what is checked is that nothing happens (the counter stops moving), and
    // only time passing can show that; there is no event for "the server has stopped".
    std::this_thread::sleep_for(std::chrono::seconds(1));
    frames_before = frames_held;
    frames_held = FramesReconstructed(*client);
  }
  EXPECT_GE(frames_held, 0);
  EXPECT_LT(frames_held, kMessages * kPerMessage / 2) << "the server went on although nothing was read";
  // Reading again lets the session go on to the end, every frame delivered.
  long frames = 0;
  std::thread reader([&] {
    while (true) {
      auto reply = (*stream)->Read();
      if (!reply.ok() || !*reply) return;
      frames += (*reply)->frames().frames_size();
    }
  });
  writer.join();
  ASSERT_EQ(written.load(), kMessages);
  ASSERT_TRUE((*stream)->CloseInput().ok());
  reader.join();
  auto summary = (*stream)->Finish();
  ASSERT_TRUE(summary.ok()) << summary.status();
  EXPECT_EQ(frames, kMessages * kPerMessage);
  std::cout << "[ backpressure ] the server held at " << frames_held << " of " << kMessages * kPerMessage
            << " frames while the client did not read\n";
}

TEST_F(ReconstructionServiceTest, AClientVanishingMidStreamFreesItsSession) {
  StartServer({"--max-sessions-per-tenant", "1"});
  auto client = Connect(keys_["acme"]);
  ImportWalks(*client);
  const std::vector<v1::WristSample> samples = QueryWrists(30);
  {
    auto stream = client->OpenReconstruction(Config(0));
    ASSERT_TRUE(stream.ok()) << stream.status();
    ASSERT_TRUE((*stream)->Write({samples.begin(), samples.begin() + 10}).ok());
    (*stream)->Cancel();
  }  // destroyed without Finish
  // The server notices and frees the tenant's only session slot. It does so in its own process,
  // with no event this client can wait on, so the test retries (polling, 100 ms apart, for up to
  // 5 s: the bound is what is checked).
  absl::Status opened = absl::UnknownError("not tried");
  for (int attempt = 0; attempt < 50 && !opened.ok(); ++attempt) {
    auto stream = client->OpenReconstruction(Config(0));
    opened = stream.status();
    if (!opened.ok()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_TRUE(opened.ok()) << opened;
  auto metrics = client->GetMetrics();
  ASSERT_TRUE(metrics.ok());
  EXPECT_NE(metrics->find("mocap_sessions_total 2"), std::string::npos) << *metrics;
}

TEST_F(ReconstructionServiceTest, NewSessionsSeeImportsWhileRunningOnesKeepTheirVersion) {
  StartServer();
  auto client = Connect(keys_["acme"]);
  ImportWalks(*client);
  const std::vector<v1::WristSample> samples = QueryWrists(30);
  auto before = client->OpenReconstruction(Config(0));
  ASSERT_TRUE(before.ok()) << before.status();
  EXPECT_EQ((*before)->started().database_frames(), 360);
  ASSERT_TRUE((*before)->Write({samples.begin(), samples.begin() + 15}).ok());

  auto more = client->ImportFiles("walks", {WriteClip("walk200.bvh", 200)});
  ASSERT_TRUE(more.ok()) << more.status();
  auto after = client->OpenReconstruction(Config(0));
  ASSERT_TRUE(after.ok()) << after.status();
  EXPECT_EQ((*after)->started().database_frames(), 560);

  ASSERT_TRUE((*before)->Write({samples.begin() + 15, samples.end()}).ok());
  auto summary = (*before)->Finish();
  ASSERT_TRUE(summary.ok()) << summary.status();
  EXPECT_EQ(summary->frames(), 30);
  EXPECT_TRUE((*after)->Finish().ok());
}

TEST_F(ReconstructionServiceTest, PerformerHeightScalesTheWholeSession) {
  StartServer();
  auto client = Connect(keys_["acme"]);
  ImportWalks(*client);
  const std::vector<v1::WristSample> samples = QueryWrists(30);
  Streamed plain = Stream(*client, Config(0), samples);
  ASSERT_TRUE(plain.summary.ok()) << plain.summary.status();

  // The same motion by a performer 1.5 times as tall: wrists 1.5 times as far from the origin.
  const float factor = 1.5f;
  std::vector<v1::WristSample> tall = samples;
  for (v1::WristSample& s : tall) {
    for (v1::Vec3* v : {s.mutable_left(), s.mutable_right()}) {
      v->set_x(v->x() * factor);
      v->set_y(v->y() * factor);
      v->set_z(v->z() * factor);
    }
  }
  v1::SessionConfig config = Config(0);
  config.set_performer_height(plain.started.database_height() * factor);
  Streamed scaled = Stream(*client, config, tall);
  ASSERT_TRUE(scaled.summary.ok()) << scaled.summary.status();
  EXPECT_NEAR(scaled.started.skeleton().joints(2).offset().y(),
              plain.started.skeleton().joints(2).offset().y() * factor, 1e-4);
  ASSERT_EQ(scaled.frames.size(), plain.frames.size());
  for (size_t i = 0; i < plain.frames.size(); ++i) {
    EXPECT_NEAR(scaled.frames[i].pelvis_position().y(), plain.frames[i].pelvis_position().y() * factor, 2e-3) << i;
    // Expected errors are lengths: the taller body's are as much larger.
    EXPECT_NEAR(scaled.frames[i].expected_error().pelvis(), plain.frames[i].expected_error().pelvis() * factor,
                0.2 * plain.frames[i].expected_error().pelvis() * factor)
        << i;
  }
}

// Issue #12: a session on the caller's rig answers with that rig (joint order, names) and its
// size: a body 1.25 times as large in inches, Z up, with fingers and toes, has its pelvis 1.25
// times as far from the origin as the database rig's; what is not a rig is refused.
TEST_F(ReconstructionServiceTest, ATargetRigAnswersEveryFrameOnThatRig) {
  StartServer();
  auto client = Connect(keys_["acme"]);
  ImportWalks(*client);
  const std::vector<v1::WristSample> samples = QueryWrists(30);
  Streamed plain = Stream(*client, Config(0), samples);
  ASSERT_TRUE(plain.summary.ok()) << plain.summary.status();

  const BvhClip avatar =
      testing::MakeWalkingClip({.z_up = true, .fingers_and_toes = true, .length_scale = 1.25 / 2.54}, 10);
  v1::SessionConfig config = Config(0);
  config.mutable_target_rig()->set_bvh(FormatBvh(avatar));
  Streamed on_avatar = Stream(*client, config, samples);
  ASSERT_TRUE(on_avatar.summary.ok()) << on_avatar.summary.status();
  ASSERT_EQ(on_avatar.started.skeleton().joints_size(), avatar.skeleton.num_joints());
  for (int j = 0; j < avatar.skeleton.num_joints(); ++j) {
    EXPECT_EQ(on_avatar.started.skeleton().joints(j).name(), avatar.skeleton.joint(j).name);
  }
  EXPECT_FALSE(on_avatar.started.config().has_target_rig());  // no echo of the rig's text
  ASSERT_EQ(on_avatar.frames.size(), plain.frames.size());
  for (size_t i = 0; i < plain.frames.size(); ++i) {
    ASSERT_EQ(on_avatar.frames[i].rotations_size(), avatar.skeleton.num_joints());
    EXPECT_NEAR(on_avatar.frames[i].pelvis_position().y(), plain.frames[i].pelvis_position().y() * 1.25, 2e-3) << i;
    EXPECT_NEAR(on_avatar.frames[i].pelvis_position().z(), plain.frames[i].pelvis_position().z() * 1.25, 2e-3) << i;
  }

  config.mutable_target_rig()->set_bvh("HIERARCHY\nROOT Hips\n{\n");
  auto bad = client->OpenReconstruction(config);
  EXPECT_EQ(bad.status().code(), absl::StatusCode::kInvalidArgument) << bad.status();
  config.mutable_target_rig()->set_unit("furlong");
  bad = client->OpenReconstruction(config);
  EXPECT_EQ(bad.status().code(), absl::StatusCode::kInvalidArgument) << bad.status();
  EXPECT_NE(bad.status().message().find("target_rig.unit"), std::string::npos) << bad.status();
  config.mutable_target_rig()->clear_unit();
  for (int j = 0; j < 4; ++j) {  // a chain of bones: no body
    v1::TargetJoint* joint = config.mutable_target_rig()->mutable_joints()->add_joints();
    joint->set_name("bone" + std::to_string(j));
    joint->set_parent(j - 1);
    joint->mutable_offset()->set_y(j == 0 ? 0 : 10);
  }
  bad = client->OpenReconstruction(config);
  EXPECT_EQ(bad.status().code(), absl::StatusCode::kFailedPrecondition) << bad.status();
}

TEST_F(ReconstructionServiceTest, ShutdownEndsLiveSessionsAfterTheirFrames) {
  StartServer({"--drain-seconds", "5"});
  auto client = Connect(keys_["acme"]);
  ImportWalks(*client);
  const std::vector<v1::WristSample> samples = QueryWrists(30);
  auto stream = client->OpenReconstruction(Config(/*lag=*/10));
  ASSERT_TRUE(stream.ok()) << stream.status();
  ASSERT_TRUE((*stream)->Write(samples).ok());
  // The 30 samples are processed and their 20 frames decided before the stop.
  std::vector<v1::Frame> frames;
  while (frames.size() < 20) {
    auto reply = (*stream)->Read();
    ASSERT_TRUE(reply.ok() && *reply);
    for (const v1::Frame& frame : (*reply)->frames().frames()) frames.push_back(frame);
  }
  std::thread stopper([&] { EXPECT_EQ(server_->Stop(), 0); });
  // Reads on without closing the input: the server ends the session, not the client.
  while (true) {
    auto reply = (*stream)->Read();
    if (!reply.ok() || !*reply) break;
    for (const v1::Frame& frame : (*reply)->frames().frames()) frames.push_back(frame);
  }
  auto summary = (*stream)->Finish();
  stopper.join();
  EXPECT_EQ(summary.status().code(), absl::StatusCode::kUnavailable) << summary.status();
  EXPECT_EQ(frames.size(), samples.size());  // the lagged frames were flushed before the end
}

}  // namespace
}  // namespace mocap
