// OUTPUT.json of `mocap reconstruct`, written a frame at a time (client/cli/reconstruction_json.h):
// byte for byte the text the whole answer converted at once gives. The CLI's sources are built
// into the `mocap` executable only, so the writer is compiled into this test.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "client/cli/reconstruction_json.cc"  // NOLINT(build/include): WriteReconstructionJson

namespace mocap {
namespace {

v1::ReconstructTrajectoryResponse Answer(int frames) {
  v1::ReconstructTrajectoryResponse answer;
  answer.mutable_started()->set_session_id("s1");
  v1::Joint* joint = answer.mutable_started()->mutable_skeleton()->add_joints();
  joint->set_name("Hips");
  joint->set_parent(-1);
  for (int f = 0; f < frames; ++f) {
    v1::Frame* frame = answer.add_frames();
    frame->set_index(f);
    frame->set_time(f / 30.0);
    frame->mutable_root_position()->set_y(0.9f + 0.01f * static_cast<float>(f));
    for (int j = 0; j < 3; ++j) frame->add_rotations()->set_w(1.0f);
    frame->mutable_expected_error()->set_head(0.02f);
    frame->set_left_hand_state(v1::TRACKING_STATE_PREDICTED);
  }
  answer.mutable_summary()->set_frames(frames);
  answer.add_rejected()->set_reason("a \"quoted\"\nreason");
  return answer;
}

std::string WrittenApart(v1::ReconstructTrajectoryResponse answer) {
  std::vector<v1::Frame> frames(answer.frames().begin(), answer.frames().end());
  answer.clear_frames();
  const std::filesystem::path path = std::filesystem::path(::testing::TempDir()) / "reconstruction_json_test.json";
  EXPECT_TRUE(cli::WriteReconstructionJson(path, answer, frames).ok());
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  std::filesystem::remove(path);
  return text.str();
}

TEST(ReconstructionJsonTest, FrameAtATimeIsTheWholeAnswersText) {
  for (int frames : {0, 1, 3}) {
    const v1::ReconstructTrajectoryResponse answer = Answer(frames);
    EXPECT_EQ(WrittenApart(answer), cli::Json(answer)) << frames << " frames";
  }
}

TEST(ReconstructionJsonTest, TheAnswerMustComeWithoutItsFrames) {
  const absl::Status status =
      cli::WriteReconstructionJson(std::filesystem::path(::testing::TempDir()) / "unused.json", Answer(2), {});
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
}

TEST(ReconstructionJsonTest, AnUnwritablePathIsDataLoss) {
  const absl::Status status = cli::WriteReconstructionJson("/nonexistent-dir/out.json", Answer(0), {});
  EXPECT_EQ(status.code(), absl::StatusCode::kDataLoss);
}

}  // namespace
}  // namespace mocap
