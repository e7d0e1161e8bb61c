// The PoseSearch service end to end: a real `mocapd serve` on loopback over a real store file,
// driven through the SDK and the `mocap` CLI, compared with `mocapd similar` on the same store.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "mocap/client.h"
#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/local_motion.h"
#include "tests/support/server_fixture.h"
#include "tools/similar_json/similar_json.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

class PoseSearchServiceTest : public testing::ServerFixture {
 protected:
  void SetUp() override {
    ServerFixture::SetUp();
    StartServer();
    client_ = Connect(keys_["acme"]);
    ImportWalks(*client_);
    // The query: the same walk on another rig (Z-up root, fingers, twist bones, inches, XYZ).
    query_ = WriteClip("query.bvh", 90,
                       {.z_up = true,
                        .fingers_and_toes = true,
                        .twist_bones = true,
                        .length_scale = 1.0 / 2.54,
                        .rotation_order = "XYZ"});
  }
  v1::FindSimilarPosesRequest Request(int first, int last, int step = 1) {
    v1::FindSimilarPosesRequest request;
    request.add_databases("walks");
    *request.mutable_bvh() = client::ReadBvhQuery(query_).value();
    request.mutable_bvh()->set_first_frame(first);
    request.mutable_bvh()->set_last_frame(last);
    request.mutable_bvh()->set_frame_step(step);
    request.set_top_k(3);
    return request;
  }
  struct Run {
    int exit_code = -1;
    std::string out;
  };
  Run Command(const std::string& command) {
    Run run;
    FILE* pipe = popen((command + " 2>>" + (dir_ / "commands.log").string()).c_str(), "r");
    char buffer[4096];
    while (size_t n = fread(buffer, 1, sizeof buffer, pipe)) run.out.append(buffer, n);
    const int status = pclose(pipe);
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return run;
  }
  int IndexBuildsLogged() {
    std::ifstream in(dir_ / "server.log");
    std::string line;
    int builds = 0;
    while (std::getline(in, line))
      builds += line.find("pose index of database") != std::string::npos && line.find(" built ") != std::string::npos;
    return builds;
  }
  std::unique_ptr<client::Client> client_;
  fs::path query_;
};

TEST_F(PoseSearchServiceTest, FindsTheSamePoseOnAnotherRigUnaryAndStreamed) {
  v1::FindSimilarPosesRequest request = Request(20, 60, 20);
  auto response = client_->FindSimilarPoses(request);
  ASSERT_TRUE(response.ok()) << response.status();
  ASSERT_EQ(response->results_size(), 3);
  EXPECT_EQ(response->window(), 1);
  for (const v1::QueryFrameMatches& frame : response->results()) {
    ASSERT_EQ(frame.matches_size(), 3);
    const v1::PoseMatch& best = frame.matches(0);
    // Every database clip holds the same periodic walk (a 30-frame cycle): the same phase is the same pose.
    const int phase = ((best.frame() - frame.query_frame()) % 30 + 30) % 30;
    EXPECT_TRUE(phase <= 1 || phase >= 29) << best.DebugString();
    EXPECT_LT(best.distance(), 0.05);
    EXPECT_EQ(best.database(), "walks");
    EXPECT_EQ(best.file_name().substr(0, 4), "walk");
    EXPECT_LE(best.distance(), frame.matches(1).distance());
    // The database's clips are copies of one walk, so its own frames lie at ~0 from each other:
    // measured against the least yardstick, the query is like them.
    ASSERT_TRUE(frame.has_novelty());
    EXPECT_LT(frame.novelty(), 1.0f);
    EXPECT_FALSE(frame.no_similar_pose());
  }
  EXPECT_EQ(response->results(0).query_frame(), 20);
  EXPECT_EQ(response->results(2).query_frame(), 60);

  // The streamed form: the same answer in parts, in query-frame order.
  request = Request(0, 89);
  auto whole = client_->FindSimilarPoses(request);
  ASSERT_TRUE(whole.ok()) << whole.status();
  v1::FindSimilarPosesResponse collected;
  int parts = 0;
  absl::Status streamed = client_->StreamSimilarPoses(request, [&](const v1::FindSimilarPosesResponse& part) {
    ++parts;
    AppendSimilarResults(part, &collected);
    return true;
  });
  ASSERT_TRUE(streamed.ok()) << streamed;
  EXPECT_GT(parts, 1);
  EXPECT_EQ(collected.SerializeAsString(), whole->SerializeAsString());

  // A reader that stops after the first part cancels the call.
  absl::Status cancelled =
      client_->StreamSimilarPoses(request, [](const v1::FindSimilarPosesResponse&) { return false; });
  EXPECT_EQ(cancelled.code(), absl::StatusCode::kCancelled);
}

TEST_F(PoseSearchServiceTest, PosesSentAsNamedJointPositions) {
  // Frame 20 of the plain synthetic walk, in metres, as named positions (what an app sends).
  const BvhClip clip = testing::MakeWalkingClip({}, 40);
  const GlobalPoses poses =
      ForwardKinematics(clip.skeleton, MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time));
  v1::FindSimilarPosesRequest request;
  request.add_databases("walks");
  for (int frame : {20, 25}) {
    v1::NamedPose* pose = request.mutable_poses()->add_poses();
    for (int j = 0; j < clip.skeleton.num_joints(); ++j) {
      v1::NamedJoint* joint = pose->add_joints();
      joint->set_name(clip.skeleton.joint(j).name);
      if (clip.skeleton.parent(j) >= 0) joint->set_parent(clip.skeleton.joint(clip.skeleton.parent(j)).name);
      const Eigen::Vector3f p = poses.position(frame, j) * 0.01f;
      joint->mutable_position()->set_x(p.x());
      joint->mutable_position()->set_y(p.y());
      joint->mutable_position()->set_z(p.z());
    }
    v1::NamedLandmarks* l = pose->mutable_landmarks();
    l->set_pelvis("Hips");
    l->set_head("Head");
    l->set_left_wrist("LeftHand");
    l->set_right_wrist("RightHand");
    l->set_left_ankle("LeftFoot");
    l->set_right_ankle("RightFoot");
  }
  auto response = client_->FindSimilarPoses(request);
  ASSERT_TRUE(response.ok()) << response.status();
  ASSERT_EQ(response->results_size(), 2);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(response->results(i).query_frame(), i);
    const int phase = ((response->results(i).matches(0).frame() - (i == 0 ? 20 : 25)) % 30 + 30) % 30;
    EXPECT_TRUE(phase <= 1 || phase >= 29) << response->results(i).matches(0).DebugString();
  }
  request.mutable_poses()->mutable_poses(1)->mutable_landmarks()->set_left_wrist("Nope");
  auto bad = client_->FindSimilarPoses(request);
  EXPECT_EQ(bad.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(bad.status().message().find("poses[1]"), std::string::npos) << bad.status();
}

TEST_F(PoseSearchServiceTest, TenancyAndAuthAsEveryOtherCall) {
  // Another tenant's database answers exactly like a missing one.
  auto other = Connect(keys_["other"])->FindSimilarPoses(Request(0, 5));
  EXPECT_EQ(other.status().code(), absl::StatusCode::kNotFound);
  v1::FindSimilarPosesRequest missing = Request(0, 5);
  missing.set_databases(0, "nope");
  auto absent = client_->FindSimilarPoses(missing);
  EXPECT_EQ(absent.status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(other.status().message(), "no motion database named 'walks'");
  auto no_key = client::Client::Connect(server_->address(), {})->get()->FindSimilarPoses(Request(0, 5));
  EXPECT_EQ(no_key.status().code(), absl::StatusCode::kUnauthenticated);
  auto bad_key = Connect("mk_bogus")->FindSimilarPoses(Request(0, 5));
  EXPECT_EQ(bad_key.status().code(), absl::StatusCode::kUnauthenticated);
  absl::Status streamed = Connect(keys_["other"])->StreamSimilarPoses(Request(0, 5), nullptr);
  EXPECT_EQ(streamed.code(), absl::StatusCode::kNotFound);
}

TEST_F(PoseSearchServiceTest, LimitsAreNamedAndCheckedBeforeAnyWork) {
  struct Case {
    const char* what;
    std::function<void(v1::FindSimilarPosesRequest&)> change;
    const char* named;
  };
  const std::vector<Case> cases = {
      {"no database", [](auto& r) { r.clear_databases(); }, "databases"},
      {"nine databases",
       [](auto& r) {
         for (int i = 0; i < 8; ++i) r.add_databases("walks" + std::to_string(i));
       },
       "at most 8"},
      {"the same database twice", [](auto& r) { r.add_databases("walks"); }, "same database"},
      {"no query", [](auto& r) { r.clear_bvh(); }, "query"},
      {"top_k 101", [](auto& r) { r.set_top_k(101); }, "top_k"},
      {"even window", [](auto& r) { r.set_window(4); }, "window"},
      {"negative weights", [](auto& r) { r.mutable_weights()->set_left_leg(-1); }, "weights"},
      {"all-zero weights", [](auto& r) { r.mutable_weights(); }, "weights"},
      {"too many exact frames",
       [](auto& r) {
         r.set_exact(true);
         r.mutable_bvh()->set_frame_step(0);
         r.mutable_bvh()->set_first_frame(0);
         r.mutable_bvh()->set_last_frame(100000);
       },
       "at most 200"},
      {"too many frames",
       [](auto& r) {
         r.mutable_bvh()->set_first_frame(0);
         r.mutable_bvh()->set_last_frame(100000);
       },
       "at most 2000"},
      {"frames x top_k",
       [](auto& r) {
         r.set_top_k(100);
         r.mutable_bvh()->set_first_frame(0);
         r.mutable_bvh()->set_last_frame(500);
       },
       "matches; at most 20000"},
      {"frames outside the file", [](auto& r) { r.mutable_bvh()->set_last_frame(90); }, "outside"},
      {"not BVH", [](auto& r) { r.mutable_bvh()->set_bvh("HIERARCHY\nnonsense"); }, "query.bvh"},
      {"window on poses",
       [](auto& r) {
         r.mutable_poses()->add_poses();
         r.set_window(3);
       },
       "window"},
  };
  for (const Case& c : cases) {
    v1::FindSimilarPosesRequest request = Request(0, 10);
    c.change(request);
    auto response = client_->FindSimilarPoses(request);
    EXPECT_EQ(response.status().code(), absl::StatusCode::kInvalidArgument) << c.what << ": " << response.status();
    EXPECT_NE(response.status().message().find(c.named), std::string::npos) << c.what << ": " << response.status();
  }
  // None of them built an index.
  EXPECT_EQ(IndexBuildsLogged(), 0);
  // The stream's own, larger limit still holds.
  v1::FindSimilarPosesRequest huge = Request(0, 10);
  huge.mutable_bvh()->set_last_frame(200000);
  EXPECT_EQ(client_->StreamSimilarPoses(huge, nullptr).code(), absl::StatusCode::kInvalidArgument);
}

TEST_F(PoseSearchServiceTest, IndexBuiltOncePerDatabaseVersionAndRebuiltAfterImport) {
  ASSERT_TRUE(client_->FindSimilarPoses(Request(0, 3)).ok());
  ASSERT_TRUE(client_->FindSimilarPoses(Request(4, 9)).ok());
  EXPECT_EQ(IndexBuildsLogged(), 1);
  // A new clip: after the import, its frames are among the matches (the same walk is in every
  // clip, so the top 20 of an exact search hold the same phase of each clip).
  const fs::path added = WriteClip("added.bvh", 45);
  v1::FindSimilarPosesRequest request = Request(10, 10);
  *request.mutable_bvh() = client::ReadBvhQuery(added).value();
  request.mutable_bvh()->set_first_frame(10);
  request.mutable_bvh()->set_last_frame(10);
  request.set_exact(true);
  request.set_top_k(20);
  auto in_added = [&](const v1::FindSimilarPosesResponse& response) {
    int count = 0;
    for (const v1::PoseMatch& match : response.results(0).matches()) count += match.file_name() == "added.bvh";
    return count;
  };
  auto before = client_->FindSimilarPoses(request);
  ASSERT_TRUE(before.ok()) << before.status();
  EXPECT_EQ(in_added(*before), 0);
  ASSERT_TRUE(client_->ImportFiles("walks", {added}).ok());
  auto after = client_->FindSimilarPoses(request);
  ASSERT_TRUE(after.ok()) << after.status();
  EXPECT_EQ(IndexBuildsLogged(), 2);
  EXPECT_GT(in_added(*after), 0);
  EXPECT_LT(after->results(0).matches(0).distance(), 1e-3);
}

// Point options per request: another scaling or sampling builds its own index once, shared by
// later calls, and answers differently; the default's index stays.
TEST_F(PoseSearchServiceTest, OtherPointOptionsBuildTheirOwnIndexOnce) {
  auto standard = client_->FindSimilarPoses(Request(0, 3));
  ASSERT_TRUE(standard.ok()) << standard.status();
  v1::FindSimilarPosesRequest seed_rules = Request(0, 3);
  seed_rules.set_scaling(v1::BODY_SCALING_BODY_SCALE);
  seed_rules.set_sampling(v1::CHAIN_SAMPLING_DROP);
  auto seed = client_->FindSimilarPoses(seed_rules);
  ASSERT_TRUE(seed.ok()) << seed.status();
  EXPECT_EQ(IndexBuildsLogged(), 2);
  // Other points, other distances (the walk itself is found either way).
  EXPECT_NE(seed->results(0).matches(0).distance(), standard->results(0).matches(0).distance());
  ASSERT_TRUE(client_->FindSimilarPoses(seed_rules).ok());
  ASSERT_TRUE(client_->FindSimilarPoses(Request(4, 9)).ok());
  EXPECT_EQ(IndexBuildsLogged(), 2);

  v1::FindSimilarPosesRequest unknown = Request(0, 3);
  unknown.set_scaling(static_cast<v1::BodyScaling>(9));
  absl::Status status = client_->FindSimilarPoses(unknown).status();
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(status.message().find("scaling"), std::string_view::npos) << status;
}

TEST_F(PoseSearchServiceTest, MocapSimilarPrintsWhatMocapdSimilarPrints) {
  const std::string common =
      " --database walks --query " + query_.string() + " --frames 10:40 --step 5 --top 4 --window 3 --json";
  const Run local =
      Command(std::string(MOCAPD_PATH) + " similar --store " + store_.string() + " --tenant acme" + common);
  ASSERT_EQ(local.exit_code, 0) << local.out;
  const Run remote = Command(std::string(MOCAP_CLI_PATH) + " similar --address " + server_->address() + " --key " +
                             keys_["acme"] + common);
  ASSERT_EQ(remote.exit_code, 0) << remote.out;
  EXPECT_EQ(nlohmann::json::parse(local.out)["results"].size(), 7u);
  EXPECT_EQ(remote.out, local.out);
  // The same with the seed's point rules, which the server builds another index for.
  const std::string seed_rules = common + " --scaling body-scale --sampling drop";
  const Run local_seed =
      Command(std::string(MOCAPD_PATH) + " similar --store " + store_.string() + " --tenant acme" + seed_rules);
  ASSERT_EQ(local_seed.exit_code, 0) << local_seed.out;
  const Run remote_seed = Command(std::string(MOCAP_CLI_PATH) + " similar --address " + server_->address() + " --key " +
                                  keys_["acme"] + seed_rules);
  EXPECT_EQ(remote_seed.out, local_seed.out);
  EXPECT_NE(remote_seed.out, remote.out);
  // Errors are reported, not printed as results.
  const Run missing = Command(std::string(MOCAP_CLI_PATH) + " similar --address " + server_->address() + " --key " +
                              keys_["other"] + common);
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_TRUE(missing.out.empty());
}

}  // namespace
}  // namespace mocap
