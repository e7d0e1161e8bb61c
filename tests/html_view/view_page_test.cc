// html_view: the page's data and escaping (the browser side is viewer/test/view_page_test.mjs).
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "html_view/view_clip.h"
#include "html_view/view_page.h"
#include "motion/bvh/bvh_reader.h"
#include "motion/bvh/bvh_writer.h"
#include "motion/skeleton/body_topology.h"

namespace mocap::html_view {
namespace {

// A humanoid in centimetres, Z up: pelvis, spine to head, two arms, two legs (toes forward, +Y).
constexpr const char* kZUpHumanoidCm = R"(HIERARCHY
ROOT Hips
{
  OFFSET 0 0 95
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Chest { OFFSET 0 0 30 CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT Head { OFFSET 0 0 32 CHANNELS 3 Zrotation Xrotation Yrotation End Site { OFFSET 0 0 16 } }
    JOINT LeftArm { OFFSET 18 0 20 CHANNELS 3 Zrotation Xrotation Yrotation
      JOINT LeftForeArm { OFFSET 28 0 0 CHANNELS 3 Zrotation Xrotation Yrotation
        JOINT LeftHand { OFFSET 25 0 0 CHANNELS 3 Zrotation Xrotation Yrotation End Site { OFFSET 8 0 0 } } } }
    JOINT RightArm { OFFSET -18 0 20 CHANNELS 3 Zrotation Xrotation Yrotation
      JOINT RightForeArm { OFFSET -28 0 0 CHANNELS 3 Zrotation Xrotation Yrotation
        JOINT RightHand { OFFSET -25 0 0 CHANNELS 3 Zrotation Xrotation Yrotation End Site { OFFSET -8 0 0 } } } } }
  JOINT LeftUpLeg { OFFSET 9 0 -3 CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT LeftLeg { OFFSET 0 0 -44 CHANNELS 3 Zrotation Xrotation Yrotation
      JOINT LeftFoot { OFFSET 0 0 -42 CHANNELS 3 Zrotation Xrotation Yrotation
        JOINT LeftToe { OFFSET 0 13 -6 CHANNELS 3 Zrotation Xrotation Yrotation End Site { OFFSET 0 5 0 } } } } }
  JOINT RightUpLeg { OFFSET -9 0 -3 CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT RightLeg { OFFSET 0 0 -44 CHANNELS 3 Zrotation Xrotation Yrotation
      JOINT RightFoot { OFFSET 0 0 -42 CHANNELS 3 Zrotation Xrotation Yrotation
        JOINT RightToe { OFFSET 0 13 -6 CHANNELS 3 Zrotation Xrotation Yrotation End Site { OFFSET 0 5 0 } } } } }
}
MOTION
Frames: 2
Frame Time: 0.0333333
)";

// Two frames of the rest pose (6 root channels + 16 joints × 3).
std::string ZUpHumanoidCm() {
  std::string text = kZUpHumanoidCm;
  for (int frame = 0; frame < 2; ++frame) {
    for (int value = 0; value < 54; ++value) text += value ? " 0" : "0";
    text += "\n";
  }
  return text;
}

TEST(ClipJsonTest, GivesTheUnitUpAxisAndLandmarksFromTheBodyAnalysis) {
  const std::string text = ZUpHumanoidCm();
  const nlohmann::json clip = ClipJson("walk.bvh", text);
  ASSERT_FALSE(clip.contains("error")) << clip["error"];
  EXPECT_EQ(clip["name"], "walk.bvh");
  // The page gets the clip as the product writes files: what this reader read, in a form on which
  // three.js's BVHLoader agrees (root_convention.h).
  EXPECT_EQ(clip["bvh"], FormatBvh(ParseBvh(text, "walk.bvh").value()));
  EXPECT_DOUBLE_EQ(clip["metresPerUnit"].get<double>(), 0.01);
  EXPECT_EQ(clip["pelvis"], "Hips");
  EXPECT_EQ(clip["head"], "Head");
  ASSERT_EQ(clip["landmarks"].size(), static_cast<size_t>(kNumBodyLandmarks));
  EXPECT_EQ(clip["landmarks"][0], "Hips");
  EXPECT_EQ(clip["note"], "2 frames at 30 fps");
  // toYUp [x, y, z, w] turns +Z (the file's up) to +Y.
  const auto q = clip["toYUp"];
  const double x = q[0], y = q[1], z = q[2], w = q[3];
  const double up_y = 2 * (y * z - w * x);  // the Y component of the rotated +Z (rotation matrix R[1][2])
  EXPECT_NEAR(up_y, 1.0, 1e-5);
}

TEST(ClipJsonTest, AMalformedFileCarriesTheReadersMessage) {
  const nlohmann::json clip = ClipJson("broken.bvh", "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 zero 0\n");
  EXPECT_EQ(ClipError(clip).rfind("broken.bvh:4:", 0), 0u) << clip;
  EXPECT_FALSE(clip.contains("metresPerUnit"));
}

TEST(ReconstructionTracesTest, WristsAndAnklesPerFrameWithMissingPointsHeld) {
  const nlohmann::json reconstruction = nlohmann::json::parse(R"({"frames": [
      {"left_wrist": {"x": 0.1, "y": 1.0, "z": 0.123456}, "right_wrist": {"x": -0.1, "y": 1.0, "z": 0},
       "left_ankle": {"x": 0.1, "y": 0.08, "z": 0}, "right_ankle": {"x": -0.1, "y": 0.08, "z": 0}},
      {"left_wrist": {"x": 0.2, "y": 1.1, "z": 0}, "right_wrist": {"x": -0.2, "y": 1.1, "z": 0},
       "right_ankle": {"x": -0.1, "y": 0.09, "z": 0.2}}]})");
  absl::StatusOr<nlohmann::json> traces = ReconstructionTraces(reconstruction);
  ASSERT_TRUE(traces.ok()) << traces.status();
  ASSERT_EQ(traces->size(), 4u);
  EXPECT_EQ((*traces)[0]["label"], "left wrist (input)");
  EXPECT_EQ((*traces)[0]["kind"], "wrist");
  EXPECT_EQ((*traces)[0]["points"], nlohmann::json({0.1, 1.0, 0.1235, 0.2, 1.1, 0.0}));
  EXPECT_EQ((*traces)[2]["label"], "left ankle (estimated)");
  EXPECT_EQ((*traces)[2]["points"], nlohmann::json({0.1, 0.08, 0.0, 0.1, 0.08, 0.0}));  // held
  EXPECT_FALSE(ReconstructionTraces(nlohmann::json::object()).ok());
  EXPECT_FALSE(ReconstructionTraces(nlohmann::json::parse(R"({"frames": [{"left_wrist": {"x": "a"}}]})")).ok());
}

TEST(ReconstructionConfidenceTest, FourteenErrorsPerFrameWithMissingOnesZero) {
  const nlohmann::json reconstruction = nlohmann::json::parse(R"({"frames": [
      {"expected_error": {"pelvis": 0.05, "head": 0.06, "left_wrist": 0.012345, "right_ankle": 0.2}},
      {}]})");
  absl::StatusOr<nlohmann::json> errors = ReconstructionConfidence(reconstruction);
  ASSERT_TRUE(errors.ok()) << errors.status();
  ASSERT_EQ(errors->size(), 28u);
  EXPECT_EQ((*errors)[0], 0.05);
  EXPECT_EQ((*errors)[1], 0.06);
  EXPECT_EQ((*errors)[6], 0.0123);  // left wrist, rounded to 0.1 mm
  EXPECT_EQ((*errors)[7], 0.0);     // left out: zero
  EXPECT_EQ((*errors)[13], 0.2);
  EXPECT_EQ((*errors)[14], 0.0);  // a frame without them
  EXPECT_EQ(ReconstructionConfidence(nlohmann::json::parse(R"({"frames": [{}]})")).status().code(),
            absl::StatusCode::kNotFound);
  EXPECT_FALSE(ReconstructionConfidence(nlohmann::json::object()).ok());
}

// The BVH beside the JSON plays on the input's clock, a dropout too long to bridge filled
// (client/cli/reconstruction_timeline.h); the JSON has only the frames made. Placed by their times
// at the session's rate, the traces go straight across the gap and its frames show no halo, so
// every point is drawn at the BVH frame it belongs to.
TEST(ReconstructionTracesTest, FramesArePlacedOnTheBvhsClockAcrossAFilledDropout) {
  const nlohmann::json reconstruction = nlohmann::json::parse(R"({"started": {"frame_rate": 10}, "frames": [
      {"left_wrist": {"x": 0.0, "y": 1, "z": 0}, "expected_error": {"pelvis": 0.01}},
      {"time": 0.1, "left_wrist": {"x": 0.1, "y": 1, "z": 0}, "expected_error": {"pelvis": 0.02}},
      {"time": 0.5, "segment": 1, "left_wrist": {"x": 0.5, "y": 1, "z": 0}, "expected_error": {"pelvis": 0.03}},
      {"time": 0.6, "segment": 1, "left_wrist": {"x": 0.6, "y": 1, "z": 0}, "expected_error": {"pelvis": 0.04}}]})");
  absl::StatusOr<nlohmann::json> traces = ReconstructionTraces(reconstruction);
  ASSERT_TRUE(traces.ok()) << traces.status();
  ASSERT_EQ(traces->size(), 1u);
  const nlohmann::json& points = (*traces)[0]["points"];
  ASSERT_EQ(points.size(), 7u * 3u);  // frames 0 and 1, three filled, 5 and 6
  for (int f = 0; f < 7; ++f) EXPECT_NEAR(points[3 * f].get<double>(), 0.1 * f, 1e-9) << "frame " << f;
  absl::StatusOr<nlohmann::json> errors = ReconstructionConfidence(reconstruction);
  ASSERT_TRUE(errors.ok()) << errors.status();
  ASSERT_EQ(errors->size(), 7u * kNumBodyLandmarks);
  const std::vector<double> pelvis = {0.01, 0.02, 0.0, 0.0, 0.0, 0.03, 0.04};
  for (int f = 0; f < 7; ++f) EXPECT_EQ((*errors)[f * kNumBodyLandmarks].get<double>(), pelvis[f]) << "frame " << f;
  // Times closer than a frame and a half, and a gap over ten minutes (left unfilled), keep one
  // point per frame.
  const nlohmann::json unfilled = nlohmann::json::parse(R"({"started": {"frame_rate": 10}, "frames": [
      {"left_wrist": {"x": 0, "y": 1, "z": 0}}, {"time": 0.14, "left_wrist": {"x": 0, "y": 1, "z": 0}},
      {"time": 900, "left_wrist": {"x": 0, "y": 1, "z": 0}}]})");
  traces = ReconstructionTraces(unfilled);
  ASSERT_TRUE(traces.ok()) << traces.status();
  EXPECT_EQ((*traces)[0]["points"].size(), 9u);
}

TEST(PageHtmlTest, DataAndTitleCannotEndTheirElements) {
  Page page;
  page.title = "<script>alert(1)</script>";
  page.data = {{"scenes", {{{"clips", {{{"name", "</script><script>alert(2)</script>"}, {"bvh", "<!-- & -->"}}}}}}}};
  const std::string html = PageHtml(page);
  EXPECT_EQ(html.find("<script>alert"), std::string::npos);
  EXPECT_EQ(html.find("<!-- &"), std::string::npos);
  EXPECT_NE(html.find("&lt;script&gt;alert(1)&lt;/script&gt;"), std::string::npos);
  EXPECT_NE(html.find("\\u003c/script\\u003e\\u003cscript\\u003ealert(2)"), std::string::npos);
  // Exactly the data element and the viewer's script (whose own text holds no "</script").
  size_t closes = 0;
  for (size_t at = html.find("</script"); at != std::string::npos; at = html.find("</script", at + 1)) ++closes;
  EXPECT_EQ(closes, 2u);
}

TEST(PageHtmlTest, InvalidUtf8IsReplacedNotFatal) {
  EXPECT_NE(ScriptSafeJson(nlohmann::json("bad \xff byte")).find("bad"), std::string::npos);
}

TEST(PageHtmlTest, WithoutDataThePageHasNoPlayer) {
  Page page;
  page.title = "report";
  page.html_before = "<h1>report</h1>";
  const std::string html = PageHtml(page);
  EXPECT_EQ(html.find("id=\"mocap-viewer"), std::string::npos);
  EXPECT_NE(html.find("<h1>report</h1>"), std::string::npos);
}

}  // namespace
}  // namespace mocap::html_view
