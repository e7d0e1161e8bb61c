// Files the product writes, read back by independent readers: Blender's importer (headless) and
// three.js's BVHLoader (node, the viewer's copy). Every joint of every frame must be where this
// reader puts it, within 1 mm (issue #23: "BVH exactly as the tools read it"). Readers that are
// not installed are skipped with a message (scripts/setup.sh installs both).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "motion/bvh/bvh_reader.h"
#include "motion/bvh/bvh_writer.h"
#include "motion/core/units.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/reconstruct/reconstruction_database.h"
#include "motion/reconstruct/reconstruction_export.h"
#include "motion/reconstruct/reconstruction_options.h"
#include "motion/reconstruct/reconstruction_session.h"
#include "motion/retarget/retarget_export.h"
#include "motion/retarget/retarget_rig.h"
#include "motion/retarget/retargeter.h"
#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/local_motion.h"
#include "tests/support/shared_data.h"
#include "tests/support/synthetic_clip.h"
#include "tests/support/synthetic_database.h"
#include "tests/support/temp_dir.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;
constexpr int kFramesCompared = 8;

// "file joint frame" -> position, in file units and axes.
using Positions = std::map<std::string, Eigen::Vector3f>;
std::string Key(const std::string& file, const std::string& joint, int frame) {
  return file + " " + joint + " " + std::to_string(frame);
}

fs::path RepoDir() { return testing::TestDataDir().parent_path().parent_path(); }

std::string Run(const std::string& command) {
  std::string output;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return output;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) output += buffer;
  pclose(pipe);
  return output;
}

Positions OwnReading(const std::string& file) {
  Positions out;
  auto clip = ReadBvhFile(file);
  EXPECT_TRUE(clip.ok()) << clip.status();
  if (!clip.ok()) return out;
  const GlobalPoses poses =
      ForwardKinematics(clip->skeleton, MotionFromChannels(clip->skeleton, clip->channels, clip->frame_time));
  for (int f = 0; f < std::min(kFramesCompared, poses.num_frames()); ++f) {
    for (int j = 0; j < clip->skeleton.num_joints(); ++j)
      out[Key(file, clip->skeleton.joint(j).name, f)] = poses.position(f, j);
  }
  return out;
}

Positions ThreeReading(const std::string& file) {
  Positions out;
  std::istringstream lines(Run("node " + (RepoDir() / "viewer/test/bvh_positions.mjs").string() + " " + file + " " +
                               std::to_string(kFramesCompared)));
  std::string joint;
  int frame;
  float x, y, z;
  for (std::string line; std::getline(lines, line);) {
    std::istringstream fields(line);
    if (fields >> joint >> frame >> x >> y >> z) out[Key(file, joint, frame)] = Eigen::Vector3f(x, y, z);
  }
  return out;
}

Positions BlenderReading(const std::vector<std::string>& files) {
  std::string command = "blender -b --factory-startup --python " +
                        (RepoDir() / "tests/interop/blender_bvh_positions.py").string() + " -- " +
                        std::to_string(kFramesCompared);
  for (const std::string& file : files) command += " " + file;
  Positions out;
  std::istringstream lines(Run(command));
  std::string file, joint;
  int frame;
  float x, y, z;
  for (std::string line; std::getline(lines, line);) {
    std::istringstream fields(line);
    if (fields >> file >> joint >> frame >> x >> y >> z) out[Key(file, joint, frame)] = Eigen::Vector3f(x, y, z);
  }
  return out;
}

// Every joint and frame of `own` found in `theirs` within `tolerance`; returns how many compared.
int ExpectAgree(const Positions& own, const Positions& theirs, const std::map<std::string, float>& tolerance,
                const std::string& reader) {
  int compared = 0, missing = 0;
  for (const auto& [key, position] : own) {
    auto it = theirs.find(key);
    if (it == theirs.end()) {
      ++missing;
      continue;
    }
    const std::string file = key.substr(0, key.find(' '));
    EXPECT_LT((it->second - position).norm(), tolerance.at(file))
        << reader << ": " << key << " at " << it->second.transpose() << ", this reader " << position.transpose();
    ++compared;
  }
  EXPECT_EQ(missing, 0) << reader << " did not report " << missing << " of " << own.size() << " joint positions";
  return compared;
}

// Frames of each file made below with the product's writers (the readers compare the first
// kFramesCompared of them; the root checks take every frame).
constexpr int kOwnOutputFrames = 40;

// A walk whose world itself is Z up, as files from Z-up tools are (the z_up rig's root turn makes
// its world Y up): that rig with the turn taken off its root, RL_BoneRoot, and its translation
// turned with it, so every position is the Y-up walk's turned +90 deg about X (up +Z, the walk
// along -Y).
BvhClip ZUpWorldWalk(testing::SyntheticRigOptions options, int frames) {
  options.z_up = true;
  BvhClip clip = testing::MakeWalkingClip(options, frames);
  const int c = clip.skeleton.channel_start(0);  // RL_BoneRoot: X Y Z position, then its rotations
  for (int f = 0; f < clip.num_frames(); ++f) {
    const float y = clip.channels(f, c + 1), z = clip.channels(f, c + 2);
    clip.channels(f, c + 1) = -z;
    clip.channels(f, c + 2) = y;
    for (int k = 3; k < 6; ++k) clip.channels(f, c + k) = 0.0f;
  }
  return clip;
}

// testing::MakeSyntheticReconstructionSetup for walks of any making: `walk(frames)` gives a clip.
absl::StatusOr<testing::SyntheticReconstructionSetup> SetupFromWalks(const std::function<BvhClip(int)>& walk,
                                                                     int test_frames) {
  testing::SyntheticReconstructionSetup setup;
  auto rig = BuildRigModel(walk(90), {});
  if (!rig.ok()) return rig.status();
  setup.rig = *rig;
  std::vector<DatabaseClip> clips;
  for (int frames : {90, 61, 47}) {
    auto prepared = PrepareClip(walk(frames), setup.rig, {});
    if (!prepared.ok()) return prepared.status();
    clips.push_back({prepared->features, EncodePoses(prepared->motion, setup.rig)});
  }
  auto database = ReconstructionDatabase::Build(setup.rig, clips);
  if (!database.ok()) return database.status();
  setup.database = *database;
  auto test = PrepareClip(walk(test_frames), setup.rig, {});
  if (!test.ok()) return test.status();
  setup.test_clip = std::move(*test);
  setup.truth = ForwardKinematics(setup.test_clip.skeleton, setup.test_clip.motion);
  return setup;
}

// The offline reconstruction of the setup's test walk from its wrists (small candidate sets, as
// reconstruction_export_test does: the file's layout is under test, not the reconstruction).
absl::StatusOr<std::vector<ReconstructedFrame>> ReconstructTestWalk(
    const testing::SyntheticReconstructionSetup& setup) {
  ReconstructionOptions options;
  options.ankle_candidates = 40;
  options.pose_neighbours = 30;
  return ReconstructOffline(setup.database, options, testing::WristSamplesOf(setup));
}

class BvhConformanceTest : public ::testing::Test {
 protected:
  // Writes `clip` as the product writes every file; 1 mm in the clip's unit is the tolerance.
  void Write(const std::string& name, const BvhClip& clip, LengthUnit unit) {
    const std::string path = (dir_.path() / (name + ".bvh")).string();
    std::ofstream(path) << FormatBvh(clip);
    tolerance_[path] = static_cast<float>(0.001 / MetresPerUnit(unit));
    files_.push_back(path);
  }
  void CompareEveryReader() {
    Positions own;
    for (const std::string& file : files_) own.merge(OwnReading(file));
    ASSERT_FALSE(own.empty());
    if (std::system("command -v node >/dev/null 2>&1") != 0 ||
        !fs::exists(RepoDir() / "viewer/node_modules/three/package.json")) {
      ADD_FAILURE() << "three.js is not installed (node and npm ci in viewer/; scripts/setup.sh does both)";
    } else {
      Positions three;
      for (const std::string& file : files_) three.merge(ThreeReading(file));
      EXPECT_GT(ExpectAgree(own, three, tolerance_, "three.js BVHLoader"), 0);
    }
    if (std::system("command -v blender >/dev/null 2>&1") != 0) {
      GTEST_SKIP() << "blender is not installed (apt-get install blender; scripts/setup.sh does)";
    }
    EXPECT_GT(ExpectAgree(own, BlenderReading(files_), tolerance_, "Blender"), 0);
  }

  // What the root check needs of a file the product wrote: its rig's unit and turn to Y up, its
  // pelvis and the body's leg length in metres.
  struct WrittenRig {
    LengthUnit unit = LengthUnit::kCentimetre;
    Eigen::Quaternionf to_y_up = Eigen::Quaternionf::Identity();
    std::string pelvis;
    float leg_metres = 0.0f;
  };
  static WrittenRig RigOf(const RigModel& rig) {
    return {rig.unit, rig.to_y_up, rig.skeleton.joint(rig.topology.landmarks.pelvis).name,
            static_cast<float>(rig.topology.leg_length * MetresPerUnit(rig.unit))};
  }
  static WrittenRig RigOf(const RetargetRig& rig) {
    return {rig.unit, rig.to_y_up, rig.skeleton.joint(rig.topology.landmarks.pelvis).name, rig.leg_length};
  }
  // Write, for a file of `rig` that the root check covers.
  void WriteOwn(const std::string& name, const BvhClip& clip, const WrittenRig& rig) {
    Write(name, clip, rig.unit);
    rigs_[files_.back()] = rig;
  }
  // Issue #23: in every frame of every file written with WriteOwn, the root joint is not below the
  // floor (y >= -1 mm in metres, Y up: the file's unit and axes undone with its rig's), and it is
  // either still or on the ground under the body (within half a leg length of the pelvis,
  // horizontally). As this reader places the joints (CompareEveryReader holds the others to it).
  void ExpectRootsOnTheFloorUnderTheBody() {
    for (const auto& entry : rigs_) {
      const std::string& file = entry.first;
      const WrittenRig& rig = entry.second;
      SCOPED_TRACE(file);
      auto clip = ReadBvhFile(file);
      ASSERT_TRUE(clip.ok()) << clip.status();
      ASSERT_GT(clip->num_frames(), 0);
      const int pelvis = clip->skeleton.Find(rig.pelvis);
      ASSERT_GE(pelvis, 0) << "no joint " << rig.pelvis;
      const GlobalPoses poses =
          ForwardKinematics(clip->skeleton, MotionFromChannels(clip->skeleton, clip->channels, clip->frame_time));
      const float metres = static_cast<float>(MetresPerUnit(rig.unit));
      auto world = [&](int f, int j) -> Eigen::Vector3f { return rig.to_y_up * (metres * poses.position(f, j)); };
      float lowest = world(0, 0).y(), farthest = 0.0f, moved = 0.0f;
      int lowest_frame = 0, farthest_frame = 0;
      for (int f = 0; f < poses.num_frames(); ++f) {
        const Eigen::Vector3f root = world(f, 0), apart = world(f, pelvis) - root;
        moved = std::max(moved, (root - world(0, 0)).norm());
        if (root.y() < lowest) {
          lowest = root.y();
          lowest_frame = f;
        }
        const float horizontal = Eigen::Vector2f(apart.x(), apart.z()).norm();
        if (horizontal > farthest) {
          farthest = horizontal;
          farthest_frame = f;
        }
      }
      EXPECT_GE(lowest, -1e-3f) << "root " << -lowest << " m below the floor at frame " << lowest_frame;
      if (moved >= 1e-3f) {
        EXPECT_LE(farthest, 0.5f * rig.leg_metres)
            << "the root moves (by up to " << moved << " m) and is " << farthest << " m from the pelvis (" << rig.pelvis
            << ") at frame " << farthest_frame << ", legs " << rig.leg_metres << " m";
      }
    }
  }

  testing::ScopedTempDir dir_;
  std::vector<std::string> files_;
  std::map<std::string, float> tolerance_;
  std::map<std::string, WrittenRig> rigs_;
};

// Synthetic rigs covering each root and channel convention the product writes: hip height in
// the root OFFSET, a static root above the hips (Bandai), position channels on every joint,
// a Z-up hierarchy under a rotated root (cmu-cc), and a root whose channels already hold the
// position (Mixamo).
TEST_F(BvhConformanceTest, EveryReaderPlacesWrittenSyntheticFilesAlike) {
  Write("walk", testing::MakeWalkingClip({}, 12), LengthUnit::kCentimetre);
  Write("static_root", testing::MakeWalkingClip({.extra_root = true}, 12), LengthUnit::kCentimetre);
  Write("bandai_like", testing::MakeWalkingClip({.extra_root = true, .position_channels_everywhere = true}, 12),
        LengthUnit::kCentimetre);
  Write("z_up", testing::MakeWalkingClip({.z_up = true, .twist_bones = true}, 12), LengthUnit::kCentimetre);
  BvhClip absolute = testing::MakeWalkingClip({.rotation_order = "XYZ"}, 12);
  for (int axis = 0; axis < 3; ++axis) absolute.channels.col(axis).array() += absolute.skeleton.joint(0).offset[axis];
  auto mixamo = ParseBvh(FormatBvh(absolute), "mixamo_like.bvh");
  ASSERT_TRUE(mixamo.ok());
  Write("mixamo_like", *mixamo, LengthUnit::kCentimetre);
  CompareEveryReader();
}

// Real files of every shared set, read and written again.
TEST_F(BvhConformanceTest, EveryReaderPlacesRewrittenSharedFilesAlike) {
  MOCAP_REQUIRE_SHARED_DATA(bandai, "bandai-namco-1");
  MOCAP_REQUIRE_SHARED_DATA(cmu, "cmu-cc");
  MOCAP_REQUIRE_SHARED_DATA(other, "other-rigs");
  const std::vector<std::pair<fs::path, LengthUnit>> sources = {
      {bandai / "dataset-1_walk_normal_001.bvh", LengthUnit::kCentimetre},
      {cmu / "002_01.bvh", LengthUnit::kCentimetre},
      {cmu / "001_01.bvh", LengthUnit::kCentimetre},
      {other / "pymo_AV_8Walk_Meredith_HVHA_Rep1.bvh", LengthUnit::kInch},
      {other / "mixamo_test_freebvh.bvh", LengthUnit::kCentimetre},
      {other / "xia_dme_neutral_01_000.bvh", LengthUnit::kCmuUnit},
  };
  for (const auto& [path, unit] : sources) {
    if (!fs::exists(path)) continue;
    auto clip = ReadBvhFile(path);
    ASSERT_TRUE(clip.ok()) << clip.status();
    Write(path.stem().string(), *clip, unit);
    // The written file is the file as read: every joint where it was.
    const Positions before = OwnReading(path.string());
    const Positions after = OwnReading(files_.back());
    for (const auto& [key, position] : before) {
      const std::string rest = key.substr(key.find(' '));
      auto it = after.find(files_.back() + rest);
      ASSERT_NE(it, after.end()) << rest;
      EXPECT_LT((it->second - position).norm(), tolerance_[files_.back()]) << path.filename() << rest;
    }
  }
  ASSERT_GE(files_.size(), 4u);
  CompareEveryReader();
}

// Every kind of file the product writes, made by its own writers, read alike by every reader and
// with its root on the floor, still or under the body (issue #23):
//  - reconstructions on the database's rig (ReconstructionToBvh: the service's and mocap-eval's
//    files) of rigs with the hips as root, with a static root above the pelvis (Bandai), with a
//    Z-up hierarchy whose pelvis has no position channels (cmu-cc) and with a Z-up world;
//  - one of them retargeted onto other rigs (RetargetedToBvh, as `mocap reconstruct` writes it
//    for a target rig): metres with 6 channels on every joint, a Z-up hierarchy in inches, a Z-up
//    world;
//  - prepared clips in centimetres exported (ToFileConventions: `mocap export`).
TEST_F(BvhConformanceTest, EveryReaderPlacesTheProductsOwnOutputsAlike) {
  // 1. Reconstructions on the database's rig.
  std::vector<std::pair<std::string, testing::SyntheticReconstructionSetup>> setups;
  setups.emplace_back("reconstruction_static_root",
                      testing::MakeSyntheticReconstructionSetup({.extra_root = true}, kOwnOutputFrames));
  setups.emplace_back("reconstruction_hips_root", testing::MakeSyntheticReconstructionSetup({}, kOwnOutputFrames));
  setups.emplace_back("reconstruction_z_up_rig",
                      testing::MakeSyntheticReconstructionSetup(testing::SyntheticRigFromBits(2), kOwnOutputFrames));
  auto z_up_world = SetupFromWalks([](int frames) { return ZUpWorldWalk({}, frames); }, kOwnOutputFrames);
  ASSERT_TRUE(z_up_world.ok()) << z_up_world.status();
  ASSERT_EQ(z_up_world->rig.topology.up_axis, 2) << "the world is Z up";
  setups.emplace_back("reconstruction_z_up_world", std::move(*z_up_world));
  std::vector<std::vector<ReconstructedFrame>> reconstructions;
  for (const auto& [name, setup] : setups) {
    auto frames = ReconstructTestWalk(setup);
    ASSERT_TRUE(frames.ok()) << name << ": " << frames.status();
    ASSERT_FALSE(frames->empty()) << name;
    WriteOwn(name, ReconstructionToBvh(*setup.database, *frames), RigOf(setup.database->rig()));
    reconstructions.push_back(*std::move(frames));
  }
  EXPECT_GT(setups[0].second.rig.topology.landmarks.pelvis, 0) << "a root above the pelvis";

  // 2. The first reconstruction on other rigs.
  const testing::SyntheticReconstructionSetup& performer = setups.front().second;
  auto source = SourceRigOf(performer.database->rig(), performer.database->body().skeleton());
  ASSERT_TRUE(source.ok()) << source.status();
  const std::vector<std::pair<std::string, BvhClip>> targets = {
      {"retargeted_metres",
       testing::MakeWalkingClip({.extra_root = true, .position_channels_everywhere = true, .length_scale = 0.01}, 60)},
      {"retargeted_z_up_inches", testing::MakeWalkingClip({.z_up = true, .length_scale = 1.0 / 2.54}, 60)},
      {"retargeted_z_up_world", ZUpWorldWalk({}, 60)},
  };
  for (const auto& [name, target_clip] : targets) {
    auto target = TargetRigFromBvh(FormatBvh(target_clip));
    ASSERT_TRUE(target.ok()) << name << ": " << target.status();
    auto retargeter = Retargeter::Create(*source, *target);
    ASSERT_TRUE(retargeter.ok()) << name << ": " << retargeter.status();
    std::vector<BodyPose> poses(reconstructions.front().size());
    for (size_t f = 0; f < poses.size(); ++f)
      retargeter->Retarget(performer.database->body(), reconstructions.front()[f].pose, &poses[f]);
    // As `mocap reconstruct` writes it (client/cli/target_rig_file.cc): a pelvis under other
    // joints without position channels gets them, so that it carries the motion.
    RetargetRig rig = retargeter->target();
    rig.skeleton = WithPelvisPositionChannels(rig.skeleton, rig.topology.landmarks.pelvis);
    WriteOwn(name, RetargetedToBvh(rig, poses, performer.database->frame_time()), RigOf(rig));
  }

  // 3. Prepared clips in centimetres, exported.
  const std::vector<std::pair<std::string, BvhClip>> captures = {
      {"exported_hips_root", testing::MakeWalkingClip({}, kOwnOutputFrames)},
      {"exported_bandai_like",
       testing::MakeWalkingClip({.extra_root = true, .position_channels_everywhere = true}, kOwnOutputFrames)},
      {"exported_z_up_world", ZUpWorldWalk({.extra_root = true}, kOwnOutputFrames)},
  };
  for (const auto& [name, capture] : captures) {
    auto rig = BuildRigModel(capture, {});
    ASSERT_TRUE(rig.ok()) << name << ": " << rig.status();
    ASSERT_EQ(rig->unit, LengthUnit::kCentimetre) << name;
    auto prepared = PrepareClip(capture, *rig, {});
    ASSERT_TRUE(prepared.ok()) << name << ": " << prepared.status();
    WriteOwn(name, ToFileConventions(prepared->skeleton, prepared->motion, *rig), RigOf(*rig));
  }

  ASSERT_EQ(files_.size(), 10u);
  ExpectRootsOnTheFloorUnderTheBody();
  CompareEveryReader();
}

}  // namespace
}  // namespace mocap
