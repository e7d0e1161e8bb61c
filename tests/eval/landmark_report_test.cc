#include "eval/landmark_report.h"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

namespace mocap::eval {
namespace {

LandmarkExperimentResult DeviceRun(const std::string& method, const std::string& device, float error_m) {
  LandmarkExperimentResult r;
  r.experiment.name = method + "@" + device;
  r.experiment.group = "device";
  r.experiment.device.name = device;
  if (method == "nearest_neighbour") r.experiment.options.method = ReconstructionMethod::kNearestNeighbour;
  LandmarkMetrics m;
  m.frames = 10;
  m.clips = 1;
  m.landmark_error_m = 10 * error_m;
  r.overall = m;
  r.by_source["cmu-cc"] = m;
  r.by_content["cmu-cc/walk"] = m;
  return r;
}

std::string ReadAll(const std::filesystem::path& file) {
  std::ifstream in(file);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// `mocap-eval --runs full@tracker_90hz nearest_neighbour@tracker_90hz` asks for device runs only:
// the report is written with their table and their confidence, not refused for want of a run on
// the lab's input.
TEST(LandmarkReportTest, DeviceRunsAloneAreReported) {
  const std::filesystem::path out = std::filesystem::path(::testing::TempDir()) / "landmark_report_test_devices_only";
  std::filesystem::remove_all(out);
  std::filesystem::create_directories(out);
  const std::vector<LandmarkExperimentResult> results = {DeviceRun("full", "tracker_90hz", 0.12f),
                                                         DeviceRun("nearest_neighbour", "tracker_90hz", 0.16f)};
  const nlohmann::json context = {{"database", "bandai-namco-2"}, {"test_set", "cmu-cc"}, {"noise_cm", 0.5}};
  absl::StatusOr<std::string> summary = WriteLandmarkReport(out, context, {}, results);
  ASSERT_TRUE(summary.ok()) << summary.status();
  EXPECT_NE(summary->find("| tracker_90hz | cmu-cc | 12.00 | 16.00 | 0.75 |"), std::string::npos) << *summary;
  const std::string md = ReadAll(out / "landmarks.md");
  EXPECT_NE(md.find("No run on the lab's input"), std::string::npos);
  EXPECT_NE(md.find("tracker_90hz"), std::string::npos);
  // Every run's plausibility, the nearest neighbour's too, in a table of its own.
  const size_t plausibility = md.find("## Plausibility per run");
  ASSERT_NE(plausibility, std::string::npos) << md;
  EXPECT_NE(md.find("| nearest_neighbour@tracker_90hz | 1 |", plausibility), std::string::npos) << md;
  // The full method's confidence on the device is reported without the plain full run beside it.
  EXPECT_NE(summary->find("Confidence on device-like input"), std::string::npos) << *summary;
  EXPECT_NE(summary->find("| full@tracker_90hz |"), std::string::npos) << *summary;
  EXPECT_EQ(summary->find("| nearest_neighbour@tracker_90hz |"), std::string::npos) << *summary;
  EXPECT_TRUE(std::filesystem::exists(out / "landmarks.json"));
  EXPECT_FALSE(WriteLandmarkReport(out, context, {}, {}).ok());  // nothing run: nothing to report
}

}  // namespace
}  // namespace mocap::eval
