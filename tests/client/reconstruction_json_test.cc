// OUTPUT.json of `mocap reconstruct`, written a frame at a time, each frame's rotations apart from
// protobuf's printer (client/cli/reconstruction_json.h): byte for byte the text the whole answer
// converted at once gives. The CLI's sources are built
// into the `mocap` executable only, so the writer is compiled into this test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "client/cli/reconstruction_json.cc"  // NOLINT(build/include): WriteReconstructionJson
#include "google/protobuf/stubs/strutil.h"

namespace mocap {
namespace {

// Floats of every kind a rotation or anything else can hold: around 1, tiny, huge, denormal,
// negative zero, and bit patterns at random.
std::vector<float> Floats() {
  std::vector<float> values = {0.0f,        -0.0f,  1.0f,       -1.0f,        0.5f,      1e-5f,     1.00000007e-05f,
                               3e-38f,      1e-45f, 3.4e38f,    0.726335049f, -5.28039f, 123456.7f, 1e7f,
                               16777216.0f, 0.1f,   2.0f / 3.0f};
  std::mt19937 random(7);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  for (int i = 0; i < 20000; ++i) values.push_back(unit(random));
  for (int i = 0; i < 20000; ++i) {
    const uint32_t bits = static_cast<uint32_t>(random());
    float value;
    std::memcpy(&value, &bits, sizeof value);
    if (std::isfinite(value)) values.push_back(value);
  }
  return values;
}

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
    v1::Quaternion* q = frame->add_rotations();
    q->set_w(0.726335049f);
    q->set_x(-0.0f);
    q->set_y(1e-5f * static_cast<float>(f + 1));
    q->set_z(-5.28039f);
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

TEST(ReconstructionJsonTest, RotationsOfAnyValueAreTheWholeAnswersText) {
  v1::ReconstructTrajectoryResponse answer = Answer(0);
  const std::vector<float> values = Floats();
  v1::Frame* frame = nullptr;
  for (size_t i = 0; i + 4 <= values.size(); i += 4) {
    if (i % 4000 == 0) frame = answer.add_frames();
    v1::Quaternion* q = frame->add_rotations();
    q->set_w(values[i]);
    q->set_x(values[i + 1]);
    q->set_y(values[i + 2]);
    q->set_z(values[i + 3]);
  }
  frame->add_rotations()->set_x(std::numeric_limits<float>::quiet_NaN());
  frame->add_rotations()->set_y(std::numeric_limits<float>::infinity());
  frame->add_rotations()->set_z(-std::numeric_limits<float>::infinity());
  // Compared apart from gtest's line diff, which is quadratic in this text's 200,000 lines.
  const std::string written = WrittenApart(answer), whole = cli::Json(answer);
  const size_t differs =
      std::mismatch(written.begin(), written.end(), whole.begin(), whole.end()).first - written.begin();
  EXPECT_EQ(written.size(), whole.size());
  EXPECT_EQ(differs, written.size()) << written.substr(differs > 80 ? differs - 80 : 0, 160) << "\n---\n"
                                     << whole.substr(differs > 80 ? differs - 80 : 0, 160);
}

TEST(ReconstructionJsonTest, FloatsAreProtobufsText) {
  for (float value : Floats()) {
    std::string text;
    cli::AppendJsonFloat(value, text);
    ASSERT_EQ(text, google::protobuf::SimpleFtoa(value)) << value;
  }
}

TEST(ReconstructionJsonTest, TheFramesKeepTheirRotations) {
  v1::ReconstructTrajectoryResponse answer = Answer(2);
  std::vector<v1::Frame> frames(answer.frames().begin(), answer.frames().end());
  answer.clear_frames();
  const std::filesystem::path path = std::filesystem::path(::testing::TempDir()) / "reconstruction_json_kept.json";
  ASSERT_TRUE(cli::WriteReconstructionJson(path, answer, frames).ok());
  std::filesystem::remove(path);
  ASSERT_EQ(frames[1].rotations_size(), 4);
  EXPECT_FLOAT_EQ(frames[1].rotations(3).y(), 2e-5f);
}

TEST(ReconstructionJsonTest, TheAnswerMustComeWithoutItsFrames) {
  std::vector<v1::Frame> no_frames;
  const absl::Status status =
      cli::WriteReconstructionJson(std::filesystem::path(::testing::TempDir()) / "unused.json", Answer(2), no_frames);
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
}

TEST(ReconstructionJsonTest, AnUnwritablePathIsDataLoss) {
  std::vector<v1::Frame> no_frames;
  const absl::Status status = cli::WriteReconstructionJson("/nonexistent-dir/out.json", Answer(0), no_frames);
  EXPECT_EQ(status.code(), absl::StatusCode::kDataLoss);
}

}  // namespace
}  // namespace mocap
