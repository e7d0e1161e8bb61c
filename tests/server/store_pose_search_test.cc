#include "server/store_pose_search.h"

#include <optional>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "motion/bvh/bvh_writer.h"
#include "motion/core/status_macros.h"
#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/local_motion.h"
#include "storage/import_pipeline.h"
#include "tests/support/synthetic_clip.h"
#include "tests/support/temp_dir.h"
#include "tools/similar_json/similar_json.h"

namespace mocap {
namespace {

// The search as `mocapd similar --json` prints it, the pose (when given) parsed as the command does.
absl::StatusOr<nlohmann::json> RunSimilar(SimilarOptions options, const std::optional<nlohmann::json>& pose = {}) {
  if (pose) {
    MOCAP_ASSIGN_OR_RETURN(options.pose, NamedPoseFromJson(*pose));
  }
  MOCAP_ASSIGN_OR_RETURN(v1::FindSimilarPosesResponse response, FindSimilarPosesInStore(options));
  return SimilarResultsJson(options.pose ? "pose" : options.query.string(), response);
}

namespace fs = std::filesystem;

class StorePoseSearchTest : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(dir_ / "db");
    ASSERT_TRUE(WriteBvhFile(testing::MakeWalkingClip({.extra_root = true}, 90), dir_ / "db" / "walk_a.bvh").ok());
    ASSERT_TRUE(WriteBvhFile(testing::MakeWalkingClip({.extra_root = true}, 70), dir_ / "db" / "walk_b.bvh").ok());
    ImportOptions import;
    import.store = dir_ / "store.db";
    import.database = "walks";
    import.inputs = {(dir_ / "db").string()};
    ASSERT_TRUE(RunImport(import).ok());
    // The query: another rig (twist bones, fingers, Z-up root, inches) of the same walk.
    query_ = dir_ / "query.bvh";
    ASSERT_TRUE(WriteBvhFile(testing::MakeWalkingClip({.z_up = true,
                                                       .fingers_and_toes = true,
                                                       .twist_bones = true,
                                                       .length_scale = 1.0 / 2.54,
                                                       .rotation_order = "XYZ"},
                                                      90),
                             query_)
                    .ok());
  }
  SimilarOptions Options() {
    SimilarOptions options;
    options.store = dir_ / "store.db";
    options.databases = {"walks"};
    options.query = query_;
    options.search.top_k = 3;
    return options;
  }
  testing::ScopedTempDir temp_;
  const fs::path& dir_ = temp_.path();
  fs::path query_;
};

TEST_F(StorePoseSearchTest, FindsTheSamePoseOnAnotherRig) {
  SimilarOptions options = Options();
  options.first_frame = 20;
  options.last_frame = 60;
  options.frame_step = 20;
  for (bool exact : {false, true}) {
    options.search.exact = exact;
    auto result = RunSimilar(options);
    ASSERT_TRUE(result.ok()) << result.status();
    const auto& results = (*result)["results"];
    ASSERT_EQ(results.size(), 3u);
    for (const auto& entry : results) {
      const auto& best = entry["matches"][0];
      // Both database clips hold the same periodic walk (one gait cycle = 30 frames at 30 fps):
      // the same phase anywhere in either clip is the same pose.
      const int cycle = static_cast<int>(testing::kSyntheticGaitCycle * 30);
      const int phase = ((best["frame"].get<int>() - entry["query_frame"].get<int>()) % cycle + cycle) % cycle;
      EXPECT_TRUE(phase <= 1 || phase >= cycle - 1) << entry.dump();
      EXPECT_LT(best["distance"].get<double>(), 0.05);
      EXPECT_EQ(best["group_distances"].size(), 6u);
    }
  }
}

// A one-frame file (a T-pose, one exported pose) is a query like any clip (issue #25: it was
// refused as "shorter than two frames"): frame 20 of the other-rig walk alone, at 60 fps, finds
// the pose of the same phase.
TEST_F(StorePoseSearchTest, AOneFrameFileIsAQuery) {
  BvhClip one = testing::MakeWalkingClip({.z_up = true, .twist_bones = true}, 21, 1.0 / 60.0);
  one.channels = one.channels.bottomRows(1).eval();
  const fs::path file = dir_ / "one.bvh";
  ASSERT_TRUE(WriteBvhFile(one, file).ok());
  SimilarOptions options = Options();
  options.query = file;
  auto result = RunSimilar(options);
  ASSERT_TRUE(result.ok()) << result.status();
  ASSERT_EQ((*result)["results"].size(), 1u);
  const auto& best = (*result)["results"][0]["matches"][0];
  // 20 frames at 60 fps: 10 at the database's 30 fps, within a gait cycle of 30 frames.
  const int cycle = static_cast<int>(testing::kSyntheticGaitCycle * 30);
  const int phase = ((best["frame"].get<int>() - 10) % cycle + cycle) % cycle;
  EXPECT_TRUE(phase <= 1 || phase >= cycle - 1) << best.dump();
  EXPECT_LT(best["distance"].get<double>(), 0.05);
}

// A pose sent as named joint positions (what an app or the RPC sends), here the synthetic walk's
// frame 20 on the plain rig, in metres, Z up.
nlohmann::json PoseOfFrame(int frame) {
  const BvhClip clip = testing::MakeWalkingClip({}, 40);
  const GlobalPoses poses =
      ForwardKinematics(clip.skeleton, MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time));
  nlohmann::json joints = nlohmann::json::array();
  for (int j = 0; j < clip.skeleton.num_joints(); ++j) {
    const Eigen::Vector3f p = poses.position(frame, j) * 0.01f;
    const int parent = clip.skeleton.parent(j);
    joints.push_back(
        {{"name", clip.skeleton.joint(j).name},
         {"parent", parent < 0 ? nlohmann::json(nullptr) : nlohmann::json(clip.skeleton.joint(parent).name)},
         {"position", {p.x(), -p.z(), p.y()}}});  // Y-up -> Z-up
  }
  return {{"up", "+Z"},
          {"joints", joints},
          {"landmarks",
           {{"pelvis", "Hips"},
            {"head", "Head"},
            {"left_wrist", "LeftHand"},
            {"right_wrist", "RightHand"},
            {"left_ankle", "LeftFoot"},
            {"right_ankle", "RightFoot"}}}};
}

TEST_F(StorePoseSearchTest, FindsAPoseSentAsJointPositions) {
  SimilarOptions options = Options();
  auto result = RunSimilar(options, PoseOfFrame(20));
  ASSERT_TRUE(result.ok()) << result.status();
  const auto& best = (*result)["results"][0]["matches"][0];
  const int phase = (best["frame"].get<int>() - 20 + 300) % 30;
  EXPECT_TRUE(phase <= 1 || phase >= 29) << best.dump();
  EXPECT_LT(best["distance"].get<double>(), 0.05);

  // The optional limb landmarks reach the search: named where the length rule finds them, the
  // same answer; an elbow outside its arm, a clear error.
  nlohmann::json pose = PoseOfFrame(20);
  for (const auto& [key, joint] : {std::pair{"left_elbow", "LeftForeArm"}, std::pair{"right_elbow", "RightForeArm"},
                                   std::pair{"left_shoulder", "LeftArm"}, std::pair{"right_shoulder", "RightArm"},
                                   std::pair{"left_knee", "LeftLeg"}, std::pair{"right_knee", "RightLeg"},
                                   std::pair{"left_hip", "LeftUpLeg"}, std::pair{"right_hip", "RightUpLeg"}}) {
    pose["landmarks"][key] = joint;
  }
  auto named = RunSimilar(options, pose);
  ASSERT_TRUE(named.ok()) << named.status();
  EXPECT_EQ((*named)["results"][0]["matches"][0], best);
  pose["landmarks"]["left_elbow"] = "RightForeArm";
  EXPECT_EQ(RunSimilar(options, pose).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(RunSimilar(options, pose).status().message().find("left_elbow"), std::string_view::npos);

  pose = PoseOfFrame(20);
  pose["landmarks"]["left_wrist"] = "Nope";
  EXPECT_EQ(RunSimilar(options, pose).status().code(), absl::StatusCode::kInvalidArgument);
  pose = PoseOfFrame(20);
  pose["landmarks"]["left_wrist"] = "Chest";  // the wrists' common ancestor itself
  EXPECT_EQ(RunSimilar(options, pose).status().code(), absl::StatusCode::kInvalidArgument);
  pose = PoseOfFrame(20);
  pose["joints"][3]["position"][0] = "x";
  EXPECT_EQ(RunSimilar(options, pose).status().code(), absl::StatusCode::kInvalidArgument);
  options.search.window = 3;
  EXPECT_EQ(RunSimilar(options, PoseOfFrame(20)).status().code(), absl::StatusCode::kInvalidArgument);
}

TEST_F(StorePoseSearchTest, BadRequestsAreClearErrors) {
  SimilarOptions options = Options();
  options.databases = {"nope"};
  EXPECT_EQ(RunSimilar(options).status().code(), absl::StatusCode::kNotFound);
  options = Options();
  options.first_frame = 0;
  options.last_frame = 500;
  EXPECT_EQ(RunSimilar(options).status().code(), absl::StatusCode::kInvalidArgument);
  options = Options();
  options.search.window = 4;
  EXPECT_EQ(RunSimilar(options).status().code(), absl::StatusCode::kInvalidArgument);
  options = Options();
  options.store = dir_ / "missing.db";
  EXPECT_EQ(RunSimilar(options).status().code(), absl::StatusCode::kNotFound);
}

}  // namespace
}  // namespace mocap
