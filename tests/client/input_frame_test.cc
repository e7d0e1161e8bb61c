// Input conventions end to end (issue #12 part 1): a real `mocapd serve` on loopback, driven
// through the SDK and the `mocap` CLI. The same held-out clip (bandai-namco-2, take 003 of a
// walk, against a database of the set's other normal walks; synthetic walks when the shared data
// is absent) is fed in each preset's frame, converted by the test, and must give the native
// frame's reconstruction within float tolerance; wrong declarations must be named.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>

#include <nlohmann/json.hpp>

#include "client/wrist_input/wrist_source.h"
#include "motion/bvh/bvh_reader.h"
#include "motion/bvh/bvh_writer.h"
#include "motion/frames/frame_transform.h"
#include "motion/frames/input_frame.h"
#include "motion/preprocess/clip_labels.h"
#include "proto/convert/input_frame_proto.h"
#include "tests/support/server_fixture.h"
#include "tests/support/shared_data.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

Eigen::Vector3f FromProto(const v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }
void Set(const Eigen::Vector3f& p, v1::Vec3* v) {
  v->set_x(p.x());
  v->set_y(p.y());
  v->set_z(p.z());
}
Eigen::Quaternionf FromProto(const v1::Quaternion& q) { return Eigen::Quaternionf(q.w(), q.x(), q.y(), q.z()); }

// Native samples as a tracker in `transform`'s frame would send them.
std::vector<v1::WristSample> InFrame(std::vector<v1::WristSample> samples, const FrameTransform& transform) {
  for (v1::WristSample& s : samples) {
    Set(transform.PositionFromNative(FromProto(s.left())), s.mutable_left());
    Set(transform.PositionFromNative(FromProto(s.right())), s.mutable_right());
  }
  return samples;
}

class InputFrameTest : public testing::ServerFixture {
 protected:
  // The database and the query: real clips when the shared data is there, else synthetic walks.
  void SetUpData() {
    StartServer();
    client_ = Connect(keys_["acme"]);
    std::string why;
    std::optional<fs::path> folder = testing::SharedDataSet("bandai-namco-2", &why);
    if (!folder) {
      std::cout << "[ input frames ] shared data unavailable (" << why << "): synthetic walks instead\n";
      ImportWalks(*client_);
      query_ = *WristsFromBvh(WriteClip("query.bvh", 120), 0.5, 1);
      return;
    }
    std::vector<fs::path> database;
    for (const fs::path& file : testing::BvhFilesIn(*folder)) {
      const std::string name = file.filename().string();
      if (name.find("_walk_normal_") == std::string::npos) continue;
      if (std::stoi(LabelValue(ParseClipLabels(name), "take")) % 10 == 3) {
        if (query_.empty()) query_ = *WristsFromBvh(file, 0.5, 1);  // held out: the query
      } else {
        database.push_back(file);
      }
    }
    auto imported = client_->ImportFiles("walks", database);
    ASSERT_TRUE(imported.ok()) << imported.status();
    ASSERT_FALSE(query_.empty());
  }
  static v1::SessionConfig Config() {
    v1::SessionConfig config;
    config.set_database("walks");
    config.mutable_overrides()->set_ankle_candidates(100);
    config.mutable_overrides()->set_pose_neighbours(30);
    config.set_include_diagnostics(true);
    return config;
  }
  v1::ReconstructTrajectoryResponse Reconstruct(const v1::SessionConfig& config,
                                                const std::vector<v1::WristSample>& samples) {
    auto response = client_->ReconstructTrajectory(config, samples);
    EXPECT_TRUE(response.ok()) << response.status();
    return response.ok() ? *response : v1::ReconstructTrajectoryResponse();
  }
  // Every output of `got` (in `transform`'s frame) against the native `expected`.
  static void ExpectSameMotion(const v1::ReconstructTrajectoryResponse& expected,
                               const v1::ReconstructTrajectoryResponse& got, const FrameTransform& transform,
                               const std::string& what) {
    SCOPED_TRACE(what);
    const auto& expected_joints = expected.started().skeleton().joints();
    const auto& got_joints = got.started().skeleton().joints();
    ASSERT_EQ(got_joints.size(), expected_joints.size());
    for (int j = 0; j < expected_joints.size(); ++j) {
      EXPECT_LT(
          (transform.VectorToNative(FromProto(got_joints[j].offset())) - FromProto(expected_joints[j].offset())).norm(),
          1e-5)
          << "joint " << j;
    }
    ASSERT_EQ(got.frames_size(), expected.frames_size());
    double worst_position = 0, worst_angle = 0;
    for (int f = 0; f < expected.frames_size(); ++f) {
      const v1::Frame& e = expected.frames(f);
      const v1::Frame& g = got.frames(f);
      auto position = [&](const v1::Vec3& got_v, const v1::Vec3& expected_v) {
        worst_position = std::max<double>(
            worst_position, (transform.PositionToNative(FromProto(got_v)) - FromProto(expected_v)).norm());
      };
      position(g.root_position(), e.root_position());
      position(g.pelvis_position(), e.pelvis_position());
      position(g.left_ankle(), e.left_ankle());
      position(g.right_ankle(), e.right_ankle());
      position(g.left_wrist(), e.left_wrist());
      position(g.right_wrist(), e.right_wrist());
      ASSERT_EQ(g.rotations_size(), e.rotations_size());
      for (int j = 0; j < e.rotations_size(); ++j) {
        const Eigen::Quaternionf native = transform.RotationToNative(FromProto(g.rotations(j)));
        worst_angle = std::max<double>(worst_angle, native.angularDistance(FromProto(e.rotations(j))));
      }
      EXPECT_NEAR(transform.LengthToNative(g.diagnostics().left_wrist_error()), e.diagnostics().left_wrist_error(),
                  1e-4);
    }
    std::cout << "[ input frames ] " << what << ": worst position difference " << worst_position * 1000
              << " mm, worst rotation " << worst_angle * 180 / M_PI << " deg over " << expected.frames_size()
              << " frames\n";
    EXPECT_LT(worst_position, 1e-3);  // 1 mm
    EXPECT_LT(worst_angle, 2e-3);     // 0.1°
  }

  std::unique_ptr<client::Client> client_;
  std::vector<v1::WristSample> query_;
};

TEST_F(InputFrameTest, EveryPresetGivesTheNativeReconstruction) {
  SetUpData();
  v1::SessionConfig native_config = Config();
  const v1::ReconstructTrajectoryResponse native = Reconstruct(native_config, query_);
  ASSERT_GT(native.frames_size(), 30);
  EXPECT_TRUE(native.input_report().warnings().empty());
  v1::SessionConfig calibrated_config = Config();  // the reference for presets that calibrate their floor
  calibrated_config.mutable_input_frame()->set_calibrate_floor(true);
  calibrated_config.set_output_frame(v1::OUTPUT_FRAME_SERVER);  // relative to the estimated floor
  const v1::ReconstructTrajectoryResponse calibrated = Reconstruct(calibrated_config, query_);
  EXPECT_TRUE(calibrated.input_report().floor_calibrated());
  std::cout << "[ input frames ] calibrated floor of the held-out clip: "
            << calibrated.input_report().floor_height() * 100 << " cm from the true one\n";
  EXPECT_LT(std::abs(calibrated.input_report().floor_height()), 0.10);

  for (const InputFramePreset& preset : InputFramePresets()) {
    // A floor-relative preset's floor where it says; a calibrated one 1.4 m below the origin (a
    // head-height origin, as OpenXR LOCAL), in the preset's own unit and up axis.
    const FrameConvention& convention = preset.frame.convention;
    const double floor = preset.frame.floor.calibrate
                             ? -1.4 / MetresPerUnit(convention.unit) * UpAxisSign(convention.up)
                             : preset.frame.floor.height;
    const FrameTransform sent(convention, floor);
    v1::SessionConfig config = Config();
    config.mutable_input_frame()->set_preset(PresetToProto(preset.name));
    ASSERT_NE(config.input_frame().preset(), v1::INPUT_FRAME_PRESET_UNSPECIFIED) << preset.name;
    const v1::ReconstructTrajectoryResponse got = Reconstruct(config, InFrame(query_, sent));
    EXPECT_TRUE(got.input_report().warnings().empty()) << preset.name << ": " << got.input_report().DebugString();
    // Frames come back in the preset's frame, positions relative to the floor it reported.
    const FrameTransform back(convention, got.input_report().floor_height());
    if (preset.frame.floor.calibrate) {
      EXPECT_NEAR(
          got.input_report().floor_height(),
          floor + calibrated.input_report().floor_height() * UpAxisSign(convention.up) / MetresPerUnit(convention.unit),
          1e-3 / MetresPerUnit(convention.unit));
    }
    ExpectSameMotion(preset.frame.floor.calibrate ? calibrated : native, got, back, std::string(preset.name));
    // The resolved frame is echoed field by field.
    EXPECT_EQ(got.started().config().input_frame().unit(), ToProto(preset.frame, {}).unit());
    // On request, in the server's frame directly.
    config.set_output_frame(v1::OUTPUT_FRAME_SERVER);
    ExpectSameMotion(preset.frame.floor.calibrate ? calibrated : native, Reconstruct(config, InFrame(query_, sent)),
                     FrameTransform(), std::string(preset.name) + " (server frame)");
  }
}

TEST_F(InputFrameTest, ExplicitFieldsAndATrackedDeviceGiveTheSameMotion) {
  SetUpData();
  const v1::ReconstructTrajectoryResponse native = Reconstruct(Config(), query_);
  // Millimetres, −X up, left-handed, floor at x = +250 mm; a controller held 8 cm from the wrist,
  // turning at random.
  const FrameConvention convention{LengthUnit::kMillimetre, UpAxis::kNegX, Handedness::kLeft};
  const FrameTransform sent(convention, 250.0);
  const Eigen::Vector3f offset(0, -20, 77);  // mm, device frame
  std::vector<v1::WristSample> samples = InFrame(query_, sent);
  std::mt19937 random(5);
  for (v1::WristSample& s : samples) {
    for (int side = 0; side < 2; ++side) {
      Eigen::Quaternionf q = Eigen::Quaternionf::UnitRandom();
      v1::Vec3* position = side == 0 ? s.mutable_left() : s.mutable_right();
      Set(FromProto(*position) - q * offset, position);  // the device's point, so that point + q·offset = wrist
      v1::Quaternion* orientation = side == 0 ? s.mutable_left_orientation() : s.mutable_right_orientation();
      orientation->set_w(q.w());
      orientation->set_x(q.x());
      orientation->set_y(q.y());
      orientation->set_z(q.z());
    }
  }
  v1::SessionConfig config = Config();
  v1::InputFrame* frame = config.mutable_input_frame();
  frame->set_unit(v1::LENGTH_UNIT_MILLIMETRE);
  frame->set_up(v1::UP_AXIS_NEG_X);
  frame->set_handedness(v1::HANDEDNESS_LEFT);
  frame->set_floor_height(250);
  frame->set_tracked_device(true);
  Set(offset, frame->mutable_device_offset());
  ExpectSameMotion(native, Reconstruct(config, samples), sent, "mm, -X up, left-handed, tracked device");

  // Without the orientations, device samples are refused one by one, saying why.
  for (v1::WristSample& s : samples) s.clear_left_orientation();
  const v1::ReconstructTrajectoryResponse refused = Reconstruct(config, samples);
  ASSERT_EQ(refused.rejected_size(), static_cast<int>(samples.size()));
  EXPECT_NE(refused.rejected(0).reason().find("left_orientation"), std::string::npos) << refused.rejected(0).reason();
  // A bad declaration is refused before any work, naming the field.
  frame->mutable_device_offset()->set_z(900);  // 0.9 m
  EXPECT_NE(client_->ReconstructTrajectory(config, samples).status().message().find("device_offset"),
            std::string::npos);
}

// A device held in the hand without its orientation (a phone): the server takes each point back
// along the forearm by the declared grip, in the declared unit, and says so in the echo.
TEST_F(InputFrameTest, AGripOffsetTakesDevicePointsBackToTheWrists) {
  SetUpData();
  const v1::ReconstructTrajectoryResponse native = Reconstruct(Config(), query_);
  ASSERT_GT(native.frames_size(), 20);
  v1::SessionConfig config = Config();
  config.mutable_input_frame()->set_unit(v1::LENGTH_UNIT_CENTIMETRE);
  config.mutable_input_frame()->set_grip_offset(9);
  const v1::ReconstructTrajectoryResponse gripped =
      Reconstruct(config, InFrame(query_, FrameTransform({LengthUnit::kCentimetre}, 0.0)));
  ASSERT_EQ(gripped.frames_size(), native.frames_size());
  EXPECT_FLOAT_EQ(gripped.started().config().input_frame().grip_offset(), 9.0f);
  // The input as wrists (Frame.left_wrist, in the declared centimetres) lies a grip short of the
  // points sent, which the native run took as the wrists themselves.
  double moved = 0;
  for (int f = 0; f < native.frames_size(); ++f) {
    moved += (FromProto(gripped.frames(f).left_wrist()) / 100.0f - FromProto(native.frames(f).left_wrist())).norm();
  }
  EXPECT_NEAR(moved / native.frames_size(), 0.09, 0.01);
  // Beside a tracked device's offset, or longer than a hand holds, it is refused naming the field.
  config.mutable_input_frame()->set_grip_offset(40);
  EXPECT_NE(client_->ReconstructTrajectory(config, query_).status().message().find("grip_offset"), std::string::npos);
  config.mutable_input_frame()->set_grip_offset(9);
  config.mutable_input_frame()->set_tracked_device(true);
  EXPECT_NE(client_->ReconstructTrajectory(config, query_).status().message().find("grip_offset"), std::string::npos);
}

TEST_F(InputFrameTest, WrongDeclarationsAreNamed) {
  SetUpData();
  // Centimetres declared as metres: every sample refused, naming the likely unit.
  std::vector<v1::WristSample> centimetres = InFrame(query_, FrameTransform({LengthUnit::kCentimetre}, 0.0));
  const v1::ReconstructTrajectoryResponse cm = Reconstruct(Config(), centimetres);
  ASSERT_EQ(cm.rejected_size(), static_cast<int>(query_.size()));
  EXPECT_NE(cm.rejected(0).reason().find("centimetres"), std::string::npos) << cm.rejected(0).reason();
  EXPECT_NE(cm.rejected(0).reason().find("declared as metres?"), std::string::npos) << cm.rejected(0).reason();

  // OpenXR LOCAL data (origin at the head) declared as LOCAL_FLOOR: wrists below the floor.
  v1::SessionConfig config = Config();
  config.mutable_input_frame()->set_preset(v1::INPUT_FRAME_PRESET_OPENXR_LOCAL_FLOOR);
  const std::vector<v1::WristSample> local = InFrame(query_, FrameTransform({}, -1.6));
  const v1::ReconstructTrajectoryResponse below = Reconstruct(config, local);
  ASSERT_EQ(below.input_report().warnings_size(), 1) << below.input_report().DebugString();
  EXPECT_EQ(below.input_report().warnings(0).kind(), v1::INPUT_WARNING_KIND_BELOW_FLOOR);
  EXPECT_NE(below.input_report().warnings(0).message().find("wrists below the floor"), std::string::npos);

  // Unity data (left-handed) sent as native: a mirrored world, so left and right look swapped.
  const std::vector<v1::WristSample> unity =
      InFrame(query_, FrameTransform({LengthUnit::kMetre, UpAxis::kPosY, Handedness::kLeft}, 0.0));
  const v1::ReconstructTrajectoryResponse mirrored = Reconstruct(Config(), unity);
  ASSERT_EQ(mirrored.input_report().warnings_size(), 1) << mirrored.input_report().DebugString();
  EXPECT_EQ(mirrored.input_report().warnings(0).kind(), v1::INPUT_WARNING_KIND_SWAPPED);
  EXPECT_NE(mirrored.input_report().warnings(0).message().find("left and right look swapped"), std::string::npos);

  std::cout << "[ input frames ] messages:\n  " << cm.rejected(0).reason() << "\n  "
            << below.input_report().warnings(0).message() << "\n  " << mirrored.input_report().warnings(0).message()
            << "\n";

  // With strict, a warning ends the call with its message.
  config.set_strict(true);
  auto strict = client_->ReconstructTrajectory(config, local);
  EXPECT_EQ(strict.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(strict.status().message().find("wrists below the floor"), std::string::npos) << strict.status();

  // The stream says the same in an input_report reply.
  auto stream = client_->OpenReconstruction(Config());
  ASSERT_TRUE(stream.ok()) << stream.status();
  ASSERT_TRUE((*stream)->Write(unity).ok());
  std::vector<v1::InputReport> reports;
  auto summary = (*stream)->Finish([&](const v1::ReconstructResponse& reply) {
    if (reply.has_input_report()) reports.push_back(reply.input_report());
  });
  ASSERT_TRUE(summary.ok()) << summary.status();
  ASSERT_GE(reports.size(), 2u);  // the first second's (floor, no warning), then the sides'
  EXPECT_TRUE(reports[0].warnings().empty());
  EXPECT_EQ(reports.back().warnings(0).kind(), v1::INPUT_WARNING_KIND_SWAPPED);
}

// Both parts of issue #12 together: declared frame → native → reconstruct → retarget onto the
// caller's rig → declared frame. The avatar's skeleton and frames come back in the caller's
// convention, equal to the native session's converted.
TEST_F(InputFrameTest, ATargetRigAnswersInTheDeclaredFrameToo) {
  SetUpData();
  const BvhClip avatar = testing::MakeWalkingClip({.z_up = true, .fingers_and_toes = true, .length_scale = 1.1f}, 10);
  v1::SessionConfig config = Config();
  config.mutable_target_rig()->set_bvh(FormatBvh(avatar));
  const v1::ReconstructTrajectoryResponse native = Reconstruct(config, query_);
  ASSERT_EQ(native.started().skeleton().joints_size(), avatar.skeleton.num_joints());
  const InputFrame unreal = FindInputFramePreset("unreal")->frame;
  config.mutable_input_frame()->set_preset(v1::INPUT_FRAME_PRESET_UNREAL);
  const FrameTransform sent(unreal.convention, unreal.floor.height);
  ExpectSameMotion(native, Reconstruct(config, InFrame(query_, sent)), sent, "unreal on a target rig");
}

// `mocap reconstruct --bvh` converts the clip's wrists into the declared frame; its BVH and JSON
// stay in the standard frame, so they match the native run.
TEST_F(InputFrameTest, CliTakesPresetsAndExplicitFlags) {
  SetUpData();
  const fs::path clip = WriteClip("cli_query.bvh", 90);
  auto run = [&](const std::string& name, const std::string& flags) {
    const std::string command = std::string(MOCAP_CLI_PATH) + " --address " + server_->address() + " --key " +
                                keys_["acme"] + " reconstruct --database walks --bvh " + clip.string() +
                                " --k1 100 --k2 30 --quiet " + flags + " -o " + (dir_ / name).string() + " 2>>" +
                                (dir_ / "cli.log").string();
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    std::ifstream in(dir_ / (name + ".json"));
    return nlohmann::json::parse(in, nullptr, false);
  };
  const nlohmann::json native = run("native", "");
  ASSERT_FALSE(native.is_discarded());
  for (const auto& [name, flags] : std::vector<std::pair<std::string, std::string>>{
           {"unreal", "--input-frame unreal"}, {"explicit", "--units in --up=-z --handedness left --floor 12.5"}}) {
    const nlohmann::json got = run(name, flags);
    ASSERT_FALSE(got.is_discarded()) << name;
    ASSERT_EQ(got["frames"].size(), native["frames"].size()) << name;
    for (size_t f = 0; f < native["frames"].size(); ++f) {
      const auto& e = native["frames"][f]["root_position"];
      const auto& g = got["frames"][f]["root_position"];
      EXPECT_NEAR(g["x"].get<double>(), e["x"].get<double>(), 1e-3) << name << " frame " << f;
      EXPECT_NEAR(g["y"].get<double>(), e["y"].get<double>(), 1e-3) << name << " frame " << f;
      EXPECT_NEAR(g["z"].get<double>(), e["z"].get<double>(), 1e-3) << name << " frame " << f;
    }
    EXPECT_TRUE(fs::exists(dir_ / (name + ".bvh")));
  }
  // A calibrated floor is an estimate: the run reports it.
  const nlohmann::json calibrated = run("calibrate", "--input-frame unity --floor calibrate");
  ASSERT_FALSE(calibrated.is_discarded());
  EXPECT_TRUE(calibrated["input_report"]["floor_calibrated"].get<bool>());
  EXPECT_EQ(calibrated["frames"].size(), native["frames"].size());
  // Bad flags are refused with the flag named.
  const std::string bad = std::string(MOCAP_CLI_PATH) + " --address " + server_->address() + " --key " + keys_["acme"] +
                          " reconstruct --database walks --bvh " + clip.string() + " --input-frame maya -o " +
                          (dir_ / "bad").string() + " 2>" + (dir_ / "bad.log").string();
  EXPECT_NE(std::system(bad.c_str()), 0);
  std::ifstream log(dir_ / "bad.log");
  const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("--input-frame: unknown preset \"maya\""), std::string::npos) << text;
  // A BVH's wrists are wrists: a grip is refused, saying so.
  const std::string gripped = std::string(MOCAP_CLI_PATH) + " --address " + server_->address() + " --key " +
                              keys_["acme"] + " reconstruct --database walks --bvh " + clip.string() +
                              " --grip-offset 0.09 -o " + (dir_ / "gripped").string() + " 2>" +
                              (dir_ / "gripped.log").string();
  EXPECT_NE(std::system(gripped.c_str()), 0);
  std::ifstream gripped_log(dir_ / "gripped.log");
  const std::string gripped_text((std::istreambuf_iterator<char>(gripped_log)), std::istreambuf_iterator<char>());
  EXPECT_NE(gripped_text.find("--grip-offset is for devices"), std::string::npos) << gripped_text;
  EXPECT_FALSE(fs::exists(dir_ / "gripped.bvh"));
}

// Issue #25: a run where every sample is refused fails with one summary naming the cause and the
// fix, and writes nothing; positions kilometres from the origin (a game engine's world) are taken
// with --recenter.
TEST_F(InputFrameTest, CliRunThatReconstructsNothingFailsWithTheCauseAndWritesNothing) {
  SetUpData();
  auto write_csv = [&](const std::string& name, double scale, double x_offset) {
    std::ofstream out(dir_ / name);
    out << "time,left_x,left_y,left_z,right_x,right_y,right_z\n";
    for (const v1::WristSample& s : query_) {
      out << s.time() << "," << scale * s.left().x() + x_offset << "," << scale * s.left().y() << ","
          << scale * s.left().z() << "," << scale * s.right().x() + x_offset << "," << scale * s.right().y() << ","
          << scale * s.right().z() << "\n";
    }
    return (dir_ / name).string();
  };
  auto run = [&](const std::string& csv, const std::string& name, const std::string& flags) {
    const std::string command = std::string(MOCAP_CLI_PATH) + " --address " + server_->address() + " --key " +
                                keys_["acme"] + " reconstruct --database walks --csv " + csv +
                                " --k1 100 --k2 30 --quiet " + flags + " -o " + (dir_ / name).string() + " 2>" +
                                (dir_ / (name + ".log")).string() + " >/dev/null";
    const int code = std::system(command.c_str());
    std::ifstream log(dir_ / (name + ".log"));
    return std::make_pair(code, std::string((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>()));
  };
  const std::string far = write_csv("far.csv", 1.0, 12000.0);  // 12 km east, as a game world puts it
  const auto [far_code, far_log] = run(far, "far", "");
  EXPECT_NE(far_code, 0) << far_log;
  EXPECT_NE(far_log.find("no frame was reconstructed: " + std::to_string(query_.size()) + " of " +
                         std::to_string(query_.size()) + " samples were refused"),
            std::string::npos)
      << far_log;
  EXPECT_NE(far_log.find("--recenter"), std::string::npos) << far_log;
  EXPECT_LT(std::count(far_log.begin(), far_log.end(), '\n'), 10) << "one summary, not a line per sample";
  EXPECT_FALSE(fs::exists(dir_ / "far.bvh"));
  EXPECT_FALSE(fs::exists(dir_ / "far.json"));
  const auto [recentered_code, recentered_log] = run(far, "recentered", "--recenter");
  EXPECT_EQ(recentered_code, 0) << recentered_log;
  EXPECT_TRUE(fs::exists(dir_ / "recentered.bvh"));
  // Centimetres declared as metres: the wrists are metres apart; the fix names the unit.
  const auto [cm_code, cm_log] = run(write_csv("centimetres.csv", 100.0, 0.0), "centimetres", "");
  EXPECT_NE(cm_code, 0) << cm_log;
  EXPECT_NE(cm_log.find("declared unit"), std::string::npos) << cm_log;
  EXPECT_FALSE(fs::exists(dir_ / "centimetres.bvh"));
}

// A dropout longer than the session bridges (3 s; max_gap_seconds 2) starts a new segment and the
// session makes no frames for it; the BVH still plays on the input's clock, the gap filled, and
// the run says so. The JSON keeps only the frames made, each at its input time.
TEST_F(InputFrameTest, CliBvhPlaysOnTheInputsClockAcrossADropoutTooLongToBridge) {
  SetUpData();
  const fs::path csv = dir_ / "gap.csv";
  {
    std::ofstream out(csv);
    out << "time,left_x,left_y,left_z,right_x,right_y,right_z\n";
    for (size_t i = 0; i < query_.size(); ++i) {
      const v1::WristSample& s = query_[i];
      out << s.time() + (i >= query_.size() / 2 ? 3.0 : 0.0) << "," << s.left().x() << "," << s.left().y() << ","
          << s.left().z() << "," << s.right().x() << "," << s.right().y() << "," << s.right().z() << "\n";
    }
  }
  const std::string command = std::string(MOCAP_CLI_PATH) + " --json --address " + server_->address() + " --key " +
                              keys_["acme"] + " reconstruct --database walks --csv " + csv.string() +
                              " --k1 100 --k2 30 --quiet -o " + (dir_ / "gap").string() + " >" +
                              (dir_ / "gap.out").string() + " 2>" + (dir_ / "gap.log").string();
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  std::ifstream summary_in(dir_ / "gap.out");
  const nlohmann::json summary = nlohmann::json::parse(summary_in, nullptr, false);
  ASSERT_FALSE(summary.is_discarded());
  EXPECT_EQ(summary["bvh_filled_gaps"].get<int>(), 1) << summary.dump();
  EXPECT_EQ(summary["bvh_unfilled_gaps"].get<int>(), 0);
  std::ifstream json_in(dir_ / "gap.json");
  const nlohmann::json answer = nlohmann::json::parse(json_in, nullptr, false);
  ASSERT_FALSE(answer.is_discarded());
  const double rate = answer["started"]["frame_rate"].get<double>();
  const auto& frames = answer["frames"];
  ASSERT_GT(frames.size(), 2u);
  const double first = frames.front().value("time", 0.0), last = frames.back().value("time", 0.0);
  double widest = 0.0;
  for (size_t f = 1; f < frames.size(); ++f) {
    widest = std::max(widest, frames[f].value("time", 0.0) - frames[f - 1].value("time", 0.0));
  }
  EXPECT_GT(widest, 2.0) << "the session bridged the dropout: no gap to fill";
  const absl::StatusOr<BvhClip> bvh = ReadBvhFile(dir_ / "gap.bvh");
  ASSERT_TRUE(bvh.ok()) << bvh.status();
  EXPECT_NEAR(bvh->frame_time, 1.0 / rate, 1e-6);
  // Frame k of the file plays at first + k / rate: the last one at the last frame's time.
  EXPECT_NEAR(first + (bvh->num_frames() - 1) / rate, last, 1.0 / rate);
  EXPECT_EQ(bvh->num_frames(), static_cast<int>(frames.size()) + summary["bvh_filled_frames"].get<int>());
}

}  // namespace
}  // namespace mocap
