#include "motion/preprocess/clip_labels.h"

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "tests/support/shared_data.h"

namespace mocap {
namespace {

struct LabelCase {
  std::string file_name;
  ClipLabels expected;
};

void PrintTo(const LabelCase& c, std::ostream* os) { *os << c.file_name; }

class ClipLabelsParseTest : public ::testing::TestWithParam<LabelCase> {};

TEST_P(ClipLabelsParseTest, ParsesKnownPatternsAndFallsBackToTheStem) {
  const LabelCase& c = GetParam();
  EXPECT_EQ(ParseClipLabels(c.file_name), c.expected) << c.file_name;
}

INSTANTIATE_TEST_SUITE_P(
    Table, ClipLabelsParseTest,
    ::testing::Values(
        // Bandai-Namco sets.
        LabelCase{"dataset-2_walk-turn-left_normal_001.bvh",
                  {{"set", "dataset-2"}, {"content", "walk-turn-left"}, {"style", "normal"}, {"take", "001"}}},
        LabelCase{"dataset-1_bow_active_003.bvh",
                  {{"set", "dataset-1"}, {"content", "bow"}, {"style", "active"}, {"take", "003"}}},
        LabelCase{"/home/someone/data/bandai-namco-2/dataset-2_raise-up-both-hands_youthful_012.bvh",
                  {{"set", "dataset-2"}, {"content", "raise-up-both-hands"}, {"style", "youthful"}, {"take", "012"}}},
        LabelCase{"relative/folder/dataset-1_dance-short_masculinity_001.bvh",
                  {{"set", "dataset-1"}, {"content", "dance-short"}, {"style", "masculinity"}, {"take", "001"}}},
        LabelCase{"dataset-2_run_elderly_010",  // no extension
                  {{"set", "dataset-2"}, {"content", "run"}, {"style", "elderly"}, {"take", "010"}}},
        // CMU.
        LabelCase{"001_08.bvh", {{"subject", "001"}, {"trial", "08"}}},
        LabelCase{"../shared/cmu-cc/002_01.bvh", {{"subject", "002"}, {"trial", "01"}}},
        LabelCase{"7_12.bvh", {{"subject", "7"}, {"trial", "12"}}},
        LabelCase{"001_08.BVH", {{"subject", "001"}, {"trial", "08"}}},
        // Free-form names: the stem, folders and extension dropped.
        LabelCase{"my_walk.bvh", {{"name", "my_walk"}}}, LabelCase{"captures/2024/Take 7.bvh", {{"name", "Take 7"}}},
        LabelCase{"walk", {{"name", "walk"}}}, LabelCase{"001_08_extra.bvh", {{"name", "001_08_extra"}}},
        LabelCase{"dataset-2_walk.bvh", {{"name", "dataset-2_walk"}}},
        LabelCase{"dataset-2_walk_normal_take1.bvh", {{"name", "dataset-2_walk_normal_take1"}}},
        LabelCase{"a_b_c_001.bvh", {{"name", "a_b_c_001"}}},
        LabelCase{"dataset-x_walk_normal_001.bvh", {{"name", "dataset-x_walk_normal_001"}}}));

// bandai-namco-1 has a hyphenated style ("not-confident"; 11 files such as
// dataset-1_walk_not-confident_001.bvh), the same way contents are hyphenated.
TEST(ClipLabelsTest, HyphenatedBandaiStyleIsAStyle) {
  const ClipLabels labels = ParseClipLabels("dataset-1_walk_not-confident_001.bvh");
  EXPECT_EQ(LabelValue(labels, "set"), "dataset-1");
  EXPECT_EQ(LabelValue(labels, "content"), "walk");
  EXPECT_EQ(LabelValue(labels, "style"), "not-confident");
  EXPECT_EQ(LabelValue(labels, "take"), "001");
}

TEST(ClipLabelsTest, LabelValueFindsKeysAndIsEmptyOtherwise) {
  const ClipLabels labels = ParseClipLabels("dataset-2_wave-left_feminine_004.bvh");
  EXPECT_EQ(LabelValue(labels, "content"), "wave-left");
  EXPECT_EQ(LabelValue(labels, "take"), "004");
  EXPECT_EQ(LabelValue(labels, "subject"), "");
  EXPECT_EQ(LabelValue({}, "name"), "");
}

TEST(ClipLabelsTest, TrialKeyStripsLeadingZeros) {
  EXPECT_EQ(TrialKey(ParseClipLabels("001_08.bvh")), "1_8");
  EXPECT_EQ(TrialKey(ParseClipLabels("folder/005_20.bvh")), "5_20");
  EXPECT_EQ(TrialKey(ParseClipLabels("10_1.bvh")), "10_1");
  EXPECT_EQ(TrialKey(ParseClipLabels("000_00.bvh")), "0_0");
  EXPECT_EQ(TrialKey(ParseClipLabels("dataset-2_walk_normal_001.bvh")), "");
  EXPECT_EQ(TrialKey(ParseClipLabels("my_walk.bvh")), "");
  EXPECT_EQ(TrialKey({{"subject", "3"}}), "");
}

class ClipLabelsCsvTest : public ::testing::Test {
 protected:
  std::filesystem::path Write(const std::string& name, const std::string& bytes) {
    const std::filesystem::path path = std::filesystem::path(::testing::TempDir()) / name;
    std::ofstream out(path, std::ios::binary);
    out << bytes;
    written_.push_back(path);
    return path;
  }
  void TearDown() override {
    for (const auto& path : written_) std::filesystem::remove(path);
  }

 private:
  std::vector<std::filesystem::path> written_;
};

TEST_F(ClipLabelsCsvTest, ReadsQuotedFieldsCrlfAndLeadingZeros) {
  const std::filesystem::path path = Write("clip_labels_test_descriptions.csv",
                                           "\"Subject\",\"Trial #\",\"Motion Description\",\"framerate\"\r\n"
                                           "1,1,\"playground - forward jumps, turn around\",120\r\n"
                                           "\"02\",\"01\",\"walk\",120\r\n"
                                           "5,010,\"say \"\"hi\"\", then wave\",120\r\n"
                                           "\r\n"
                                           "7,3,plain words\r\n"
                                           "8,2\r\n"                // too short: skipped
                                           ",4,\"no subject\"\r\n"  // no subject: skipped
                                           "9,5,\"last line, no newline\"");
  const std::map<std::string, std::string> table = ReadTrialDescriptions(path);
  const std::map<std::string, std::string> expected = {
      {"1_1", "playground - forward jumps, turn around"},
      {"2_1", "walk"},
      {"5_10", "say \"hi\", then wave"},
      {"7_3", "plain words"},
      {"9_5", "last line, no newline"},
  };
  EXPECT_EQ(table, expected);
  // The keys match the file names of the set, whatever their zero padding.
  EXPECT_EQ(table.at(TrialKey(ParseClipLabels("002_01.bvh"))), "walk");
  EXPECT_EQ(table.at(TrialKey(ParseClipLabels("2_1.bvh"))), "walk");
  EXPECT_EQ(table.at(TrialKey(ParseClipLabels("005_10.bvh"))), "say \"hi\", then wave");
}

TEST_F(ClipLabelsCsvTest, HeaderOnlyOrMissingFileGivesEmptyMap) {
  EXPECT_TRUE(ReadTrialDescriptions(Write("clip_labels_test_header.csv", "\"Subject\",\"Trial #\"\n")).empty());
  EXPECT_TRUE(ReadTrialDescriptions(Write("clip_labels_test_empty.csv", "")).empty());
  EXPECT_TRUE(ReadTrialDescriptions(std::filesystem::path(::testing::TempDir()) / "no_such_file_12345.csv").empty());
}

TEST(ClipLabelsSharedDataTest, EveryCmuClipHasADescription) {
  MOCAP_REQUIRE_SHARED_DATA(folder, "cmu-cc");
  const std::map<std::string, std::string> table = ReadTrialDescriptions(folder / "cmu-descriptions.csv");
  ASSERT_GT(table.size(), 1000u);
  EXPECT_EQ(table.at("2_1"), "walk");
  EXPECT_EQ(table.at("1_1"), "playground - forward jumps, turn around");
  const std::vector<std::filesystem::path> files = testing::BvhFilesIn(folder);
  ASSERT_FALSE(files.empty());
  for (const auto& file : files) {
    const std::string key = TrialKey(ParseClipLabels(file.string()));
    ASSERT_FALSE(key.empty()) << file;
    EXPECT_TRUE(table.count(key)) << file << " -> " << key;
  }
}

}  // namespace
}  // namespace mocap
