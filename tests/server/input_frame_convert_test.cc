// Replies into the caller's frame (server/input_frame_convert.h) on a rig that is not the
// database's: any skeleton and frame convert field by field and stay one consistent pose.
#include "server/input_frame_convert.h"

#include <gtest/gtest.h>

#include <vector>

namespace mocap {
namespace {

Eigen::Vector3f V(const v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }
Eigen::Quaternionf Q(const v1::Quaternion& q) { return Eigen::Quaternionf(q.w(), q.x(), q.y(), q.z()); }
void Set(const Eigen::Vector3f& p, v1::Vec3* v) {
  v->set_x(p.x());
  v->set_y(p.y());
  v->set_z(p.z());
}
void Set(const Eigen::Quaternionf& q, v1::Quaternion* out) {
  out->set_w(q.w());
  out->set_x(q.x());
  out->set_y(q.y());
  out->set_z(q.z());
}

// World positions of a chain skeleton (each joint the previous one's child) and its end site.
std::vector<Eigen::Vector3f> Positions(const v1::Skeleton& skeleton, const v1::Frame& frame) {
  std::vector<Eigen::Vector3f> out = {V(frame.root_position())};
  Eigen::Quaternionf global = Q(frame.rotations(0));
  for (int j = 1; j < skeleton.joints_size(); ++j) {
    out.push_back(out.back() + global * V(skeleton.joints(j).offset()));
    global = global * Q(frame.rotations(j));
  }
  out.push_back(out.back() + global * V(skeleton.joints(skeleton.joints_size() - 1).end_site()));
  return out;
}

TEST(InputFrameConvertTest, AnyRigAndFrameConvertAsOnePose) {
  v1::Skeleton skeleton;  // five joints, 0.2–0.4 m bones, an end site: no database rig
  const Eigen::Vector3f offsets[5] = {{0, 0, 0}, {0, 0.3f, 0.05f}, {0.25f, 0, 0}, {0, -0.4f, 0.1f}, {0.2f, 0.1f, 0}};
  v1::Frame frame;
  Set({0.4f, 1.0f, -2.0f}, frame.mutable_root_position());
  for (int j = 0; j < 5; ++j) {
    v1::Joint* joint = skeleton.add_joints();
    joint->set_parent(j - 1);
    Set(offsets[j], joint->mutable_offset());
    Set(Eigen::Quaternionf(Eigen::AngleAxisf(0.3f * (j + 1), Eigen::Vector3f(1, j, 2).normalized())),
        frame.add_rotations());
  }
  Set({0, 0, 0.12f}, skeleton.mutable_joints(4)->mutable_end_site());
  Set({1, 2, 3}, frame.mutable_left_wrist());
  frame.mutable_diagnostics()->set_left_wrist_error(0.05f);
  frame.mutable_expected_error()->set_pelvis(0.04f);
  frame.mutable_expected_error()->set_right_ankle(0.12f);
  const std::vector<Eigen::Vector3f> native = Positions(skeleton, frame);

  // Unreal with its floor 30 cm below z = 0.
  const FrameTransform unreal({LengthUnit::kCentimetre, UpAxis::kPosZ, Handedness::kLeft}, -30.0);
  ToCallerFrame(unreal, &skeleton);
  ToCallerFrame(unreal, &frame);
  const std::vector<Eigen::Vector3f> caller = Positions(skeleton, frame);
  for (size_t j = 0; j < native.size(); ++j) {
    EXPECT_TRUE(unreal.PositionToNative(caller[j]).isApprox(native[j], 1e-5f)) << j;
  }
  EXPECT_TRUE(V(frame.root_position()).isApprox(Eigen::Vector3f(40, -200, 70), 1e-5f));  // (x, z, y)·100, floor at −30
  EXPECT_TRUE(V(frame.left_wrist()).isApprox(Eigen::Vector3f(100, 300, 170), 1e-5f));
  EXPECT_FLOAT_EQ(frame.diagnostics().left_wrist_error(), 5.0f);  // cm
  EXPECT_FLOAT_EQ(frame.expected_error().pelvis(), 4.0f);
  EXPECT_FLOAT_EQ(frame.expected_error().right_ankle(), 12.0f);
  EXPECT_TRUE(V(skeleton.joints(4).end_site()).isApprox(Eigen::Vector3f(0, 12, 0), 1e-5f));
}

}  // namespace
}  // namespace mocap
