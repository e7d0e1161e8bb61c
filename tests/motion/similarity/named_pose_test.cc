// A pose sent as named joint positions (NamedPosePoints) gives the points the importer's path
// gives for the same frame of a BVH clip: the landmarks' chains match the analysis' groups, and
// with bone directions the length rules find the same shoulders, elbows, hips and knees.
#include "motion/similarity/named_pose.h"

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/local_motion.h"
#include "tests/support/clip_points.h"
#include "tests/support/synthetic_clip.h"

namespace mocap {
namespace {

// Frame `frame` of `clip` as a NamedPose: every joint with its parent and world position.
NamedPose PoseOfFrame(const BvhClip& clip, int frame) {
  const GlobalPoses poses =
      ForwardKinematics(clip.skeleton, MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time));
  NamedPose pose;
  for (int j = 0; j < clip.skeleton.num_joints(); ++j) {
    const int parent = clip.skeleton.parent(j);
    pose.joints.push_back(
        {clip.skeleton.joint(j).name, parent >= 0 ? clip.skeleton.joint(parent).name : "", poses.position(frame, j)});
  }
  pose.pelvis = "Hips";
  pose.head = "Head";
  pose.left_wrist = "LeftHand";
  pose.right_wrist = "RightHand";
  pose.left_ankle = "LeftFoot";
  pose.right_ankle = "RightFoot";
  return pose;
}

class NamedPoseTest : public ::testing::TestWithParam<ChainScaling> {};

TEST_P(NamedPoseTest, GivesTheImportersPointsForTheSameFrame) {
  const BodyPointOptions options{.scaling = GetParam()};
  const BvhClip clip = testing::MakeWalkingClip({.fingers_and_toes = true});
  absl::StatusOr<ClipPoints> clip_points = testing::QueryPoints(clip, options);
  ASSERT_TRUE(clip_points.ok()) << clip_points.status();
  for (int frame : {0, 17, 42}) {
    absl::StatusOr<ClipPoints> pose_points = NamedPosePoints(PoseOfFrame(clip, frame), options);
    ASSERT_TRUE(pose_points.ok()) << pose_points.status();
    ASSERT_EQ(pose_points->points.cols(), clip_points->points.cols());
    EXPECT_LT((pose_points->points.row(0) - clip_points->points.row(frame)).cwiseAbs().maxCoeff(), 1e-4f)
        << "frame " << frame << "\n"
        << pose_points->points.row(0) << "\n"
        << clip_points->points.row(frame);
  }
}

// Forearms much longer than upper arms (40 against 28, clavicles 14): by lengths alone the
// clavicle's start looks like the shoulder (clavicle + upper arm ≈ forearm). Naming the shoulders
// and elbows gives the importer's points, which the analysis finds from the motion.
TEST(NamedPoseLimbLandmarksTest, NamedShouldersAndElbowsOverrideTheLengthRule) {
  BvhClip clip = testing::MakeWalkingClip();
  std::vector<Joint> joints = clip.skeleton.joints();
  for (const char* hand : {"LeftHand", "RightHand"}) joints[clip.skeleton.Find(hand)].offset *= 1.6f;
  clip.skeleton = Skeleton(std::move(joints));
  const BodyPointOptions options;  // bone directions
  absl::StatusOr<ClipPoints> clip_points = testing::QueryPoints(clip, options);
  ASSERT_TRUE(clip_points.ok()) << clip_points.status();
  const int frame = 20;
  NamedPose pose = PoseOfFrame(clip, frame);
  absl::StatusOr<ClipPoints> by_length = NamedPosePoints(pose, options);
  ASSERT_TRUE(by_length.ok()) << by_length.status();
  EXPECT_GT((by_length->points.row(0) - clip_points->points.row(frame)).cwiseAbs().maxCoeff(), 0.01f);

  pose.left_elbow = "LeftForeArm";
  pose.right_elbow = "RightForeArm";
  pose.left_shoulder = "LeftArm";
  pose.right_shoulder = "RightArm";
  absl::StatusOr<ClipPoints> named = NamedPosePoints(pose, options);
  ASSERT_TRUE(named.ok()) << named.status();
  EXPECT_LT((named->points.row(0) - clip_points->points.row(frame)).cwiseAbs().maxCoeff(), 1e-4f);
}

TEST(NamedPoseLimbLandmarksTest, LimbLandmarksOutsideTheirLimbAreRefusedByName) {
  const BvhClip clip = testing::MakeWalkingClip();
  const NamedPose base = PoseOfFrame(clip, 0);
  struct Case {
    std::function<void(NamedPose&)> edit;
    std::string message;
  };
  for (const Case& c : std::vector<Case>{
           {[](NamedPose& p) { p.left_elbow = "RightForeArm"; }, "'left_elbow' is not a joint inside the left_arm"},
           {[](NamedPose& p) { p.left_knee = "LeftFoot"; }, "'left_knee' is not a joint inside the left_leg"},
           {[](NamedPose& p) {
              p.left_elbow = "LeftForeArm";
              p.left_shoulder = "LeftHand";
            },
            "'left_shoulder' is not a joint of the left_arm above 'left_elbow'"},
           {[](NamedPose& p) { p.right_hip = "RightUpLeg"; }, "right_hip needs right_knee"},
           {[](NamedPose& p) { p.right_knee = "NoSuchJoint"; }, "'right_knee' names no joint"},
       }) {
    NamedPose pose = base;
    c.edit(pose);
    absl::StatusOr<ClipPoints> points = NamedPosePoints(pose, {});
    ASSERT_FALSE(points.ok()) << c.message;
    EXPECT_EQ(points.status().code(), absl::StatusCode::kInvalidArgument);
    EXPECT_NE(points.status().message().find(c.message), std::string_view::npos) << points.status();
  }
}

INSTANTIATE_TEST_SUITE_P(Scalings, NamedPoseTest,
                         ::testing::Values(ChainScaling::kBoneDirections, ChainScaling::kPerChain,
                                           ChainScaling::kBodyScale),
                         [](const auto& info) { return testing::ChainScalingTestName(info.param); });

}  // namespace
}  // namespace mocap
