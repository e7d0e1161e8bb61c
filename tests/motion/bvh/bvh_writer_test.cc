#include "motion/bvh/bvh_writer.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "motion/bvh/bvh_reader.h"
#include "motion/bvh/root_convention.h"
#include "tests/support/shared_data.h"
#include "tests/support/synthetic_clip.h"

namespace mocap {
namespace {

// Float values equal up to float rounding (the writer prints the shortest round-trip form, so in
// practice they are identical).
bool CloseFloat(float a, float b) { return std::abs(a - b) <= 1e-6f * std::max({1.0f, std::abs(a), std::abs(b)}); }

// `written` as the writer means it: offsets under position channels are written as zero, the
// root's inside its channels (root_convention.h), so that every reader places it alike.
::testing::AssertionResult SameClip(const BvhClip& written, const BvhClip& actual) {
  BvhClip expected = written;
  MakeReadersAgree(expected);
  const Skeleton& a = expected.skeleton;
  const Skeleton& b = actual.skeleton;
  if (a.num_joints() != b.num_joints()) {
    return ::testing::AssertionFailure() << a.num_joints() << " joints became " << b.num_joints();
  }
  for (int j = 0; j < a.num_joints(); ++j) {
    const Joint& x = a.joint(j);
    const Joint& y = b.joint(j);
    if (x.name != y.name || x.parent != y.parent || x.channels != y.channels) {
      return ::testing::AssertionFailure() << "joint " << j << " '" << x.name << "' became '" << y.name << "'";
    }
    for (int axis = 0; axis < 3; ++axis) {
      if (!CloseFloat(x.offset[axis], y.offset[axis])) {
        return ::testing::AssertionFailure()
               << "OFFSET of " << x.name << ": " << x.offset.transpose() << " became " << y.offset.transpose();
      }
    }
    if (x.end_site.has_value() != y.end_site.has_value()) {
      return ::testing::AssertionFailure() << "End Site of " << x.name << " appeared or vanished";
    }
    for (int axis = 0; x.end_site && axis < 3; ++axis) {
      if (!CloseFloat((*x.end_site)[axis], (*y.end_site)[axis])) {
        return ::testing::AssertionFailure() << "End Site of " << x.name << " differs";
      }
    }
  }
  if (std::abs(expected.frame_time - actual.frame_time) > 1e-7 * expected.frame_time) {
    return ::testing::AssertionFailure() << "frame time " << expected.frame_time << " became " << actual.frame_time;
  }
  if (expected.channels.rows() != actual.channels.rows() || expected.channels.cols() != actual.channels.cols()) {
    return ::testing::AssertionFailure() << expected.channels.rows() << "x" << expected.channels.cols()
                                         << " channels became " << actual.channels.rows() << "x"
                                         << actual.channels.cols();
  }
  for (int f = 0; f < expected.channels.rows(); ++f) {
    for (int c = 0; c < expected.channels.cols(); ++c) {
      if (!CloseFloat(expected.channels(f, c), actual.channels(f, c))) {
        return ::testing::AssertionFailure() << "frame " << f << " channel " << c << ": " << expected.channels(f, c)
                                             << " became " << actual.channels(f, c);
      }
    }
  }
  return ::testing::AssertionSuccess();
}

struct RigCase {
  std::string name;
  testing::SyntheticRigOptions options;
};

std::vector<RigCase> RigCases() {
  std::vector<RigCase> cases;
  cases.push_back({"Plain", {}});
  testing::SyntheticRigOptions o;
  o.extra_root = true;
  cases.push_back({"ExtraRoot", o});
  o = {};
  o.z_up = true;
  cases.push_back({"ZUp", o});
  o = {};
  o.fingers_and_toes = true;
  cases.push_back({"FingersAndToes", o});
  o = {};
  o.twist_bones = true;
  cases.push_back({"TwistBones", o});
  o = {};
  o.position_channels_everywhere = true;
  cases.push_back({"PositionChannelsEverywhere", o});
  o = {};
  o.length_scale = 0.01;
  cases.push_back({"Metres", o});
  o = {};
  o.length_scale = 1 / 2.54;
  cases.push_back({"Inches", o});
  for (const char* order : {"XYZ", "XZY", "YXZ", "YZX", "ZYX"}) {
    o = {};
    o.rotation_order = order;
    cases.push_back({std::string("Order") + order, o});
  }
  o = {};
  o.extra_root = o.z_up = o.fingers_and_toes = o.twist_bones = o.position_channels_everywhere = true;
  o.length_scale = 0.01;
  o.rotation_order = "YZX";
  cases.push_back({"Everything", o});
  o.extra_root = false;
  cases.push_back({"EverythingButExtraRoot", o});
  return cases;
}

class BvhWriterSyntheticTest : public ::testing::TestWithParam<RigCase> {};

TEST_P(BvhWriterSyntheticTest, RoundTrips) {
  const BvhClip clip = testing::MakeWalkingClip(GetParam().options, 45);
  ASSERT_TRUE(clip.skeleton.Validate().ok()) << clip.skeleton.Validate();
  const std::string text = FormatBvh(clip);
  absl::StatusOr<BvhClip> parsed = ParseBvh(text, "synthetic.bvh");
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  EXPECT_TRUE(SameClip(clip, *parsed));
  // Formatting what was read gives the same text again.
  EXPECT_EQ(FormatBvh(*parsed).substr(0, text.find("Frame Time:")), text.substr(0, text.find("Frame Time:")));
}

INSTANTIATE_TEST_SUITE_P(BvhWriterRigs, BvhWriterSyntheticTest, ::testing::ValuesIn(RigCases()),
                         [](const ::testing::TestParamInfo<RigCase>& info) { return info.param.name; });

TEST(BvhWriterTest, FormatSanity) {
  const BvhClip clip = testing::MakeWalkingClip({}, 12);
  const std::string text = FormatBvh(clip);
  EXPECT_EQ(text.rfind("HIERARCHY\nROOT Hips\n", 0), 0u);
  EXPECT_EQ(text.find('\r'), std::string::npos);
  EXPECT_NE(text.find("\nMOTION\nFrames: 12\nFrame Time: "), std::string::npos);
  EXPECT_NE(text.find("End Site"), std::string::npos);
  EXPECT_EQ(text.back(), '\n');
  // One line per frame after the headers, each with every channel.
  const std::string motion = text.substr(text.find("Frame Time: "));
  std::istringstream lines(motion);
  std::string line;
  std::getline(lines, line);  // Frame Time
  int frames = 0;
  while (std::getline(lines, line)) {
    std::istringstream values(line);
    int count = 0;
    std::string value;
    while (values >> value) ++count;
    EXPECT_EQ(count, clip.skeleton.num_channels()) << "frame " << frames;
    ++frames;
  }
  EXPECT_EQ(frames, 12);
  // Balanced braces.
  EXPECT_EQ(std::count(text.begin(), text.end(), '{'), std::count(text.begin(), text.end(), '}'));
}

TEST(BvhWriterTest, ZeroIsNotWrittenNegative) {
  BvhClip clip = testing::MakeWalkingClip({}, 2);
  clip.channels(1, 3) = -0.0f;
  const std::string text = FormatBvh(clip);
  EXPECT_EQ(text.find("-0 "), std::string::npos);
}

TEST(BvhWriterTest, JointsWithoutChannelsKeepNoChannels) {
  std::vector<Joint> joints(3);
  joints[0] = Joint{.name = "Root", .parent = -1, .channels = {ChannelType::kYposition, ChannelType::kYrotation}};
  joints[1] = Joint{.name = "Static", .parent = 0, .offset = Eigen::Vector3f(0, 1, 0)};
  joints[2] = Joint{.name = "Tip",
                    .parent = 1,
                    .offset = Eigen::Vector3f(0, 1, 0),
                    .channels = {ChannelType::kXrotation},
                    .end_site = Eigen::Vector3f(0, 0.5f, 0)};
  BvhClip clip;
  clip.skeleton = Skeleton(std::move(joints));
  clip.frame_time = 0.01;
  clip.channels.resize(2, 3);
  clip.channels << 1, 2, 3, 4.25f, -5.5f, 6e-5f;
  absl::StatusOr<BvhClip> parsed = ParseBvh(FormatBvh(clip), "static.bvh");
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  EXPECT_TRUE(SameClip(clip, *parsed));
}

// A Skeleton only promises parents before children; a breadth-first order is valid. The writer
// emits the hierarchy depth-first, so the frame rows must follow the joints they belong to.
TEST(BvhWriterTest, NonDepthFirstJointOrderKeepsValuesWithTheirJoints) {
  std::vector<Joint> joints;
  const std::vector<ChannelType> rotations = {ChannelType::kZrotation, ChannelType::kXrotation,
                                              ChannelType::kYrotation};
  joints.push_back(Joint{.name = "Hips",
                         .parent = -1,
                         .offset = Eigen::Vector3f::Zero(),  // (a root OFFSET would be written into its channels)
                         .channels = {ChannelType::kXposition, ChannelType::kYposition, ChannelType::kZposition,
                                      ChannelType::kZrotation, ChannelType::kXrotation, ChannelType::kYrotation}});
  joints.push_back(Joint{.name = "LeftUpLeg", .parent = 0, .offset = Eigen::Vector3f(9, -6, 0), .channels = rotations});
  joints.push_back(
      Joint{.name = "RightUpLeg", .parent = 0, .offset = Eigen::Vector3f(-9, -6, 0), .channels = rotations});
  joints.push_back(Joint{.name = "LeftLeg",
                         .parent = 1,
                         .offset = Eigen::Vector3f(0, -43, 0),
                         .channels = rotations,
                         .end_site = Eigen::Vector3f(0, -42, 0)});
  joints.push_back(Joint{.name = "RightLeg",
                         .parent = 2,
                         .offset = Eigen::Vector3f(0, -43, 0),
                         .channels = rotations,
                         .end_site = Eigen::Vector3f(0, -42, 0)});
  BvhClip clip;
  clip.skeleton = Skeleton(std::move(joints));
  ASSERT_TRUE(clip.skeleton.Validate().ok());
  clip.frame_time = 1.0 / 30;
  clip.channels.resize(2, clip.skeleton.num_channels());
  for (int c = 0; c < clip.channels.cols(); ++c) {
    clip.channels(0, c) = static_cast<float>(c);
    clip.channels(1, c) = static_cast<float>(100 + c);
  }
  absl::StatusOr<BvhClip> parsed = ParseBvh(FormatBvh(clip), "bfs.bvh");
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  ASSERT_EQ(parsed->skeleton.num_joints(), clip.skeleton.num_joints());
  for (int j = 0; j < clip.skeleton.num_joints(); ++j) {
    const Joint& joint = clip.skeleton.joint(j);
    const int k = parsed->skeleton.Find(joint.name);
    ASSERT_GE(k, 0) << joint.name;
    EXPECT_EQ(parsed->skeleton.joint(parsed->skeleton.parent(k) < 0 ? 0 : parsed->skeleton.parent(k)).name,
              clip.skeleton.joint(joint.parent < 0 ? 0 : joint.parent).name);
    std::ostringstream written, read;
    for (size_t c = 0; c < joint.channels.size(); ++c) {
      written << " " << clip.channels(0, clip.skeleton.channel_start(j) + static_cast<int>(c));
      read << " " << parsed->channels(0, parsed->skeleton.channel_start(k) + static_cast<int>(c));
    }
    EXPECT_EQ(read.str(), written.str()) << "frame 0 channels of " << joint.name;
  }
}

TEST(BvhWriterTest, WritesFilesAtomically) {
  const std::filesystem::path folder = std::filesystem::path(::testing::TempDir()) / "bvh_writer_test";
  std::filesystem::create_directories(folder);
  const std::filesystem::path path = folder / "walk.bvh";
  const BvhClip clip = testing::MakeWalkingClip({.fingers_and_toes = true}, 20);
  ASSERT_TRUE(WriteBvhFile(clip, path).ok());
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
  absl::StatusOr<BvhClip> read = ReadBvhFile(path);
  ASSERT_TRUE(read.ok()) << read.status();
  EXPECT_TRUE(SameClip(clip, *read));
  // Overwriting replaces the content.
  const BvhClip shorter = testing::MakeWalkingClip({}, 3);
  ASSERT_TRUE(WriteBvhFile(shorter, path).ok());
  read = ReadBvhFile(path);
  ASSERT_TRUE(read.ok()) << read.status();
  EXPECT_TRUE(SameClip(shorter, *read));
  std::filesystem::remove_all(folder);
}

TEST(BvhWriterTest, FailsInAMissingFolder) {
  const BvhClip clip = testing::MakeWalkingClip({}, 2);
  const absl::Status status =
      WriteBvhFile(clip, std::filesystem::path(::testing::TempDir()) / "no_such_folder_xyz" / "walk.bvh");
  EXPECT_FALSE(status.ok());
}

class BvhWriterSharedDataTest : public ::testing::TestWithParam<const char*> {};

TEST_P(BvhWriterSharedDataTest, RealFilesRoundTrip) {
  MOCAP_REQUIRE_SHARED_DATA(folder, GetParam());
  const std::vector<std::filesystem::path> files = testing::BvhFilesIn(folder);
  ASSERT_FALSE(files.empty());
  // A handful spread over the sorted list.
  std::vector<std::filesystem::path> chosen;
  for (size_t i : {size_t{0}, files.size() / 3, files.size() / 2, 2 * files.size() / 3, files.size() - 1}) {
    if (std::find(chosen.begin(), chosen.end(), files[i]) == chosen.end()) chosen.push_back(files[i]);
  }
  for (const std::filesystem::path& path : chosen) {
    SCOPED_TRACE(path.string());
    absl::StatusOr<BvhClip> original = ReadBvhFile(path);
    ASSERT_TRUE(original.ok()) << original.status();
    absl::StatusOr<BvhClip> again = ParseBvh(FormatBvh(*original), "rewritten.bvh");
    ASSERT_TRUE(again.ok()) << again.status();
    EXPECT_TRUE(SameClip(*original, *again));
  }
}

INSTANTIATE_TEST_SUITE_P(BvhWriterSets, BvhWriterSharedDataTest,
                         ::testing::Values("bandai-namco-1", "bandai-namco-2", "cmu-cc"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

}  // namespace
}  // namespace mocap
