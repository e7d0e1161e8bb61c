// The BVH `mocap reconstruct -o OUT` writes (issue #23 item 3), read back with the product's
// reader: every joint where the frames put it (1 mm), the root never below the floor and still
// (or on the floor under the body), the pelvis carrying the motion, also when the rig gives the
// pelvis no position channels of its own. The CLI's sources are built into the `mocap`
// executable only, so the two writers are compiled into this test.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "client/cli/reconstruction_bvh.cc"  // NOLINT(build/include): ReconstructionBvh
#include "client/cli/target_rig_file.cc"     // NOLINT(build/include): RetargetedBvhText
#include "motion/bvh/bvh_reader.h"
#include "motion/bvh/bvh_writer.h"
#include "motion/core/units.h"
#include "motion/retarget/retarget_rig.h"
#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/local_motion.h"
#include "tests/support/synthetic_clip.h"

namespace mocap {
namespace {

Eigen::Vector3f ToEigen(const v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }

void SetVec3(const Eigen::Vector3f& p, v1::Vec3* out) {
  out->set_x(p.x());
  out->set_y(p.y());
  out->set_z(p.z());
}

void SetQuaternion(const Eigen::Quaternionf& q, v1::Quaternion* out) {
  out->set_w(q.w());
  out->set_x(q.x());
  out->set_y(q.y());
  out->set_z(q.z());
}

v1::Joint* AddJoint(v1::Skeleton* skeleton, const std::string& name, int parent, const Eigen::Vector3f& offset) {
  v1::Joint* joint = skeleton->add_joints();
  joint->set_name(name);
  joint->set_parent(parent);
  SetVec3(offset, joint->mutable_offset());
  return joint;
}

// World positions of every joint of `frame` on `skeleton` (skeleton order): what the frames say.
std::vector<Eigen::Vector3f> FramePositions(const v1::Skeleton& skeleton, const v1::Frame& frame) {
  const int joints = skeleton.joints_size();
  std::vector<Eigen::Vector3f> positions(joints);
  std::vector<Eigen::Quaternionf> rotations(joints);
  for (int j = 0; j < joints; ++j) {
    const v1::Quaternion& q = frame.rotations(j);
    const Eigen::Quaternionf local = Eigen::Quaternionf(q.w(), q.x(), q.y(), q.z()).normalized();
    const int parent = skeleton.joints(j).parent();
    if (parent < 0) {
      positions[j] = ToEigen(frame.root_position());
      rotations[j] = local;
    } else {
      positions[j] = positions[parent] + rotations[parent] * ToEigen(skeleton.joints(j).offset());
      rotations[j] = (rotations[parent] * local).normalized();
    }
  }
  return positions;
}

int PositionChannelCount(const Joint& joint) {
  int count = 0;
  for (ChannelType c : joint.channels) count += IsRotation(c) ? 0 : 1;
  return count;
}

// (b) and (c) of the target, on world positions in metres, Y up, floor at y = 0: the root
// never below the floor, and either still (within 1 mm of where it starts) or on the floor within
// half a leg length of the pelvis, in every frame.
void ExpectRootOnTheFloorStillOrUnderTheBody(const std::vector<Eigen::Vector3f>& root,
                                             const std::vector<Eigen::Vector3f>& pelvis, float leg_length) {
  ASSERT_EQ(root.size(), pelvis.size());
  ASSERT_FALSE(root.empty());
  bool still = true;
  for (const Eigen::Vector3f& r : root) still = still && (r - root.front()).norm() < 1e-3f;
  for (size_t f = 0; f < root.size(); ++f) {
    EXPECT_GE(root[f].y(), -1e-4f) << "root below the floor at frame " << f << ": " << root[f].transpose();
    if (still) continue;
    const Eigen::Vector2f apart(root[f].x() - pelvis[f].x(), root[f].z() - pelvis[f].z());
    EXPECT_LT(apart.norm(), 0.5f * leg_length) << "root neither still nor under the pelvis at frame " << f;
    EXPECT_LT(root[f].y(), 0.01f) << "root neither still nor on the floor at frame " << f;
  }
}

// A database rig whose pelvis sits under an extra root (Bandai's joint_Root, an RL_BoneRoot), its
// OFFSET where the database's first clip started (0 0.93 4.5 m), with the frames placing the root
// through it as the service does: 4.4 m from the pelvis and 0.7 m under the floor. The file must
// keep the root still on the floor with the pelvis carrying the motion; the session's skeleton
// gives the pelvis no position channels (only the root gets them from the proto).
TEST(ReconstructionBvhTest, AnExtraRootStaysStillOnTheFloorAndEveryJointIsWhereTheFramesPutIt) {
  v1::SessionStarted started;
  started.set_frame_rate(30.0);
  v1::Skeleton* skeleton = started.mutable_skeleton();
  const Eigen::Vector3f hips_offset(0.0f, 0.93f, 4.5f);
  AddJoint(skeleton, "Root", -1, Eigen::Vector3f::Zero());
  AddJoint(skeleton, "Hips", 0, hips_offset);
  AddJoint(skeleton, "Spine", 1, {0.0f, 0.25f, 0.0f});
  SetVec3({0.0f, 0.2f, 0.0f}, AddJoint(skeleton, "Head", 2, {0.0f, 0.45f, 0.0f})->mutable_end_site());
  AddJoint(skeleton, "LeftUpLeg", 1, {0.1f, -0.05f, 0.0f});
  AddJoint(skeleton, "LeftLeg", 4, {0.0f, -0.42f, 0.0f});
  SetVec3({0.0f, -0.05f, 0.12f}, AddJoint(skeleton, "LeftFoot", 5, {0.0f, -0.42f, 0.0f})->mutable_end_site());
  AddJoint(skeleton, "RightUpLeg", 1, {-0.1f, -0.05f, 0.0f});
  AddJoint(skeleton, "RightLeg", 7, {0.0f, -0.42f, 0.0f});
  SetVec3({0.0f, -0.05f, 0.12f}, AddJoint(skeleton, "RightFoot", 8, {0.0f, -0.42f, 0.0f})->mutable_end_site());
  skeleton->mutable_landmarks()->set_pelvis(1);
  const int joints = skeleton->joints_size();
  const float leg_length = 0.84f;  // hip joint to ankle

  // A walk: the pelvis travels and bobs about 0.9 m up, the body turns and leans; the root's
  // rotation follows the pelvis' (the chain above the pelvis at rest, as the body model keeps it).
  std::vector<v1::Frame> frames;
  using Eigen::AngleAxisf;
  using Eigen::Vector3f;
  for (int f = 0; f < 24; ++f) {
    const float s = std::sin(0.4f * static_cast<float>(f));
    const Vector3f pelvis(0.2f + 0.04f * f, 0.9f + 0.02f * std::sin(0.6f * f), -0.3f + 0.01f * f);
    const Eigen::Quaternionf root_rotation(AngleAxisf(0.05f * f, Vector3f::UnitY()) *
                                           AngleAxisf(-0.15f, Vector3f::UnitX()));
    std::vector<Eigen::Quaternionf> local(joints, Eigen::Quaternionf::Identity());
    local[0] = root_rotation;
    local[1] = Eigen::Quaternionf(AngleAxisf(0.1f * std::sin(0.5f * f), Vector3f::UnitZ()));
    local[2] = Eigen::Quaternionf(AngleAxisf(0.05f * s, Vector3f::UnitX()));
    local[4] = Eigen::Quaternionf(AngleAxisf(0.4f * s, Vector3f::UnitX()));
    local[5] = Eigen::Quaternionf(AngleAxisf(0.3f + 0.2f * s, Vector3f::UnitX()));
    local[7] = Eigen::Quaternionf(AngleAxisf(-0.4f * s, Vector3f::UnitX()));
    local[8] = Eigen::Quaternionf(AngleAxisf(0.3f - 0.2f * s, Vector3f::UnitX()));
    v1::Frame frame;
    frame.set_index(f);
    SetVec3(pelvis - root_rotation * hips_offset, frame.mutable_root_position());
    for (const Eigen::Quaternionf& q : local) SetQuaternion(q, frame.add_rotations());
    frames.push_back(std::move(frame));
  }
  // The frames as written before: the root far from the body and under the floor.
  EXPECT_LT(FramePositions(*skeleton, frames[0])[0].y(), -0.5f);
  EXPECT_GT((FramePositions(*skeleton, frames[0])[0] - FramePositions(*skeleton, frames[0])[1]).norm(), 3.0f);

  const absl::StatusOr<std::string> text = cli::ReconstructionBvh(started, frames);
  ASSERT_TRUE(text.ok()) << text.status();
  const absl::StatusOr<BvhClip> parsed = ParseBvh(*text, "reconstruction.bvh");
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  ASSERT_EQ(parsed->num_frames(), static_cast<int>(frames.size()));
  ASSERT_EQ(parsed->skeleton.num_joints(), joints);
  const int hips = parsed->skeleton.Find("Hips"), root = parsed->skeleton.Find("Root");
  ASSERT_EQ(root, 0);
  ASSERT_GT(hips, 0);
  EXPECT_EQ(PositionChannelCount(parsed->skeleton.joint(hips)), 3) << "the pelvis carries the motion";
  const GlobalPoses read =
      ForwardKinematics(parsed->skeleton, MotionFromChannels(parsed->skeleton, parsed->channels, parsed->frame_time));

  std::vector<Eigen::Vector3f> root_track, pelvis_track;
  for (int f = 0; f < read.num_frames(); ++f) {
    const std::vector<Eigen::Vector3f> expected = FramePositions(*skeleton, frames[f]);
    for (int j = 1; j < joints; ++j) {  // every joint below the root, where the frames put it
      const int at = parsed->skeleton.Find(skeleton->joints(j).name());
      ASSERT_GE(at, 0) << skeleton->joints(j).name();
      EXPECT_LT((read.position(f, at) - expected[j]).norm(), 1e-3f)
          << skeleton->joints(j).name() << " at frame " << f << ": " << read.position(f, at).transpose()
          << " where the frame says " << expected[j].transpose();
    }
    root_track.push_back(read.position(f, root));
    pelvis_track.push_back(read.position(f, hips));
  }
  ExpectRootOnTheFloorStillOrUnderTheBody(root_track, pelvis_track, leg_length);
  // Still, at the origin.
  for (size_t f = 0; f < root_track.size(); ++f) EXPECT_LT(root_track[f].norm(), 1e-3f) << "frame " << f;
}

// A stream that learned the performer's size (Frame.body_scale 1 → 1.2 over its frames): a BVH
// has one skeleton, the size reached; the earlier frames keep their pelvis over the same ground
// point at its height in that body's proportion, so a standing body's feet stay on the floor.
TEST(ReconstructionBvhTest, ABodyThatGrewIsWrittenAtTheSizeItReachedWithItsFeetOnTheFloor) {
  v1::SessionStarted started;
  started.set_frame_rate(30.0);
  v1::Skeleton* skeleton = started.mutable_skeleton();
  AddJoint(skeleton, "Hips", -1, Eigen::Vector3f::Zero());
  for (const float side : {1.0f, -1.0f}) {
    const int hip = skeleton->joints_size();
    AddJoint(skeleton, side > 0 ? "LeftUpLeg" : "RightUpLeg", 0, {0.1f * side, -0.05f, 0.0f});
    AddJoint(skeleton, side > 0 ? "LeftLeg" : "RightLeg", hip, {0.0f, -0.42f, 0.0f});
    SetVec3({0.0f, 0.0f, 0.12f},
            AddJoint(skeleton, side > 0 ? "LeftFoot" : "RightFoot", hip + 1, {0.0f, -0.42f, 0.0f})->mutable_end_site());
  }
  skeleton->mutable_landmarks()->set_pelvis(0);
  constexpr float kFinal = 1.2f;
  std::vector<v1::Frame> frames;
  for (int f = 0; f < 30; ++f) {
    const float scale = f < 10 ? 1.0f : f < 20 ? 1.0f + (kFinal - 1.0f) * static_cast<float>(f - 10) / 10.0f : kFinal;
    v1::Frame frame;
    frame.set_index(f);
    if (scale != 1.0f) frame.set_body_scale(scale);
    const Eigen::Vector3f pelvis(0.03f * f, 0.89f * scale, 0.5f);  // standing straight, feet on the floor
    SetVec3(pelvis, frame.mutable_root_position());
    SetVec3(pelvis, frame.mutable_pelvis_position());
    for (int j = 0; j < skeleton->joints_size(); ++j)
      SetQuaternion(Eigen::Quaternionf::Identity(), frame.add_rotations());
    frames.push_back(std::move(frame));
  }
  const absl::StatusOr<std::string> text = cli::ReconstructionBvh(started, frames);
  ASSERT_TRUE(text.ok()) << text.status();
  const absl::StatusOr<BvhClip> parsed = ParseBvh(*text, "grown.bvh");
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  const int foot = parsed->skeleton.Find("LeftFoot");
  ASSERT_GT(foot, 0);
  EXPECT_NEAR(parsed->skeleton.joint(foot).offset.y(), -0.42f * kFinal, 1e-5f);  // the size reached
  const GlobalPoses read =
      ForwardKinematics(parsed->skeleton, MotionFromChannels(parsed->skeleton, parsed->channels, parsed->frame_time));
  ASSERT_EQ(read.num_frames(), 30);
  for (int f = 0; f < read.num_frames(); ++f) {
    EXPECT_NEAR(read.position(f, foot).y(), 0.0f, 1e-4f) << "frame " << f;    // on the floor
    EXPECT_NEAR(read.position(f, 0).x(), 0.03f * f, 1e-5f) << "frame " << f;  // over the same ground point
    EXPECT_NEAR(read.position(f, 0).z(), 0.5f, 1e-5f) << "frame " << f;
  }
}

// `mocap reconstruct --target-rig AVATAR.bvh` on a rig whose pelvis has no position channels
// (cmu-cc's CC_Base_Hip under RL_BoneRoot; here the synthetic Z-up rig's Hips): the file gives the
// pelvis position channels and holds the root at rest, instead of moving the root with the body.
TEST(ReconstructionBvhTest, OnATargetRigWhosePelvisHasNoPositionChannelsTheRootStaysStill) {
  const std::string avatar_text = FormatBvh(testing::MakeWalkingClip({.z_up = true}, 30));
  const absl::StatusOr<BvhClip> avatar = ParseBvh(avatar_text, "avatar.bvh");  // the rig's joint order
  ASSERT_TRUE(avatar.ok()) << avatar.status();
  const absl::StatusOr<RetargetRig> rig = TargetRigFromBvh(avatar_text);
  ASSERT_TRUE(rig.ok()) << rig.status();
  const int joints = rig->skeleton.num_joints();
  ASSERT_EQ(avatar->skeleton.num_joints(), joints);
  const int pelvis = rig->topology.landmarks.pelvis;
  ASSERT_GT(pelvis, 0) << "a root above the pelvis";
  ASSERT_EQ(PositionChannelCount(avatar->skeleton.joint(pelvis)), 0) << "the case under test";

  // Frames on the target rig as the service sends them (metres, world Y up): the avatar's own walk,
  // turning about the vertical so that the root's rotation changes too.
  LocalMotion motion = MotionFromChannels(avatar->skeleton, avatar->channels, avatar->frame_time);
  ScaleTranslations(motion, static_cast<float>(MetresPerUnit(rig->unit)));
  RotateWorld(motion, rig->to_y_up);
  for (int f = 0; f < motion.num_frames(); ++f) {
    const Eigen::Quaternionf turn(Eigen::AngleAxisf(0.03f * f, Eigen::Vector3f::UnitY()));
    motion.SetRotation(f, 0, turn * motion.rotation(f, 0));
    motion.SetTranslation(f, 0, turn * motion.translation(f, 0));
  }
  const GlobalPoses expected = ForwardKinematics(rig->skeleton, motion);
  v1::SessionStarted started;
  started.set_frame_rate(1.0 / avatar->frame_time);
  for (int j = 0; j < joints; ++j) {
    AddJoint(started.mutable_skeleton(), rig->skeleton.joint(j).name, rig->skeleton.parent(j),
             rig->skeleton.joint(j).offset);
  }
  started.mutable_skeleton()->mutable_landmarks()->set_pelvis(pelvis);
  std::vector<v1::Frame> frames(motion.num_frames());
  for (int f = 0; f < motion.num_frames(); ++f) {
    frames[f].set_index(f);
    SetVec3(motion.translation(f, 0), frames[f].mutable_root_position());
    for (int j = 0; j < joints; ++j) SetQuaternion(motion.rotation(f, j), frames[f].add_rotations());
  }

  const absl::StatusOr<std::string> text = cli::RetargetedBvhText(avatar_text, started, frames);
  ASSERT_TRUE(text.ok()) << text.status();
  const absl::StatusOr<BvhClip> parsed = ParseBvh(*text, "retargeted.bvh");
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  ASSERT_EQ(parsed->num_frames(), motion.num_frames());
  ASSERT_EQ(parsed->skeleton.num_joints(), joints);
  EXPECT_EQ(PositionChannelCount(parsed->skeleton.joint(pelvis)), 3) << "the pelvis carries the motion";
  const GlobalPoses read =
      ForwardKinematics(parsed->skeleton, MotionFromChannels(parsed->skeleton, parsed->channels, parsed->frame_time));
  // The file is in the rig's own unit and axes: back to metres, Y up.
  const float metres = static_cast<float>(MetresPerUnit(rig->unit));
  std::vector<Eigen::Vector3f> root_track, pelvis_track;
  for (int f = 0; f < read.num_frames(); ++f) {
    for (int j = 0; j < joints; ++j) {
      ASSERT_EQ(parsed->skeleton.joint(j).name, rig->skeleton.joint(j).name);
      if (j == 0) continue;  // the root is held (below)
      const Eigen::Vector3f world = rig->to_y_up * (metres * read.position(f, j));
      EXPECT_LT((world - expected.position(f, j)).norm(), 1e-3f)
          << rig->skeleton.joint(j).name << " at frame " << f << ": " << world.transpose() << " where the frame says "
          << expected.position(f, j).transpose();
    }
    root_track.push_back(rig->to_y_up * (metres * read.position(f, 0)));
    pelvis_track.push_back(rig->to_y_up * (metres * read.position(f, pelvis)));
  }
  ExpectRootOnTheFloorStillOrUnderTheBody(root_track, pelvis_track, rig->leg_length);
  // Still: the rig's root OFFSET (zero here) in every frame, while the walk travels.
  for (size_t f = 0; f < root_track.size(); ++f) EXPECT_LT(root_track[f].norm(), 1e-3f) << "frame " << f;
  EXPECT_GT((pelvis_track.back() - pelvis_track.front()).norm(), 0.3f) << "the pelvis travels";
}

}  // namespace
}  // namespace mocap
