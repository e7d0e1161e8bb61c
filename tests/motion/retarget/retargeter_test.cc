#include "motion/retarget/retargeter.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "motion/bvh/bvh_reader.h"
#include "motion/bvh/bvh_writer.h"
#include "motion/retarget/retarget_export.h"
#include "motion/skeleton/forward_kinematics.h"
#include "tests/support/rig_variants.h"
#include "tests/support/synthetic_database.h"
#include "tests/support/temp_dir.h"

namespace mocap {
namespace {

// The synthetic database's rig as the source, and its test walk's frames (truth) as what a
// reconstruction gave on it.
struct Source {
  testing::SyntheticReconstructionSetup setup = testing::MakeSyntheticReconstructionSetup({}, 60);
  RetargetRig rig;
  std::vector<std::vector<Eigen::Quaternionf>> rotations;
  std::vector<std::vector<Eigen::Vector3f>> positions;

  Source() {
    auto source = SourceRigOf(setup.database->rig(), setup.database->body().skeleton());
    EXPECT_TRUE(source.ok()) << source.status();
    rig = *source;
    for (int f = 0; f < setup.truth.num_frames(); ++f) {
      rotations.emplace_back();
      positions.emplace_back();
      for (int j = 0; j < setup.truth.num_joints(); ++j) {
        rotations.back().push_back(setup.truth.rotation(f, j));
        positions.back().push_back(setup.truth.position(f, j));
      }
    }
  }
};

const Source& TheSource() {
  static const Source* source = new Source();
  return *source;
}

// A target rig made from the synthetic walking rig: `edit` changes the clip (renames, extra
// joints, proportions, units, axes, rest pose) before it is written as BVH text.
absl::StatusOr<RetargetRig> TargetFrom(const testing::SyntheticRigOptions& options,
                                       const std::function<void(BvhClip&, const BodyTopology&)>& edit = nullptr) {
  BvhClip clip = testing::MakeWalkingClip(options, 60);
  if (edit) {
    auto rig = BuildRigModel(clip, {});
    if (!rig.ok()) return rig.status();
    edit(clip, rig->topology);
  }
  return TargetRigFromBvh(FormatBvh(clip));
}

// Turns the rest pose's arms down by `degrees` about the body's forward axis (a T-pose rig
// becomes an A-pose rig): every offset below each shoulder joint is rotated.
void ArmsDownAtRest(BvhClip& clip, const BodyTopology& topology, float degrees) {
  std::vector<Joint> joints = clip.skeleton.joints();
  for (BodyGroup arm : {BodyGroup::kLeftArm, BodyGroup::kRightArm}) {
    const float sign = arm == BodyGroup::kLeftArm ? -1.0f : 1.0f;  // left arm at +X turns towards -Y
    const Eigen::AngleAxisf turn(sign * degrees * static_cast<float>(M_PI) / 180.0f, Eigen::Vector3f::UnitZ());
    const int top = topology.group_top[static_cast<int>(arm)];
    for (int j = 0; j < clip.skeleton.num_joints(); ++j) {
      int a = j;
      while (a > top) a = clip.skeleton.parent(a);
      if (a != top || j == top || clip.skeleton.parent(j) == top) continue;  // below the shoulder joint
      joints[j].offset = turn * joints[j].offset;
      if (joints[j].end_site) joints[j].end_site = turn * *joints[j].end_site;
    }
  }
  clip.skeleton = Skeleton(std::move(joints));
}

struct Result {
  std::vector<std::vector<Eigen::Vector3f>> positions;  // target world, per frame
  std::vector<std::vector<Eigen::Quaternionf>> rotations;
  std::vector<BodyPose> poses;
};

Result RetargetAll(Retargeter& retargeter, const Source& source) {
  Result result;
  for (size_t f = 0; f < source.rotations.size(); ++f) {
    BodyPose pose;
    retargeter.Retarget(source.rotations[f], source.positions[f], &pose);
    result.poses.push_back(pose);
    result.positions.push_back(retargeter.world_positions());
    result.rotations.push_back(retargeter.world_rotations());
  }
  return result;
}

float AngleBetween(const Eigen::Quaternionf& a, const Eigen::Quaternionf& b) { return a.angularDistance(b); }

TEST(RetargeterTest, OntoItsOwnRigEveryJointLandsWhereTheSourceIs) {
  const Source& source = TheSource();
  auto target = TargetFrom({});
  ASSERT_TRUE(target.ok()) << target.status();
  auto retargeter = Retargeter::Create(source.rig, *target);
  ASSERT_TRUE(retargeter.ok()) << retargeter.status();
  EXPECT_NEAR(retargeter->scale(), 1.0f, 1e-4f);
  const Result result = RetargetAll(*retargeter, source);
  for (size_t f = 0; f < result.positions.size(); ++f) {
    for (int j = 0; j < target->skeleton.num_joints(); ++j) {
      EXPECT_LT((result.positions[f][j] - source.positions[f][j]).norm(), 1e-3f) << "frame " << f << " joint " << j;
    }
  }
}

struct Variant {
  std::string name;
  testing::SyntheticRigOptions options;
  std::function<void(BvhClip&, const BodyTopology&)> edit;
};

std::vector<Variant> Variants() {
  return {
      {"renamed", {}, [](BvhClip& c, const BodyTopology&) { testing::RenameJoints(c); }},
      {"fingers_toes_twist_bones", {.fingers_and_toes = true, .twist_bones = true}, nullptr},
      {"z_up_inches", {.z_up = true, .length_scale = 1.0 / 2.54}, nullptr},
      {"extra_root_metres", {.extra_root = true, .position_channels_everywhere = true, .length_scale = 0.01}, nullptr},
      {"long_legs_short_arms",
       {},
       [](BvhClip& c, const BodyTopology& t) {
         testing::ScaleProportions(c, t, {.legs = 1.2f, .arms = 0.8f, .spine = 1.15f, .head = 0.9f});
       }},
      {"a_pose_split_forearm",
       {},
       [](BvhClip& c, const BodyTopology& t) {
         ArmsDownAtRest(c, t, 45.0f);
         ASSERT_TRUE(testing::SplitBone(c, c.skeleton.Find("LeftHand"), "LeftForeArmSplit").ok());
       }},
  };
}

absl::StatusOr<Retargeter> RetargeterOnto(const Variant& variant) {
  auto target = TargetFrom(variant.options, variant.edit);
  if (!target.ok()) return target.status();
  return Retargeter::Create(TheSource().rig, *std::move(target));
}

// What the retargeting promises (retargeter.h step 4) and no flips, on rigs that differ from the
// database's in names, joint count, units, axes, proportions and rest pose.
TEST(RetargeterTest, LandmarksFollowTheSourceOnEveryVariantRig) {
  const Source& source = TheSource();
  const BodyLandmarks& sl = source.rig.topology.landmarks;
  for (const Variant& variant : Variants()) {
    SCOPED_TRACE(variant.name);
    auto retargeter = RetargeterOnto(variant);
    ASSERT_TRUE(retargeter.ok()) << retargeter.status();
    const RetargetRig* target = &retargeter->target();
    const float k = retargeter->scale();
    const Result result = RetargetAll(*retargeter, source);
    const BodyLandmarks& tl = target->topology.landmarks;
    // Scaled about the floor under the first frame's pelvis, not the world origin.
    ASSERT_TRUE(retargeter->anchor().has_value());
    const Eigen::Vector3f anchor = *retargeter->anchor();
    EXPECT_NEAR(anchor.x(), source.positions[0][sl.pelvis].x(), 1e-5f);
    EXPECT_EQ(anchor.y(), 0.0f);
    auto scaled = [&](const Eigen::Vector3f& p) -> Eigen::Vector3f { return anchor + k * (p - anchor); };
    float largest_source_step = 0.0f, largest_target_step = 0.0f;
    for (size_t f = 0; f < result.positions.size(); ++f) {
      const auto& t = result.positions[f];
      const auto& s = source.positions[f];
      EXPECT_LT((t[tl.pelvis] - scaled(s[sl.pelvis])).norm(), 1e-3f) << "frame " << f;
      EXPECT_LT((t[tl.left_ankle] - scaled(s[sl.left_ankle])).norm(), 1e-3f) << "frame " << f;
      EXPECT_LT((t[tl.right_ankle] - scaled(s[sl.right_ankle])).norm(), 1e-3f) << "frame " << f;
      // Hands: the source's reach from the shoulder, scaled to the target's arm.
      const int arms[2] = {static_cast<int>(BodyGroup::kLeftArm), static_cast<int>(BodyGroup::kRightArm)};
      const int target_wrists[2] = {tl.left_wrist, tl.right_wrist}, source_wrists[2] = {sl.left_wrist, sl.right_wrist};
      for (int side = 0; side < 2; ++side) {
        const int ts = target->chains.joints[arms[side]][target->anchors[arms[side]].root];
        const int ss = source.rig.chains.joints[arms[side]][source.rig.anchors[arms[side]].root];
        const Eigen::Vector3f wanted =
            t[ts] + (s[source_wrists[side]] - s[ss]) * (target->arm_length[side] / source.rig.arm_length[side]);
        EXPECT_LT((t[target_wrists[side]] - wanted).norm(), 2e-3f) << "frame " << f << " side " << side;
      }
      // The head: where the source's is, in leg lengths, give or take what the proportions move it
      // (a spine 15% longer on 20% longer legs puts it 0.1 leg lengths off).
      const float head_error =
          ((t[tl.head] - anchor) / target->leg_length - (s[sl.head] - anchor) / source.rig.leg_length).norm();
      EXPECT_LT(head_error, 0.12f) << "frame " << f;
      if (f > 0) {
        for (int j = 0; j < source.rig.skeleton.num_joints(); ++j) {
          largest_source_step =
              std::max(largest_source_step, AngleBetween(source.rotations[f][j], source.rotations[f - 1][j]));
        }
        for (int j = 0; j < target->skeleton.num_joints(); ++j) {
          largest_target_step =
              std::max(largest_target_step, AngleBetween(result.rotations[f][j], result.rotations[f - 1][j]));
        }
      }
    }
    // No flips: no target joint turns between two frames much more than any source joint does.
    EXPECT_LT(largest_target_step, largest_source_step + 0.1f);
  }
}

// Hands and feet point where the source's do, whatever the rest pose (T vs A) and joint count.
TEST(RetargeterTest, HandsAndFeetPointWhereTheSourcesDo) {
  const Source& source = TheSource();
  const BodyTopology& st = source.rig.topology;
  for (const Variant& variant : Variants()) {
    SCOPED_TRACE(variant.name);
    auto retargeter = RetargeterOnto(variant);
    ASSERT_TRUE(retargeter.ok()) << retargeter.status();
    const RetargetRig* target = &retargeter->target();
    const Result result = RetargetAll(*retargeter, source);
    const BodyTopology& tt = target->topology;
    for (BodyGroup limb : {BodyGroup::kLeftArm, BodyGroup::kRightArm, BodyGroup::kLeftLeg, BodyGroup::kRightLeg}) {
      const int g = static_cast<int>(limb);
      const int t_end = target->chains.joints[g].back(), s_end = source.rig.chains.joints[g].back();
      if (tt.group_end[g] == t_end || st.group_end[g] == s_end) continue;  // a hand without fingers: nothing beyond
      for (size_t f = 0; f < result.positions.size(); f += 7) {
        const Eigen::Vector3f t_dir = (result.positions[f][tt.group_end[g]] - result.positions[f][t_end]).normalized();
        const Eigen::Vector3f s_dir = (source.positions[f][st.group_end[g]] - source.positions[f][s_end]).normalized();
        EXPECT_GT(t_dir.dot(s_dir), std::cos(0.1f)) << BodyGroupName(limb) << " frame " << f;
      }
    }
  }
}

TEST(RetargeterTest, TheBvhIsWrittenInTheTargetFilesOwnUnitsAxesAndChannels) {
  const Source& source = TheSource();
  for (const Variant& variant : Variants()) {
    SCOPED_TRACE(variant.name);
    auto retargeter = RetargeterOnto(variant);
    ASSERT_TRUE(retargeter.ok()) << retargeter.status();
    const RetargetRig* target = &retargeter->target();
    const Result result = RetargetAll(*retargeter, source);
    const BvhClip written = RetargetedToBvh(*target, result.poses, 1.0 / 30);
    auto parsed = ParseBvh(FormatBvh(written), "retargeted.bvh");
    ASSERT_TRUE(parsed.ok()) << parsed.status();
    ASSERT_EQ(parsed->skeleton.num_joints(), target->skeleton.num_joints());
    for (int j = 0; j < parsed->skeleton.num_joints(); ++j) {
      EXPECT_EQ(parsed->skeleton.joint(j).name, target->skeleton.joint(j).name);
      EXPECT_EQ(parsed->skeleton.joint(j).channels, target->skeleton.joint(j).channels);
    }
    // Read back in the file's unit and axes, then to metres and Y up: the retargeted motion.
    const LocalMotion motion = MotionFromChannels(parsed->skeleton, parsed->channels, parsed->frame_time);
    const GlobalPoses poses = ForwardKinematics(parsed->skeleton, motion);
    const float metres = static_cast<float>(MetresPerUnit(target->unit));
    const int pelvis = target->topology.landmarks.pelvis;
    for (int f : {0, 29, 59}) {
      for (int j = 0; j < poses.num_joints(); ++j) {
        bool above_pelvis = false;  // held still, as captures keep them
        for (int a = target->skeleton.parent(pelvis); a >= 0; a = target->skeleton.parent(a)) above_pelvis |= a == j;
        if (above_pelvis) continue;
        const Eigen::Vector3f read_back = target->to_y_up * (poses.position(f, j) * metres);
        EXPECT_LT((read_back - result.positions[f][j]).norm(), 1e-3f) << "frame " << f << " joint " << j;
      }
    }
  }
}

// Blender's BVH importer (Debian's blender, headless) reads every written file with one bone per
// joint of the target rig. Skipped, with a message, where blender is not installed
// (scripts/setup.sh installs it).
TEST(RetargeterTest, BlenderImportsTheWrittenBvhWithOneBonePerJoint) {
  if (std::system("command -v blender >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "blender is not installed (apt-get install blender)";
  const Source& source = TheSource();
  testing::ScopedTempDir dir;
  std::map<std::string, int> expected;  // file -> joints
  for (const Variant& variant : Variants()) {
    auto retargeter = RetargeterOnto(variant);
    ASSERT_TRUE(retargeter.ok()) << retargeter.status();
    const RetargetRig* target = &retargeter->target();
    const std::string path = (dir.path() / (variant.name + ".bvh")).string();
    std::ofstream(path) << FormatBvh(RetargetedToBvh(*target, RetargetAll(*retargeter, source).poses, 1.0 / 30));
    expected[path] = target->skeleton.num_joints();
  }
  // Blender 3.4's importer opens files with mode 'rU', which Python 3.11 refuses: drop the 'U'.
  const std::string script = (dir.path() / "count_bones.py").string();
  std::ofstream(script) << "import builtins, sys, bpy\n"
                           "_open = builtins.open\n"
                           "builtins.open = lambda f, mode='r', *a, **k: _open(f, mode.replace('U', ''), *a, **k)\n"
                           "for path in sys.argv[sys.argv.index('--') + 1:]:\n"
                           "    bpy.ops.wm.read_factory_settings(use_empty=True)\n"
                           "    bpy.ops.import_anim.bvh(filepath=path)\n"
                           "    arm = [o for o in bpy.data.objects if o.type == 'ARMATURE'][0]\n"
                           "    print('BONES', len(arm.data.bones), path, flush=True)\n";
  std::string command = "blender -b --factory-startup --python " + script + " --";
  for (const auto& [path, joints] : expected) command += " " + path;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::map<std::string, int> counted;
  char line[4096];
  while (std::fgets(line, sizeof line, pipe)) {
    char path[4000];
    int bones = 0;
    if (std::sscanf(line, "BONES %d %3999s", &bones, path) == 2) counted[path] = bones;
  }
  pclose(pipe);
  for (const auto& [path, joints] : expected) {
    ASSERT_TRUE(counted.count(path)) << "blender did not import " << path;
    EXPECT_EQ(counted[path], joints) << path;
  }
}

TEST(RetargeterTest, AHierarchyWithoutFramesIsARigWhenItsRestPoseStands) {
  const BvhClip clip = testing::MakeWalkingClip({.fingers_and_toes = true}, 30);
  const std::string text = FormatBvh(clip);
  auto with_frames = TargetRigFromBvh(text);
  auto hierarchy_only = TargetRigFromBvh(text.substr(0, text.find("MOTION")));
  ASSERT_TRUE(with_frames.ok()) << with_frames.status();
  ASSERT_TRUE(hierarchy_only.ok()) << hierarchy_only.status();
  const BodyLandmarks& a = with_frames->topology.landmarks;
  const BodyLandmarks& b = hierarchy_only->topology.landmarks;
  EXPECT_EQ(
      std::tie(a.pelvis, a.head, a.left_wrist, a.right_wrist, a.left_ankle, a.right_ankle, a.left_elbow, a.left_knee),
      std::tie(b.pelvis, b.head, b.left_wrist, b.right_wrist, b.left_ankle, b.right_ankle, b.left_elbow, b.left_knee));
  EXPECT_NEAR(with_frames->leg_length, 0.85f, 1e-3f);
  EXPECT_NEAR(hierarchy_only->leg_length, 0.85f, 1e-3f);
}

// Issue #24 finding 4: a 90-byte hierarchy declaring CHANNELS 99999999 made the server size a
// frame of that many values before reading it. It is refused at its line, allocating nothing.
TEST(RetargeterTest, AbsurdChannelCountsInAHierarchyAreRefusedBeforeSizingAFrame) {
  const std::string hostile = "HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 99999999 Xposition\n}\n";
  std::string many;
  for (int i = 0; i < 30; ++i) many += hostile;
  for (const std::string& text : {hostile, many}) {
    auto rig = TargetRigFromBvh(text);
    ASSERT_FALSE(rig.ok());
    EXPECT_NE(rig.status().message().find("channel count"), std::string_view::npos) << rig.status();
  }
}

TEST(RetargeterTest, WhatIsNotARigIsRefusedWithTheReason) {
  auto garbage = TargetRigFromBvh("HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0\n");
  EXPECT_EQ(garbage.status().code(), absl::StatusCode::kInvalidArgument) << garbage.status();
  // A chain of bones: no limbs to find.
  std::vector<Joint> joints;
  for (int j = 0; j < 6; ++j) {
    Joint joint;
    joint.name = "bone" + std::to_string(j);
    joint.parent = j - 1;
    joint.offset = Eigen::Vector3f(0, j == 0 ? 0 : 10, 0);
    joint.channels = {ChannelType::kZrotation, ChannelType::kXrotation, ChannelType::kYrotation};
    if (j == 5) joint.end_site = Eigen::Vector3f(0, 5, 0);
    joints.push_back(joint);
  }
  auto snake = TargetRigFromSkeleton(Skeleton(joints));
  EXPECT_EQ(snake.status().code(), absl::StatusCode::kFailedPrecondition) << snake.status();
  EXPECT_NE(snake.status().message().find("not a recognisable humanoid"), std::string::npos) << snake.status();
}

}  // namespace
}  // namespace mocap
