// eval/html_report.cc and eval/report_player_scenes.cc: report.html from a report.json object read
// generically, and the player's clips (worst first per content type).
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "eval/html_report.h"
#include "eval/report_player_scenes.h"
#include "html_view/text_file.h"
#include "motion/bvh/bvh_reader.h"
#include "motion/bvh/bvh_writer.h"

namespace mocap::eval {
namespace {

namespace fs = std::filesystem;

constexpr const char* kTinyBvh =
    "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition "
    "Zrotation Xrotation Yrotation\n  End Site\n  {\n    OFFSET 0 10 0\n  }\n}\nMOTION\n"
    "Frames: 1\nFrame Time: 0.0333333\n0 0 0 0 0 0\n";

class HtmlReportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) / ("html_report_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "bvh" / "truth");
    fs::create_directories(dir_ / "plots");
    for (const char* name : {"walk_1.bvh", "walk_2.bvh", "walk_3.bvh", "walk_4.bvh", "run_1.bvh"}) {
      ASSERT_TRUE(html_view::WriteTextFile(dir_ / "bvh" / name, kTinyBvh).ok());
      ASSERT_TRUE(html_view::WriteTextFile(dir_ / "bvh" / "truth" / name, kTinyBvh).ok());
    }
    ASSERT_TRUE(html_view::WriteTextFile(dir_ / "plots" / "error_by_content.svg", "<svg id=\"chart\"></svg>").ok());
    auto clip = [](const char* content, double mpjpe) {
      return nlohmann::json{{"content", content}, {"mpjpe_cm", mpjpe}};
    };
    report_ = {{"database", "a <b> database"},
               {"test_clips", 5},
               {"targets", {{"mpjpe_reduction_target", 0.25}}},
               {"experiments",
                {{"full",
                  {{"group", "main"},
                   {"x", 0},
                   {"overall", {{"mpjpe_cm", 4.5}, {"a_new_metric", 7}}},
                   {"by_content", {{"walk", {{"mpjpe_cm", 4.0}}}, {"run", {{"mpjpe_cm", 6.0}}}}},
                   {"clips",
                    {{"walk_1.bvh", clip("walk", 3.0)},
                     {"walk_2.bvh", clip("walk", 9.0)},
                     {"walk_3.bvh", clip("walk", 5.0)},
                     {"walk_4.bvh", clip("walk", 1.0)},
                     {"run_1.bvh", clip("run", 6.0)},
                     {"gone.bvh", clip("run", 99.0)}}}}},
                 {"lag_5", {{"group", "lag"}, {"x", 5}, {"overall", {{"mpjpe_cm", 5.5}}}}}}}};
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  nlohmann::json report_;
};

TEST_F(HtmlReportTest, PlaysTheWorstClipsOfEachContentTypeFirst) {
  const nlohmann::json scenes = ReportPlayerScenes(report_, dir_, 3);
  ASSERT_EQ(scenes.size(), 4u);  // run_1 (gone.bvh has no files), then walk 2, 3, 1
  EXPECT_EQ(scenes[0]["label"], "run · run_1.bvh · MPJPE 6.00 cm");
  EXPECT_EQ(scenes[1]["label"], "walk · walk_2.bvh · MPJPE 9.00 cm");
  EXPECT_EQ(scenes[2]["label"], "walk · walk_3.bvh · MPJPE 5.00 cm");
  EXPECT_EQ(scenes[3]["label"], "walk · walk_1.bvh · MPJPE 3.00 cm");
  EXPECT_EQ(scenes[1]["clips"][0]["name"], "reconstruction (full method)");
  EXPECT_EQ(scenes[1]["clips"][1]["name"], "captured motion");
  EXPECT_EQ(scenes[1]["clips"][1]["bvh"], FormatBvh(ParseBvh(kTinyBvh, "tiny.bvh").value()));
}

TEST_F(HtmlReportTest, WritesTablesPlotsAndThePlayerFromAnyReport) {
  ASSERT_TRUE(WriteHtmlReport(report_, dir_).ok());
  absl::StatusOr<std::string> html = html_view::ReadTextFile(dir_ / "report.html");
  ASSERT_TRUE(html.ok());
  EXPECT_NE(html->find("a &lt;b&gt; database"), std::string::npos);
  EXPECT_NE(html->find("<th>MPJPE (cm)</th>"), std::string::npos);
  EXPECT_NE(html->find("<th>a new metric</th>"), std::string::npos);     // metrics not known in advance
  EXPECT_LT(html->find("<td>full</td>"), html->find("<td>lag_5</td>"));  // main runs first
  EXPECT_NE(html->find("MPJPE (cm) per content type"), std::string::npos);
  EXPECT_NE(html->find("<svg id=\"chart\"></svg>"), std::string::npos);
  EXPECT_NE(html->find("Position error per body part"), std::string::npos);
  EXPECT_NE(html->find("id=\"mocap-viewer-data\""), std::string::npos);
}

TEST_F(HtmlReportTest, WithoutBvhFilesThereIsNoPlayerButAWord) {
  fs::remove_all(dir_ / "bvh");
  ASSERT_TRUE(WriteHtmlReport(report_, dir_).ok());
  absl::StatusOr<std::string> html = html_view::ReadTextFile(dir_ / "report.html");
  ASSERT_TRUE(html.ok());
  EXPECT_EQ(html->find("mocap-viewer-data"), std::string::npos);
  EXPECT_NE(html->find("No clips to play"), std::string::npos);
}

}  // namespace
}  // namespace mocap::eval
