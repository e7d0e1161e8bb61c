#include "motion/bvh/bvh_inspection.h"

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/support/shared_data.h"

namespace mocap {
namespace {

// Every file of the three shared sets: the landmarks the importer finds agree with the joint
// names, which the analysis never looks at.
struct ExpectedNames {
  const char* set;
  const char* pelvis;
  const char* left_wrist;
  const char* right_wrist;
  const char* left_ankle;
  const char* right_ankle;
  const char* head;
  // Where the left limbs' upper long bones start and where they bend (the right ones mirror them:
  // "_L" -> "_R" / "_L_" -> "_R_").
  const char* left_shoulder;
  const char* left_elbow;
  const char* left_hip;
  const char* left_knee;
};

// The right side's name of a left joint.
std::string RightOf(std::string name) {
  for (const char* left : {"_L_", "_L"}) {
    if (const size_t at = name.rfind(left); at != std::string::npos) {
      name[at + 1] = 'R';
      break;
    }
  }
  return name;
}

void PrintTo(const ExpectedNames& names, std::ostream* out) { *out << names.set; }

class InspectSharedDataTest : public ::testing::TestWithParam<ExpectedNames> {};

TEST_P(InspectSharedDataTest, FindsLandmarksInEveryFile) {
  const ExpectedNames& expected = GetParam();
  MOCAP_REQUIRE_SHARED_DATA(folder, expected.set);
  int checked = 0;
  for (const auto& file : testing::BvhFilesIn(folder)) {
    auto report = InspectBvhFile(file);
    ASSERT_TRUE(report.ok()) << report.status();
    const BodyLandmarks& landmarks = report->topology.landmarks;
    auto name = [&](int joint) { return report->skeleton.joint(joint).name; };
    EXPECT_EQ(name(landmarks.pelvis), expected.pelvis) << file;
    EXPECT_EQ(name(landmarks.left_wrist), expected.left_wrist) << file;
    EXPECT_EQ(name(landmarks.right_wrist), expected.right_wrist) << file;
    EXPECT_EQ(name(landmarks.left_ankle), expected.left_ankle) << file;
    EXPECT_EQ(name(landmarks.right_ankle), expected.right_ankle) << file;
    EXPECT_EQ(name(landmarks.head), expected.head) << file;
    EXPECT_EQ(name(landmarks.left_shoulder), expected.left_shoulder) << file;
    EXPECT_EQ(name(landmarks.left_elbow), expected.left_elbow) << file;
    EXPECT_EQ(name(landmarks.left_hip), expected.left_hip) << file;
    EXPECT_EQ(name(landmarks.left_knee), expected.left_knee) << file;
    EXPECT_EQ(name(landmarks.right_shoulder), RightOf(expected.left_shoulder)) << file;
    EXPECT_EQ(name(landmarks.right_elbow), RightOf(expected.left_elbow)) << file;
    EXPECT_EQ(name(landmarks.right_hip), RightOf(expected.left_hip)) << file;
    EXPECT_EQ(name(landmarks.right_knee), RightOf(expected.left_knee)) << file;
    EXPECT_EQ(AxisName(report->topology.up_axis, report->topology.up_sign), "+Y") << file;
    EXPECT_EQ(report->topology.unit, LengthUnit::kCentimetre) << file;
    EXPECT_GT(report->frames, 0) << file;
    ++checked;
  }
  EXPECT_GT(checked, 0);
}

// Every file of `other-rigs` (real captures from other exporters and labs: the CMU 31-joint rig
// with clavicles longer than the forearms, PyMO, Mixamo, mocapbank, Perfume, one-frame Xsens
// T-poses): every landmark is the joint its `landmarks.tsv` names ("A|B": either is right). The
// analysis never reads the names.
TEST(InspectOtherRigsTest, EveryFileMatchesLandmarksTsv) {
  MOCAP_REQUIRE_SHARED_DATA(folder, "other-rigs");
  std::ifstream tsv(folder / "landmarks.tsv");
  ASSERT_TRUE(tsv) << "no landmarks.tsv in " << folder;
  // file -> landmark -> the names that are right.
  std::map<std::string, std::map<std::string, std::vector<std::string>>> expected;
  std::string line;
  while (std::getline(tsv, line)) {
    std::istringstream fields(line);
    std::string file, landmark, joints;
    if (!std::getline(fields, file, '\t') || !std::getline(fields, landmark, '\t') || !std::getline(fields, joints)) {
      continue;
    }
    if (file == "file") continue;  // the header
    std::vector<std::string>& names = expected[file][landmark];
    std::istringstream alternatives(joints);
    for (std::string name; std::getline(alternatives, name, '|');) names.push_back(name);
  }
  const std::pair<const char*, int BodyLandmarks::*> kLandmarks[] = {{"pelvis", &BodyLandmarks::pelvis},
                                                                     {"head", &BodyLandmarks::head},
                                                                     {"left_shoulder", &BodyLandmarks::left_shoulder},
                                                                     {"right_shoulder", &BodyLandmarks::right_shoulder},
                                                                     {"left_elbow", &BodyLandmarks::left_elbow},
                                                                     {"right_elbow", &BodyLandmarks::right_elbow},
                                                                     {"left_wrist", &BodyLandmarks::left_wrist},
                                                                     {"right_wrist", &BodyLandmarks::right_wrist},
                                                                     {"left_hip", &BodyLandmarks::left_hip},
                                                                     {"right_hip", &BodyLandmarks::right_hip},
                                                                     {"left_knee", &BodyLandmarks::left_knee},
                                                                     {"right_knee", &BodyLandmarks::right_knee},
                                                                     {"left_ankle", &BodyLandmarks::left_ankle},
                                                                     {"right_ankle", &BodyLandmarks::right_ankle}};
  int files = 0, files_right = 0;
  for (const auto& file : testing::BvhFilesIn(folder)) {
    ++files;
    const std::string stem = file.filename().string();
    ASSERT_TRUE(expected.count(stem)) << stem << " is not in landmarks.tsv";
    auto report = InspectBvhFile(file);
    ASSERT_TRUE(report.ok()) << report.status();
    bool all_right = true;
    for (const auto& [landmark, member] : kLandmarks) {
      const int joint = report->topology.landmarks.*member;
      const std::string found = joint >= 0 ? report->skeleton.joint(joint).name : "<none>";
      const std::vector<std::string>& names = expected[stem][landmark];
      ASSERT_FALSE(names.empty()) << stem << ": landmarks.tsv has no " << landmark;
      const bool right = std::find(names.begin(), names.end(), found) != names.end();
      EXPECT_TRUE(right) << stem << ": " << landmark << " is " << found << ", expected " << names[0];
      all_right = all_right && right;
    }
    files_right += all_right ? 1 : 0;
  }
  EXPECT_EQ(files, static_cast<int>(expected.size())) << "landmarks.tsv lists files that are not there";
  EXPECT_EQ(files_right, files) << "files with every landmark right";
}

TEST(BvhInspectionTest, MissingFileIsNotFoundAndNamed) {
  auto report = InspectBvhFile("/nonexistent/walk.bvh");
  ASSERT_FALSE(report.ok());
  EXPECT_NE(report.status().message().find("walk.bvh"), std::string::npos) << report.status();
}

TEST(BvhInspectionTest, AxisNames) {
  EXPECT_EQ(AxisName(0, 1), "+X");
  EXPECT_EQ(AxisName(2, -1), "-Z");
}

INSTANTIATE_TEST_SUITE_P(
    AllSets, InspectSharedDataTest,
    ::testing::Values(ExpectedNames{"bandai-namco-1", "Hips", "Hand_L", "Hand_R", "Foot_L", "Foot_R", "Head",
                                    "UpperArm_L", "LowerArm_L", "UpperLeg_L", "LowerLeg_L"},
                      ExpectedNames{"bandai-namco-2", "Hips", "Hand_L", "Hand_R", "Foot_L", "Foot_R", "Head",
                                    "UpperArm_L", "LowerArm_L", "UpperLeg_L", "LowerLeg_L"},
                      ExpectedNames{"cmu-cc", "CC_Base_Hip", "CC_Base_L_Hand", "CC_Base_R_Hand", "CC_Base_L_Foot",
                                    "CC_Base_R_Foot", "CC_Base_Head", "CC_Base_L_Upperarm", "CC_Base_L_Forearm",
                                    "CC_Base_L_Thigh", "CC_Base_L_Calf"}),
    [](const auto& info) {
      std::string name = info.param.set;
      for (char& c : name)
        if (c == '-') c = '_';
      return name;
    });

}  // namespace
}  // namespace mocap
