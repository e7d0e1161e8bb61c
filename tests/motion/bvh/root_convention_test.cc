// The root's position channels read as each file means them, and files written so that every
// reader (OFFSET + channels, or channels alone as Blender and three.js read them) agrees.
#include "motion/bvh/root_convention.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "motion/bvh/bvh_reader.h"
#include "motion/bvh/bvh_writer.h"
#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/local_motion.h"
#include "tests/support/shared_data.h"
#include "tests/support/synthetic_clip.h"

namespace mocap {
namespace {

GlobalPoses WorldPoses(const BvhClip& clip) {
  return ForwardKinematics(clip.skeleton, MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time));
}

// The largest distance between the same joint in two readings of a clip.
float LargestDifference(const GlobalPoses& a, const GlobalPoses& b) {
  return std::sqrt(((a.px - b.px).square() + (a.py - b.py).square() + (a.pz - b.pz).square()).maxCoeff());
}

// The lowest joint over the clip along Y.
float Lowest(const BvhClip& clip) { return WorldPoses(clip).py.minCoeff(); }

// What a channels-only reader sees: the same file with the root OFFSET taken as zero.
BvhClip ReadChannelsOnly(BvhClip clip) {
  std::vector<Joint> joints = clip.skeleton.joints();
  joints[0].offset.setZero();
  clip.skeleton = Skeleton(std::move(joints));
  return clip;
}

// The synthetic walk keeps the hip height in the root OFFSET and travel in the channels, as the
// cmu-cc files rooted at the hip do: OFFSET + channels.
TEST(RootConventionTest, HipHeightInTheOffsetIsAddedToTheChannels) {
  const BvhClip walk = testing::MakeWalkingClip();
  ASSERT_GT(walk.skeleton.joint(0).offset.y(), 50.0f);
  EXPECT_EQ(DecideRootPositionReading(walk), RootPositionReading::kOffsetPlusChannels);
  auto parsed = ParseBvh(FormatBvh(walk), "walk.bvh");
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  EXPECT_LT(std::abs(Lowest(*parsed)), 10.0f);  // feet on the floor
}

// Mixamo-style: the channels are the root's position, the OFFSET repeats the rest height and the
// common readers ignore it. Read as the sum, the body would float a hip height above the floor.
TEST(RootConventionTest, ChannelsThatAlreadyHoldThePositionIgnoreTheOffset) {
  BvhClip walk = testing::MakeWalkingClip();
  const Eigen::Vector3f rest = walk.skeleton.joint(0).offset;
  for (int axis = 0; axis < 3; ++axis) walk.channels.col(axis).array() += rest[axis];  // absolute channels
  EXPECT_EQ(DecideRootPositionReading(walk), RootPositionReading::kChannelsOnly);
  BvhClip normalised = walk;
  NormaliseRootPosition(normalised);
  EXPECT_EQ(normalised.root_reading, RootPositionReading::kChannelsOnly);
  EXPECT_TRUE(normalised.skeleton.joint(0).offset.isZero());
  EXPECT_LT(LargestDifference(WorldPoses(normalised), WorldPoses(ReadChannelsOnly(walk))), 1e-4f);
  EXPECT_LT(std::abs(Lowest(normalised)), 10.0f);
  // Also at twice the scale (an exporter's scale setting), and with a horizontal OFFSET part.
  for (const float scale : {2.0f, 0.01f}) {
    BvhClip scaled = walk;
    std::vector<Joint> joints = scaled.skeleton.joints();
    for (Joint& joint : joints) joint.offset *= scale;
    joints[0].offset.x() += 30.0f * scale;
    scaled.skeleton = Skeleton(std::move(joints));
    for (int axis = 0; axis < 3; ++axis) scaled.channels.col(axis) *= scale;
    EXPECT_EQ(DecideRootPositionReading(scaled), RootPositionReading::kChannelsOnly) << scale;
  }
}

TEST(RootConventionTest, ZeroOffsetIsUnambiguous) {
  BvhClip walk = testing::MakeWalkingClip();
  MakeReadersAgree(walk);
  EXPECT_TRUE(walk.skeleton.joint(0).offset.isZero());
  EXPECT_EQ(DecideRootPositionReading(walk), RootPositionReading::kUnambiguous);
  EXPECT_EQ(DecideRootPositionReading(testing::MakeWalkingClip({.extra_root = true})),
            RootPositionReading::kUnambiguous);
}

// Every file the product writes reads the same with the OFFSET added and with it ignored.
TEST(RootConventionTest, WrittenFilesReadTheSameEitherWay) {
  for (const bool extra_root : {false, true}) {
    const BvhClip walk = testing::MakeWalkingClip({.extra_root = extra_root});
    auto parsed = ParseBvh(FormatBvh(walk), "walk.bvh");
    ASSERT_TRUE(parsed.ok()) << parsed.status();
    EXPECT_TRUE(parsed->skeleton.joint(0).offset.isZero());
    EXPECT_LT(LargestDifference(WorldPoses(*parsed), WorldPoses(walk)), 1e-3f);
    EXPECT_LT(LargestDifference(WorldPoses(ReadChannelsOnly(*parsed)), WorldPoses(walk)), 1e-3f);
  }
}

// Declared sizes the text cannot hold are refused before anything is allocated (issue #24, 5).
TEST(RootConventionTest, FrameCountsTheTextCannotHoldAreRefusedBeforeAllocating) {
  std::string text = FormatBvh(testing::MakeWalkingClip({}, 2));
  const size_t at = text.find("Frames: 2");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 9, "Frames: 5000000");
  auto parsed = ParseBvh(text, "huge.bvh");
  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.status().message().find("truncated"), std::string_view::npos) << parsed.status();
}

// Real files of both conventions: the cmu-cc files rooted at the hip (hip height in the root
// OFFSET) need the sum; every other-rigs file is read with its feet on the floor on its first
// frame (none starts off the ground), whatever its root OFFSET.
TEST(RootConventionSharedDataTest, RealFilesAreReadAsTheirExportersMeantThem) {
  MOCAP_REQUIRE_SHARED_DATA(other_rigs, "other-rigs");
  MOCAP_REQUIRE_SHARED_DATA(cmu, "cmu-cc");
  int hip_rooted = 0;
  for (const auto& file : testing::BvhFilesIn(cmu)) {
    std::ifstream in(file);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (text.find("ROOT CC_Base_Hip") == std::string::npos) continue;
    auto clip = ParseBvh(text, file.string());
    ASSERT_TRUE(clip.ok()) << clip.status();
    EXPECT_EQ(clip->root_reading, RootPositionReading::kOffsetPlusChannels) << file.filename();
    ++hip_rooted;
  }
  EXPECT_GT(hip_rooted, 30);
  int checked = 0;
  for (const auto& file : testing::BvhFilesIn(other_rigs)) {
    auto clip = ReadBvhFile(file);
    ASSERT_TRUE(clip.ok()) << clip.status();
    const GlobalPoses poses = WorldPoses(*clip);
    const float extent_y = poses.py.row(0).maxCoeff() - poses.py.row(0).minCoeff();
    const float extent_z = poses.pz.row(0).maxCoeff() - poses.pz.row(0).minCoeff();
    const float lowest = extent_y >= extent_z ? poses.py.row(0).minCoeff() : poses.pz.row(0).minCoeff();
    EXPECT_LT(std::abs(lowest), 0.2f * std::max(extent_y, extent_z)) << file.filename();
    ++checked;
  }
  EXPECT_GT(checked, 10);
}

}  // namespace
}  // namespace mocap
