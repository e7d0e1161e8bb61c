// Files the product writes, read back by independent readers: Blender's importer (headless) and
// three.js's BVHLoader (node, the viewer's copy). Every joint of every frame must be where this
// reader puts it, within 1 mm (issue #23: "BVH exactly as the tools read it"). Readers that are
// not installed are skipped with a message (scripts/setup.sh installs both).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "motion/bvh/bvh_reader.h"
#include "motion/bvh/bvh_writer.h"
#include "motion/core/units.h"
#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/local_motion.h"
#include "tests/support/shared_data.h"
#include "tests/support/synthetic_clip.h"
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

  testing::ScopedTempDir dir_;
  std::vector<std::string> files_;
  std::map<std::string, float> tolerance_;
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

}  // namespace
}  // namespace mocap
