// Issue #14 (hardening), findings 1–8 against a real `mocapd serve` on loopback, through the SDK
// and the raw stubs where a test must misbehave. Each test failed before its fix.
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <latch>
#include <limits>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "client/wrist_input/wrist_source.h"
#include "mocap/v1/motion_store.grpc.pb.h"
#include "mocap/v1/reconstruction.grpc.pb.h"
#include "tests/support/raw_reconstruct.h"
#include "tests/support/server_fixture.h"
#include "tests/support/stream_events.h"

namespace mocap {
namespace {

using Clock = std::chrono::steady_clock;
using client::Client;

class ServiceRegressionTest : public testing::ServerFixture {
 protected:
  // A database with enough frames that K1 = 1000 (the default) costs real compute per frame.
  void ImportLongWalks(Client& client) {
    std::vector<std::filesystem::path> files;
    for (int frames : {600, 700, 800}) files.push_back(WriteClip("long" + std::to_string(frames) + ".bvh", frames));
    auto imported = client.ImportFiles("walks", files);
    ASSERT_TRUE(imported.ok()) << imported.status();
  }
  // `count` samples at 30 Hz: a walk's wrists, repeated.
  std::vector<v1::WristSample> Samples(int count) {
    auto walk = WristsFromBvh(WriteClip("query.bvh", 90), 0.0, 1);
    EXPECT_TRUE(walk.ok()) << walk.status();
    std::vector<v1::WristSample> samples(count);
    for (int i = 0; i < count; ++i) {
      samples[i] = (*walk)[i % walk->size()];
      samples[i].set_time(i / 30.0);
    }
    return samples;
  }
  static v1::SessionConfig Config(int lag = -1) {
    v1::SessionConfig config;
    config.set_database("walks");
    if (lag >= 0) config.mutable_fixed_lag()->set_lag_frames(lag);
    return config;
  }
  double Metric(Client& client, const std::string& name) {
    auto text = client.GetMetrics();
    EXPECT_TRUE(text.ok()) << text.status();
    std::istringstream lines(*text);
    for (std::string line; std::getline(lines, line);) {
      if (line.rfind(name + " ", 0) == 0) return std::stod(line.substr(name.size() + 1));
    }
    ADD_FAILURE() << "no metric " << name;
    return -1;
  }
  // mocap_sessions_active once it is 0, or after 5 s. Polls: the sessions end in the server's
  // process, with no event this client can wait on; the 5 s bound is what the callers check.
  double ActiveSessionsAfterWaiting(Client& client) {
    double active = -1;
    for (int i = 0; i < 100; ++i) {
      active = Metric(client, "mocap_sessions_active");
      if (active == 0) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return active;
  }
  // Streams `samples` one per message at full speed; the session's wall time in seconds.
  static double TimedSession(Client& client, const v1::SessionConfig& config,
                             const std::vector<v1::WristSample>& samples, size_t* frames) {
    const Clock::time_point start = Clock::now();
    auto stream = client.OpenReconstruction(config);
    EXPECT_TRUE(stream.ok()) << stream.status();
    if (!stream.ok()) return 1e9;
    for (const v1::WristSample& sample : samples) EXPECT_TRUE((*stream)->Write({sample}).ok());
    *frames = 0;
    auto summary =
        (*stream)->Finish([&](const v1::ReconstructResponse& reply) { *frames += reply.frames().frames_size(); });
    EXPECT_TRUE(summary.ok()) << summary.status();
    return std::chrono::duration<double>(Clock::now() - start).count();
  }
  std::string ServerLog() {
    std::ifstream in(dir_ / "server.log");
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  // The log once it holds every one of `lines` (a session's end line is written after its count
  // drops), or as it is after 10 s. Polls the file: the server is another process.
  std::string ServerLogOnceItHas(const std::vector<std::string>& lines) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (true) {
      std::string log = ServerLog();
      const bool all = std::all_of(lines.begin(), lines.end(),
                                   [&](const std::string& line) { return log.find(line) != std::string::npos; });
      if (all || std::chrono::steady_clock::now() > deadline) return log;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
};

// Finding 1: a cancelled session kept computing its whole message (~50 s) and the tenant's next
// sessions, and every other tenant's, waited behind it.
TEST_F(ServiceRegressionTest, CancelledSessionsStopComputingAtOnce) {
  StartServer();
  auto acme = Connect(keys_["acme"]);
  ImportLongWalks(*acme);
  auto other = Connect(keys_["other"]);
  ImportLongWalks(*other);
  const std::vector<v1::WristSample> flood = Samples(25'000);  // ~1.1 MB, under the 4 MiB limit
  std::vector<std::unique_ptr<client::ReconstructionStream>> streams;
  for (const v1::SessionConfig& config : {Config(/*lag=*/0), Config()}) {
    auto stream = acme->OpenReconstruction(config);
    ASSERT_TRUE(stream.ok()) << stream.status();
    ASSERT_TRUE((*stream)->Write(flood).ok());
    streams.push_back(std::move(*stream));
  }
  // Cancel while the flood is being computed: once the fixed-lag session has answered (its first
  // replies come from the first task of its 25,000 samples). The whole-trajectory session answers
  // only at its end, but its tasks share the tenant's queue with the first one's, turn about.
  ASSERT_TRUE(testing::NextReply(*streams[0]).has_value()) << "the flood was not computed";
  for (auto& stream : streams) stream->Cancel();
  // Both sessions end within a frame's work, not when their 25,000 samples are done.
  EXPECT_EQ(ActiveSessionsAfterWaiting(*acme), 0) << "cancelled sessions still computing 5 s after the cancel";
  size_t frames = 0;
  const double seconds = TimedSession(*other, Config(0), Samples(150), &frames);
  EXPECT_EQ(frames, 150u);
  EXPECT_LT(seconds, 20.0) << "another tenant's 150-sample session waited for the cancelled work";
  for (auto& stream : streams) EXPECT_EQ(stream->Finish().status().code(), absl::StatusCode::kCancelled);
}

// Finding 1: one tenant's large messages held both compute threads until done; they are now cut
// into short tasks, shared round robin between tenants.
TEST_F(ServiceRegressionTest, OneTenantsFloodDoesNotStallAnother) {
  StartServer();
  auto acme = Connect(keys_["acme"]);
  ImportLongWalks(*acme);
  auto other = Connect(keys_["other"]);
  ImportLongWalks(*other);
  const std::vector<v1::WristSample> flood = Samples(25'000);
  std::vector<std::unique_ptr<client::ReconstructionStream>> streams;
  std::vector<std::thread> readers;
  std::latch computing(4);  // each flood session has answered once: all four are being computed
  for (int i = 0; i < 4; ++i) {
    auto stream = acme->OpenReconstruction(Config(/*lag=*/0));
    ASSERT_TRUE(stream.ok()) << stream.status();
    ASSERT_TRUE((*stream)->Write(flood).ok());
    client::ReconstructionStream* s = stream->get();
    readers.emplace_back([s, &computing] {
      bool counted = false;
      while (true) {
        auto reply = s->Read();
        if (!counted) {  // also when the call ended without a reply: the test must not hang
          computing.count_down();
          counted = true;
        }
        if (!reply.ok() || !*reply) return;
      }
    });
    streams.push_back(std::move(*stream));
  }
  computing.wait();
  size_t frames = 0;
  const double seconds = TimedSession(*other, Config(0), Samples(60), &frames);
  EXPECT_EQ(frames, 60u);
  // Before: the 60 samples waited for 4 × 25,000 frames of acme's (minutes).
  EXPECT_LT(seconds, 20.0) << "the victim's session took " << seconds << " s beside the flood";
  for (auto& stream : streams) stream->Cancel();
  for (std::thread& reader : readers) reader.join();
}

// Finding 1: the unary call computed the whole trajectory in one task, even for a client gone.
TEST_F(ServiceRegressionTest, CancelledUnaryCallStopsComputing) {
  StartServer();
  auto acme = Connect(keys_["acme"]);
  ImportLongWalks(*acme);
  const auto start = Clock::now();
  auto result = acme->ReconstructTrajectory(Config(0), Samples(25'000), std::chrono::milliseconds(1500));
  EXPECT_EQ(result.status().code(), absl::StatusCode::kDeadlineExceeded) << result.status();
  EXPECT_EQ(ActiveSessionsAfterWaiting(*acme), 0) << "the expired call still computes";
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 20.0);
}

// Finding 2: ImportStart.frame_rate = 1e9 crashed the server (a multi-GB resampling allocation).
TEST_F(ServiceRegressionTest, AbsurdFrameRatesAreRefusedBeforeAnyWork) {
  StartServer();
  auto acme = Connect(keys_["acme"]);
  const std::filesystem::path clip = WriteClip("walk.bvh", 60);
  for (double rate : {1e9, 1e5, 1001.0, 0.5, -30.0, std::numeric_limits<double>::quiet_NaN()}) {
    auto imported = acme->ImportFiles("fast", {clip}, {.frame_rate = rate});
    EXPECT_EQ(imported.status().code(), absl::StatusCode::kInvalidArgument) << rate << ": " << imported.status();
    EXPECT_NE(imported.status().message().find("[1, 1000]"), std::string::npos) << imported.status();
    auto created = acme->CreateDatabase("fast", rate);
    EXPECT_EQ(created.status().code(), absl::StatusCode::kInvalidArgument) << rate << ": " << created.status();
  }
  auto databases = acme->ListDatabases();  // the server is alive and nothing was stored
  ASSERT_TRUE(databases.ok()) << databases.status();
  EXPECT_TRUE(databases->empty());
  EXPECT_TRUE(acme->ImportFiles("fast", {clip}, {.frame_rate = 120}).ok());
}

// Finding 3: a label with a newline forged a whole log line; a 100 KB label was logged in full.
TEST_F(ServiceRegressionTest, ClientStringsCannotForgeOrFloodLogLines) {
  StartServer();
  auto acme = Connect(keys_["acme"]);
  ImportLongWalks(*acme);
  for (const std::string& label : {std::string("app\ninfo: request=999 method=DeleteDatabase tenant=other code=OK"),
                                   std::string(100'000, 'x'), std::string("\x1b[2J\x1b[31mred")}) {
    v1::SessionConfig config = Config(0);
    config.set_client_label(label);
    size_t frames = 0;
    TimedSession(*acme, config, Samples(5), &frames);
  }
  const std::string log = ServerLog();
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    EXPECT_NE(line.rfind("info: request=999", 0), 0u) << "forged line: " << line;
    EXPECT_LT(line.size(), 2000u) << line.substr(0, 200);
    EXPECT_EQ(line.find('\x1b'), std::string::npos) << "raw escape character logged";
  }
  EXPECT_NE(log.find("app\\ninfo: request=999"), std::string::npos);
}

// Finding 4: a NUL in an import file name was echoed with the NUL but stored cut at it.
TEST_F(ServiceRegressionTest, FileNamesWithControlCharactersAreRefused) {
  StartServer();
  auto stub = v1::MotionStore::NewStub(grpc::CreateChannel(server_->address(), grpc::InsecureChannelCredentials()));
  grpc::ClientContext context;
  context.AddMetadata("authorization", "Bearer " + keys_["acme"]);
  v1::ImportBvhResponse response;
  auto writer = stub->ImportBvh(&context, &response);
  v1::ImportBvhRequest start;
  start.mutable_start()->set_database("walks");
  ASSERT_TRUE(writer->Write(start));
  std::ifstream in(WriteClip("walk.bvh", 40));
  v1::ImportBvhRequest chunk;
  chunk.mutable_chunk()->set_file_name(std::string("walk\0evil.bvh", 13));
  chunk.mutable_chunk()->set_data(std::string(std::istreambuf_iterator<char>(in), {}));
  chunk.mutable_chunk()->set_end_of_file(true);
  writer->Write(chunk);
  writer->WritesDone();
  const grpc::Status status = writer->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << status.error_message();
  EXPECT_EQ(status.error_message().find('\0'), std::string::npos);
  auto databases = Connect(keys_["acme"])->ListDatabases();
  ASSERT_TRUE(databases.ok());
  EXPECT_TRUE(databases->empty());
}

// Finding 5: time = +inf ended the session; absurd positions and confidences were reconstructed.
TEST_F(ServiceRegressionTest, NonFiniteAndAbsurdSamplesAreRefusedOneByOne) {
  StartServer();
  auto acme = Connect(keys_["acme"]);
  ImportLongWalks(*acme);
  std::vector<v1::WristSample> samples = Samples(40);
  samples[10].set_time(std::numeric_limits<double>::infinity());
  samples[12].mutable_left()->set_x(1e9);
  samples[14].set_left_confidence(1e30f);
  samples[16].set_right_confidence(-5.0f);
  samples[18].mutable_right()->set_y(std::numeric_limits<double>::quiet_NaN());
  samples[20].mutable_right()->set_x(samples[20].left().x() + 50.0);  // 50 m apart: not one person
  auto stream = acme->OpenReconstruction(Config(0));
  ASSERT_TRUE(stream.ok()) << stream.status();
  for (const v1::WristSample& sample : samples) ASSERT_TRUE((*stream)->Write({sample}).ok());
  std::vector<long> rejected;
  std::vector<v1::Frame> frames;
  auto summary = (*stream)->Finish([&](const v1::ReconstructResponse& reply) {
    if (reply.has_rejected()) rejected.push_back(reply.rejected().sample_index());
    for (const v1::Frame& frame : reply.frames().frames()) frames.push_back(frame);
  });
  ASSERT_TRUE(summary.ok()) << summary.status();  // the session went on
  EXPECT_EQ(rejected, (std::vector<long>{10, 12, 14, 16, 18, 20}));
  ASSERT_FALSE(frames.empty());
  for (const v1::Frame& frame : frames) {
    EXPECT_LT(std::abs(frame.pelvis_position().x()), 10.0) << "frame " << frame.index();
  }
}

// Finding 5: a BVH with a 1e30 position value imported.
TEST_F(ServiceRegressionTest, BvhWithAbsurdPositionsIsRefused) {
  StartServer();
  auto acme = Connect(keys_["acme"]);
  std::ifstream in(WriteClip("walk.bvh", 40));
  std::string text(std::istreambuf_iterator<char>(in), {});
  const size_t motion = text.find("Frame Time:");
  const size_t first_value = text.find('\n', motion) + 1;
  text.replace(first_value, text.find(' ', first_value) - first_value, "1e30");
  auto imported = acme->ImportFiles("walks", {WriteText("huge.bvh", text)});
  EXPECT_EQ(imported.status().code(), absl::StatusCode::kInvalidArgument) << imported.status();
  EXPECT_NE(imported.status().message().find("huge.bvh"), std::string::npos) << imported.status();
}

// Finding 6: a 10,000-character database name was looked up and echoed into the error.
TEST_F(ServiceRegressionTest, OversizedDatabaseNamesAreRefusedWithoutEcho) {
  StartServer();
  auto acme = Connect(keys_["acme"]);
  const std::string name(10'000, 'd');
  v1::SessionConfig config;
  config.set_database(name);
  auto stream = acme->OpenReconstruction(config);
  ASSERT_FALSE(stream.ok());
  EXPECT_EQ(stream.status().code(), absl::StatusCode::kInvalidArgument) << stream.status().message().substr(0, 200);
  EXPECT_LT(stream.status().message().size(), 300u);
  auto described = acme->DescribeDatabase(name);
  EXPECT_EQ(described.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_LT(described.status().message().size(), 300u);
}

// Finding 7: a keyless stream was read before authentication (samples first → INVALID_ARGUMENT)
// and 2,000 keyless silent streams were all held until the idle limit.
TEST_F(ServiceRegressionTest, StreamsAreAuthenticatedBeforeAnythingIsRead) {
  StartServer({"--idle-seconds", "60"});
  auto stub = v1::Reconstruction::NewStub(grpc::CreateChannel(server_->address(), grpc::InsecureChannelCredentials()));
  for (const std::string& key : {std::string(), std::string("not-a-key")}) {
    // First message samples: the answer is about the key, not the message order.
    const grpc::Status status = testing::SamplesBeforeConfig(server_->address(), key, Samples(1)[0]);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAUTHENTICATED)
        << "key '" << key << "': " << status.error_message();
    // A silent stream is answered at once, not held until the 60 s idle limit.
    const auto start = Clock::now();
    grpc::ClientContext context;
    if (!key.empty()) context.AddMetadata("authorization", "Bearer " + key);
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(20));
    auto stream = stub->Reconstruct(&context);
    v1::ReconstructResponse reply;
    EXPECT_FALSE(stream->Read(&reply));
    const grpc::Status silent = stream->Finish();
    EXPECT_EQ(silent.error_code(), grpc::StatusCode::UNAUTHENTICATED)
        << "key '" << key << "': " << silent.error_message();
    EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 10.0) << "a keyless silent stream was held";
  }
}

// Finding 8: cancelled sessions never logged their end; the log said "client went away" for
// every cancellation.
TEST_F(ServiceRegressionTest, EverySessionEndIsLoggedWithTheClientsCode) {
  StartServer();
  auto acme = Connect(keys_["acme"]);
  ImportLongWalks(*acme);
  auto stream = acme->OpenReconstruction(Config(0));
  ASSERT_TRUE(stream.ok()) << stream.status();
  ASSERT_TRUE((*stream)->Write(Samples(3'000)).ok());
  // Cancel mid-session: once the server has answered the first samples.
  ASSERT_TRUE(testing::NextReply(**stream).has_value()) << "the session was not computed";
  (*stream)->Cancel();
  EXPECT_EQ((*stream)->Finish().status().code(), absl::StatusCode::kCancelled);
  size_t frames = 0;
  TimedSession(*acme, Config(0), Samples(10), &frames);
  ASSERT_EQ(ActiveSessionsAfterWaiting(*acme), 0);
  const std::string log = ServerLogOnceItHas({"ended code=CANCELLED", "ended code=OK: 10 frames"});
  EXPECT_NE(log.find("ended code=CANCELLED"), std::string::npos) << log;
  EXPECT_NE(log.find("ended code=OK: 10 frames"), std::string::npos) << log;
  EXPECT_EQ(log.find("client went away"), std::string::npos);
}

// Finding 8: a ReconstructTrajectory answer over the message limit failed in the transport after
// the server had logged code=OK.
TEST_F(ServiceRegressionTest, OversizedUnaryAnswersAreRefusedAndLoggedAsSuch) {
  StartServer();
  ImportLongWalks(*Connect(keys_["acme"]));
  StartServer({"--max-message-bytes", "65536"});  // the same store, a small message limit
  auto acme = Connect(keys_["acme"]);
  auto result = acme->ReconstructTrajectory(Config(0), Samples(400));  // ~25 kB in, ~10× that out
  EXPECT_EQ(result.status().code(), absl::StatusCode::kResourceExhausted) << result.status();
  EXPECT_NE(result.status().message().find("Reconstruct"), std::string::npos) << result.status();
  const std::string log = ServerLog();
  std::istringstream lines(log);
  int logged = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.find("method=ReconstructTrajectory") == std::string::npos) continue;
    ++logged;
    EXPECT_NE(line.find("code=RESOURCE_EXHAUSTED"), std::string::npos) << line;
  }
  EXPECT_EQ(logged, 1);
}

}  // namespace
}  // namespace mocap
