#include "motion/bvh/bvh_reader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "tests/support/shared_data.h"

namespace mocap {
namespace {

// Whether `text` contains `part`; the message shows both.
::testing::AssertionResult HasSubstr(std::string_view text, std::string_view part) {
  if (text.find(part) != std::string_view::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
}

std::filesystem::path MalformedDir() { return testing::TestDataDir() / "bvh" / "malformed"; }
std::filesystem::path ValidDir() { return testing::TestDataDir() / "bvh" / "valid"; }

std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// ---------------------------------------------------------------------------------------------
// Malformed corpus: every file is rejected with "FILE:LINE: specific phrase".

struct MalformedCase {
  const char* file;
  int line;
  const char* phrase;
};

void PrintTo(const MalformedCase& c, std::ostream* os) { *os << c.file; }

constexpr MalformedCase kMalformedCases[] = {
    {"truncated_motion.bvh.txt", 21, "truncated motion block: 'Frames: 3' but the file ends after 2 frames"},
    {"wrong_value_count.bvh.txt", 20, "frame 1 has 8 values; the hierarchy declares 9"},
    {"too_many_values.bvh.txt", 20, "frame 1 has more than the 9 values"},
    {"nan_value.bvh.txt", 20, "expected a finite number, found 'nan'"},
    {"inf_value.bvh.txt", 20, "expected a finite number, found '-inf'"},
    {"garbage_value.bvh.txt", 20, "expected a finite number, found '8x'"},
    {"unknown_channel.bvh.txt", 9, "unknown channel 'Wrotation' on joint 'Spine'"},
    {"channel_count_7.bvh.txt", 5, "expected a channel count from 0 to 6, found '7'"},
    {"repeated_channel.bvh.txt", 9, "channel 'Zrotation' repeated on joint 'Spine'"},
    {"missing_close_brace.bvh.txt", 15, "unbalanced braces: joint 'Hips' is not closed before 'MOTION'"},
    {"extra_close_brace.bvh.txt", 16, "expected 'MOTION', found '}'"},
    {"duplicate_joint_names.bvh.txt", 10, "duplicate joint name 'Spine'"},
    {"zero_frame_time.bvh.txt", 18, "frame time 0 s is outside"},
    {"absurd_frame_time.bvh.txt", 18, "frame time 50 s is outside"},
    {"negative_frame_count.bvh.txt", 17, "frame count -2 outside 1.."},
    {"fractional_frame_count.bvh.txt", 17, "expected a whole frame count after 'Frames:', found '2.5'"},
    {"missing_frames_line.bvh.txt", 17, "expected 'Frames: N', found 'Frame Time: 0.0333333'"},
    {"missing_frame_time.bvh.txt", 18, "expected 'Frame Time: T', found '0 0 0 0 0 0 0 0 0'"},
    {"missing_motion.bvh.txt", 16, "expected 'MOTION', found end of file"},
    {"non_numeric_offset.bvh.txt", 8, "expected a finite number for OFFSET of Spine, found 'ten'"},
    {"short_offset.bvh.txt", 9, "expected a finite number for OFFSET of Spine, found 'CHANNELS'"},
    {"two_end_sites.bvh.txt", 17, "joint 'Spine' has two End Sites"},
    {"empty.bvh.txt", 1, "expected 'HIERARCHY', found end of file"},
    {"binary_garbage.bvh.txt", 1, "expected 'HIERARCHY', found '"},
    {"second_root.bvh.txt", 16, "a second ROOT is not supported"},
    {"data_after_frames.bvh.txt", 21, "unexpected data after the 2 declared frames"},
};

class BvhReaderMalformedTest : public ::testing::TestWithParam<MalformedCase> {};

TEST_P(BvhReaderMalformedTest, RejectsWithFileLineAndReason) {
  const MalformedCase& c = GetParam();
  const std::filesystem::path path = MalformedDir() / c.file;
  ASSERT_TRUE(std::filesystem::exists(path)) << path;
  absl::StatusOr<BvhClip> clip = ReadBvhFile(path);
  ASSERT_FALSE(clip.ok()) << c.file << " was accepted";
  EXPECT_EQ(clip.status().code(), absl::StatusCode::kInvalidArgument) << clip.status();
  const std::string message(clip.status().message());
  EXPECT_TRUE(HasSubstr(message, c.file));
  EXPECT_TRUE(HasSubstr(message, ":" + std::to_string(c.line) + ": ")) << message;
  EXPECT_TRUE(HasSubstr(message, c.phrase));

  // The same text through ParseBvh names the given source.
  absl::StatusOr<BvhClip> parsed = ParseBvh(ReadText(path), "memory.bvh");
  ASSERT_FALSE(parsed.ok());
  EXPECT_TRUE(HasSubstr(parsed.status().ToString(), "memory.bvh:" + std::to_string(c.line) + ": "));
}

INSTANTIATE_TEST_SUITE_P(BvhMalformedCorpus, BvhReaderMalformedTest, ::testing::ValuesIn(kMalformedCases),
                         [](const ::testing::TestParamInfo<MalformedCase>& info) {
                           std::string name = info.param.file;
                           name = name.substr(0, name.find('.'));
                           for (char& ch : name) {
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           }
                           return name;
                         });

TEST(BvhReaderTest, MalformedCorpusIsCoveredByTheTable) {
  std::vector<std::string> listed;
  for (const MalformedCase& c : kMalformedCases) listed.push_back(c.file);
  for (const auto& entry : std::filesystem::directory_iterator(MalformedDir())) {
    const std::string name = entry.path().filename().string();
    EXPECT_NE(std::find(listed.begin(), listed.end(), name), listed.end()) << name << " has no table entry";
  }
}

TEST(BvhReaderTest, MissingFileIsNotFound) {
  absl::StatusOr<BvhClip> clip = ReadBvhFile(MalformedDir() / "no_such_file.bvh");
  ASSERT_FALSE(clip.ok());
  EXPECT_EQ(clip.status().code(), absl::StatusCode::kNotFound);
  EXPECT_TRUE(HasSubstr(clip.status().ToString(), "no_such_file.bvh"));
}

// ---------------------------------------------------------------------------------------------
// Generated hierarchies.

std::string JointChain(int depth) {
  std::string text = "HIERARCHY\nROOT J0\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n";
  for (int i = 1; i < depth; ++i) {
    text += "JOINT J" + std::to_string(i) + "\n{\n  OFFSET 0 1 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n";
  }
  text += "End Site\n{\n  OFFSET 0 1 0\n}\n";
  for (int i = 0; i < depth; ++i) text += "}\n";
  text += "MOTION\nFrames: 1\nFrame Time: 0.0333333\n";
  for (int i = 0; i < depth; ++i) text += i == 0 ? "0 0 0" : " 0 0 0";
  return text + "\n";
}

// A root with `children` leaf joints.
std::string WideHierarchy(int children) {
  std::string text =
      "HIERARCHY\nROOT Root\n{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation "
      "Yrotation\n";
  for (int i = 0; i < children; ++i) {
    text += "  JOINT Leaf" + std::to_string(i) + "\n  {\n    OFFSET " + std::to_string(i) +
            " 1 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n    End Site\n    {\n      OFFSET 0 1 0\n    }\n  }\n";
  }
  text += "}\nMOTION\nFrames: 2\nFrame Time: 0.0333333\n";
  for (int frame = 0; frame < 2; ++frame) {
    text += "1 2 3 4 5 6";
    for (int i = 0; i < children; ++i) text += " " + std::to_string(frame) + " 0 " + std::to_string(i % 90);
    text += "\n";
  }
  return text;
}

TEST(BvhReaderTest, RejectsThousandsOfJoints) {
  const std::string text = WideHierarchy(3000);
  absl::StatusOr<BvhClip> clip = ParseBvh(text, "wide.bvh");
  ASSERT_FALSE(clip.ok());
  EXPECT_EQ(clip.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_TRUE(HasSubstr(clip.status().ToString(), "wide.bvh:"));
  EXPECT_TRUE(HasSubstr(clip.status().ToString(), "more than 1024 joints"));
}

TEST(BvhReaderTest, AcceptsAThousandJoints) {
  const std::string text = WideHierarchy(1000);
  absl::StatusOr<BvhClip> clip = ParseBvh(text, "wide.bvh");
  ASSERT_TRUE(clip.ok()) << clip.status();
  EXPECT_EQ(clip->skeleton.num_joints(), 1001);
  EXPECT_EQ(clip->skeleton.num_channels(), 6 + 3 * 1000);
  EXPECT_EQ(clip->num_frames(), 2);
  EXPECT_EQ(clip->skeleton.joint(500).name, "Leaf499");
  EXPECT_EQ(clip->skeleton.joint(500).offset.x(), 499.0f);
  EXPECT_EQ(clip->channels(1, clip->skeleton.channel_start(500) + 2), 499 % 90);
}

TEST(BvhReaderTest, RejectsThousandsOfNestedJointsWithoutOverflowingTheStack) {
  absl::StatusOr<BvhClip> clip = ParseBvh(JointChain(5000), "deep.bvh");
  ASSERT_FALSE(clip.ok());
  EXPECT_EQ(clip.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_TRUE(HasSubstr(clip.status().ToString(), "deep.bvh:"));
  EXPECT_TRUE(HasSubstr(clip.status().ToString(), "nested too deeply"));
}

TEST(BvhReaderTest, AcceptsAModeratelyDeepChain) {
  absl::StatusOr<BvhClip> clip = ParseBvh(JointChain(100), "chain.bvh");
  ASSERT_TRUE(clip.ok()) << clip.status();
  EXPECT_EQ(clip->skeleton.num_joints(), 100);
  EXPECT_EQ(clip->skeleton.parent(99), 98);
  EXPECT_TRUE(clip->skeleton.joint(99).end_site.has_value());
}

// ---------------------------------------------------------------------------------------------
// Number syntax.

std::string OneJointFile(std::string_view frame_line) {
  return "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n"
         "  End Site\n  {\n    OFFSET 0 1 0\n  }\n}\nMOTION\nFrames: 1\nFrame Time: 0.0333333\n" +
         std::string(frame_line) + "\n";
}

TEST(BvhReaderTest, AcceptsCommonNumberSpellings) {
  absl::StatusOr<BvhClip> clip = ParseBvh(OneJointFile("+1.5 -.25 1e-3"), "numbers.bvh");
  ASSERT_TRUE(clip.ok()) << clip.status();
  EXPECT_EQ(clip->channels(0, 0), 1.5f);
  EXPECT_EQ(clip->channels(0, 1), -0.25f);
  EXPECT_EQ(clip->channels(0, 2), 1e-3f);
}

TEST(BvhReaderTest, RejectsOverflowingValues) {
  absl::StatusOr<BvhClip> clip = ParseBvh(OneJointFile("0 1e39 0"), "big.bvh");
  ASSERT_FALSE(clip.ok());
  EXPECT_TRUE(HasSubstr(clip.status().ToString(), "big.bvh:14: "));
  EXPECT_TRUE(HasSubstr(clip.status().ToString(), "expected a finite number, found '1e39'"));
}

// "+-1" is not a number; the reader must not read it as -1.
TEST(BvhReaderTest, RejectsDoublySignedValue) {
  absl::StatusOr<BvhClip> clip = ParseBvh(OneJointFile("0 +-1 0"), "signs.bvh");
  ASSERT_FALSE(clip.ok()) << "'+-1' was read as " << clip->channels(0, 1);
  EXPECT_TRUE(HasSubstr(clip.status().ToString(), "signs.bvh:14: "));
}

// A value too small for a float is a valid number (an exporter working in double precision);
// it should read as zero (or the nearest float) rather than fail the whole file.
TEST(BvhReaderTest, AcceptsValuesThatUnderflowToZero) {
  absl::StatusOr<BvhClip> clip = ParseBvh(OneJointFile("1e-50 -2.5e-60 1e-40"), "tiny.bvh");
  ASSERT_TRUE(clip.ok()) << clip.status();
  EXPECT_EQ(clip->channels(0, 0), 0.0f);
  EXPECT_EQ(clip->channels(0, 1), 0.0f);
  EXPECT_NEAR(clip->channels(0, 2), 0.0f, 1e-39f);
}

// ---------------------------------------------------------------------------------------------
// Valid edge cases.

// The two-joint file most edge cases are variations of: Hips (6 channels ZXY) -> Spine (3) ->
// End Site, frames "0 x 9" and "1 2 ... 9".
void ExpectBaseClip(const BvhClip& clip) {
  ASSERT_EQ(clip.skeleton.num_joints(), 2);
  EXPECT_EQ(clip.skeleton.joint(0).name, "Hips");
  EXPECT_EQ(clip.skeleton.joint(1).name, "Spine");
  EXPECT_EQ(clip.skeleton.parent(1), 0);
  // The file's root OFFSET is (0 90 0), but its channels alone put this small body on the floor:
  // read as Blender and three.js read it (root_convention.h), the OFFSET is left out.
  EXPECT_EQ(clip.root_reading, RootPositionReading::kChannelsOnly);
  EXPECT_EQ(clip.skeleton.joint(0).offset, Eigen::Vector3f(0, 0, 0));
  EXPECT_EQ(clip.skeleton.joint(1).offset, Eigen::Vector3f(0, 10, 0));
  EXPECT_FALSE(clip.skeleton.joint(0).end_site.has_value());
  ASSERT_TRUE(clip.skeleton.joint(1).end_site.has_value());
  EXPECT_EQ(*clip.skeleton.joint(1).end_site, Eigen::Vector3f(0, 20, 0));
  const std::vector<ChannelType> root_channels = {ChannelType::kXposition, ChannelType::kYposition,
                                                  ChannelType::kZposition, ChannelType::kZrotation,
                                                  ChannelType::kXrotation, ChannelType::kYrotation};
  EXPECT_EQ(clip.skeleton.joint(0).channels, root_channels);
  EXPECT_EQ(clip.skeleton.num_channels(), 9);
  EXPECT_EQ(clip.skeleton.channel_start(1), 6);
  EXPECT_NEAR(clip.frame_time, 0.0333333, 1e-7);
  ASSERT_EQ(clip.num_frames(), 2);
  for (int c = 0; c < 9; ++c) {
    EXPECT_EQ(clip.channels(0, c), 0.0f);
    EXPECT_EQ(clip.channels(1, c), static_cast<float>(c + 1));
  }
}

class BvhReaderBaseVariantTest : public ::testing::TestWithParam<const char*> {};

TEST_P(BvhReaderBaseVariantTest, ParsesLikeThePlainFile) {
  absl::StatusOr<BvhClip> clip = ReadBvhFile(ValidDir() / GetParam());
  ASSERT_TRUE(clip.ok()) << clip.status();
  ExpectBaseClip(*clip);
}

INSTANTIATE_TEST_SUITE_P(BvhValidCorpus, BvhReaderBaseVariantTest,
                         ::testing::Values("crlf.bvh.txt", "tabs.bvh.txt", "trailing_blank_lines.bvh.txt",
                                           "frame_time_leading_dot.bvh.txt", "utf8_bom.bvh.txt"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string name = info.param;
                           return name.substr(0, name.find('.'));
                         });

TEST(BvhReaderTest, CorpusFilesReallyHaveTheirQuirks) {
  EXPECT_NE(ReadText(ValidDir() / "crlf.bvh.txt").find("\r\n"), std::string::npos);
  EXPECT_NE(ReadText(ValidDir() / "tabs.bvh.txt").find("Frame Time:\t"), std::string::npos);
  EXPECT_NE(ReadText(ValidDir() / "frame_time_leading_dot.bvh.txt").find("Frame Time: .0333333"), std::string::npos);
  EXPECT_EQ(ReadText(ValidDir() / "utf8_bom.bvh.txt").rfind("\xEF\xBB\xBFHIERARCHY", 0), 0u);
  const std::string trailing = ReadText(ValidDir() / "trailing_blank_lines.bvh.txt");
  EXPECT_EQ(trailing.substr(trailing.size() - 2), "\n\n");
  EXPECT_NE(trailing.find("9\n\n"), std::string::npos);
}

TEST(BvhReaderTest, RootWithThreeRotationChannels) {
  absl::StatusOr<BvhClip> clip = ReadBvhFile(ValidDir() / "root_3_channels.bvh.txt");
  ASSERT_TRUE(clip.ok()) << clip.status();
  ASSERT_EQ(clip->skeleton.num_joints(), 2);
  EXPECT_EQ(clip->skeleton.joint(0).channels.size(), 3u);
  EXPECT_EQ(clip->skeleton.num_channels(), 6);
  ASSERT_EQ(clip->num_frames(), 3);
  EXPECT_EQ(clip->channels(1, 5), 60.0f);
  const float last[] = {-1.5f, 25.0f, 3.0f, 0.25f, 0.0f, 7.0f};
  for (int c = 0; c < 6; ++c) EXPECT_EQ(clip->channels(2, c), last[c]) << c;
}

TEST(BvhReaderTest, SixChannelsMidHierarchy) {
  absl::StatusOr<BvhClip> clip = ReadBvhFile(ValidDir() / "mid_hierarchy_6_channels.bvh.txt");
  ASSERT_TRUE(clip.ok()) << clip.status();
  ASSERT_EQ(clip->skeleton.num_joints(), 3);
  EXPECT_EQ(clip->skeleton.joint(1).channels.size(), 6u);
  EXPECT_EQ(clip->skeleton.joint(1).channels[0], ChannelType::kXposition);
  EXPECT_EQ(clip->skeleton.channel_start(1), 6);
  EXPECT_EQ(clip->skeleton.channel_start(2), 12);
  EXPECT_EQ(clip->skeleton.num_channels(), 15);
  ASSERT_EQ(clip->num_frames(), 2);
  EXPECT_EQ(clip->channels(1, 6), 0.5f);
  EXPECT_EQ(clip->channels(1, 7), 12.0f);
  EXPECT_EQ(clip->channels(1, 14), 6.0f);
}

TEST(BvhReaderTest, JointsWithoutChannelsLine) {
  absl::StatusOr<BvhClip> clip = ReadBvhFile(ValidDir() / "no_channels_line.bvh.txt");
  ASSERT_TRUE(clip.ok()) << clip.status();
  ASSERT_EQ(clip->skeleton.num_joints(), 4);
  EXPECT_EQ(clip->skeleton.joint(1).name, "Spine");
  EXPECT_TRUE(clip->skeleton.joint(1).channels.empty());
  EXPECT_EQ(clip->skeleton.joint(2).channels.size(), 3u);
  EXPECT_TRUE(clip->skeleton.joint(3).channels.empty());
  EXPECT_EQ(clip->skeleton.parent(3), 2);
  EXPECT_EQ(clip->skeleton.channel_start(2), 6);
  EXPECT_EQ(clip->skeleton.channel_start(3), 9);
  EXPECT_EQ(clip->skeleton.num_channels(), 9);
  EXPECT_EQ(clip->channels(1, 8), 9.0f);
}

TEST(BvhReaderTest, RotationOrders) {
  struct Case {
    const char* file;
    std::vector<ChannelType> rotations;
  };
  const Case cases[] = {
      {"order_xyz.bvh.txt", {ChannelType::kXrotation, ChannelType::kYrotation, ChannelType::kZrotation}},
      {"order_yxz.bvh.txt", {ChannelType::kYrotation, ChannelType::kXrotation, ChannelType::kZrotation}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    absl::StatusOr<BvhClip> clip = ReadBvhFile(ValidDir() / c.file);
    ASSERT_TRUE(clip.ok()) << clip.status();
    ASSERT_EQ(clip->skeleton.num_joints(), 2);
    const std::vector<ChannelType>& root = clip->skeleton.joint(0).channels;
    ASSERT_EQ(root.size(), 6u);
    EXPECT_EQ(std::vector<ChannelType>(root.begin() + 3, root.end()), c.rotations);
    EXPECT_EQ(clip->skeleton.joint(1).channels, c.rotations);
    ASSERT_EQ(clip->num_frames(), 3);
    EXPECT_EQ(clip->channels(1, 3), 10.0f);
    EXPECT_EQ(clip->channels(2, 8), -60.0f);
  }
}

TEST(BvhReaderTest, EveryValidCorpusFileParses) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(ValidDir())) {
    absl::StatusOr<BvhClip> clip = ReadBvhFile(entry.path());
    EXPECT_TRUE(clip.ok()) << entry.path() << ": " << clip.status();
    if (clip.ok()) {
      EXPECT_TRUE(clip->channels.allFinite()) << entry.path();
    }
    ++count;
  }
  EXPECT_GE(count, 10);
}

TEST(BvhReaderTest, HonoursLimits) {
  const std::string text = ReadText(ValidDir() / "order_xyz.bvh.txt");
  BvhReadLimits limits;
  limits.max_frames = 2;
  absl::StatusOr<BvhClip> clip = ParseBvh(text, "limits.bvh", limits);
  ASSERT_FALSE(clip.ok());
  EXPECT_TRUE(HasSubstr(clip.status().ToString(), "limits.bvh:17: frame count 3 outside 1..2"));
  limits = BvhReadLimits{};
  limits.max_frame_time = 0.02;
  clip = ParseBvh(text, "limits.bvh", limits);
  ASSERT_FALSE(clip.ok());
  EXPECT_TRUE(HasSubstr(clip.status().ToString(), "limits.bvh:18: frame time"));
}

// ---------------------------------------------------------------------------------------------
// The real data sets (skipped when ../shared/data is absent).

struct SetExpectation {
  const char* name;
  int min_joints;
  int max_joints;
  double fps;
  int min_files;
};

class BvhReaderSharedDataTest : public ::testing::TestWithParam<SetExpectation> {};

TEST_P(BvhReaderSharedDataTest, ParsesEveryFile) {
  const SetExpectation& set = GetParam();
  MOCAP_REQUIRE_SHARED_DATA(folder, set.name);
  const std::vector<std::filesystem::path> files = testing::BvhFilesIn(folder);
  EXPECT_GE(static_cast<int>(files.size()), set.min_files);
  int failures = 0;
  long long frames = 0;
  for (const std::filesystem::path& path : files) {
    absl::StatusOr<BvhClip> clip = ReadBvhFile(path);
    if (!clip.ok()) {
      ADD_FAILURE() << clip.status();
      if (++failures > 10) break;
      continue;
    }
    const int joints = clip->skeleton.num_joints();
    const bool good = joints >= set.min_joints && joints <= set.max_joints &&
                      std::abs(clip->frame_rate() - set.fps) < 0.01 && clip->num_frames() > 0 &&
                      clip->channels.allFinite();
    EXPECT_TRUE(good) << path << ": " << joints << " joints, " << clip->frame_rate() << " fps, " << clip->num_frames()
                      << " frames, finite " << clip->channels.allFinite();
    if (!good && ++failures > 10) break;
    frames += clip->num_frames();
  }
  RecordProperty("frames", static_cast<int>(frames));
}

INSTANTIATE_TEST_SUITE_P(BvhReaderSets, BvhReaderSharedDataTest,
                         ::testing::Values(SetExpectation{"bandai-namco-1", 22, 22, 30.0, 100},
                                           SetExpectation{"bandai-namco-2", 22, 22, 30.0, 2000},
                                           SetExpectation{"cmu-cc", 99, 101, 60.0, 40}),
                         [](const ::testing::TestParamInfo<SetExpectation>& info) {
                           std::string name = info.param.name;
                           for (char& ch : name) {
                             if (ch == '-') ch = '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace mocap
