// The rig column's codec (storage/rig_codec.h): every field of a RigModel survives a round trip
// bit for bit (real analysed rigs of every synthetic variant, and a hand-made one at the edges:
// odd names, channel orders, inches, all groups and landmarks), rigs stored before elbows and knees
// were kept still read, and text that is not a rig is refused with DataLoss, never read as one.
#include "storage/rig_codec.h"

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/synthetic_clip.h"

namespace mocap::storage {
// Named, so that helpers do not meet other files' in a unity batch.
namespace rig_codec_test {
namespace {

using nlohmann::json;

void ExpectSameVector(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const std::string& what) {
  for (int i = 0; i < 3; ++i) EXPECT_EQ(a[i], b[i]) << what << "[" << i << "]";
}
void ExpectSameQuaternion(const Eigen::Quaternionf& a, const Eigen::Quaternionf& b, const std::string& what) {
  EXPECT_EQ(a.coeffs(), b.coeffs()) << what;  // (x, y, z, w) exactly: w is not confused with x
}

// Every field, exactly (floats go through JSON as doubles and back without loss).
void ExpectSameRig(const RigModel& a, const RigModel& b) {
  ASSERT_EQ(a.skeleton.num_joints(), b.skeleton.num_joints());
  for (int j = 0; j < a.skeleton.num_joints(); ++j) {
    const Joint& x = a.skeleton.joint(j);
    const Joint& y = b.skeleton.joint(j);
    const std::string at = "joint " + std::to_string(j) + " (" + x.name + ")";
    EXPECT_EQ(x.name, y.name) << at;
    EXPECT_EQ(x.parent, y.parent) << at;
    ExpectSameVector(x.offset, y.offset, at + " offset");
    EXPECT_EQ(x.channels, y.channels) << at;
    ASSERT_EQ(x.end_site.has_value(), y.end_site.has_value()) << at;
    if (x.end_site) ExpectSameVector(*x.end_site, *y.end_site, at + " end site");
  }
  EXPECT_EQ(a.skeleton.num_channels(), b.skeleton.num_channels());
  EXPECT_EQ(a.unit, b.unit);
  ExpectSameQuaternion(a.to_y_up, b.to_y_up, "to_y_up");
  ASSERT_EQ(a.reference_rotations.size(), b.reference_rotations.size());
  for (size_t j = 0; j < a.reference_rotations.size(); ++j) {
    ExpectSameQuaternion(a.reference_rotations[j], b.reference_rotations[j], "reference rotation " + std::to_string(j));
  }
  ExpectSameVector(a.pelvis_up_local, b.pelvis_up_local, "pelvis_up_local");
  const BodyTopology& s = a.topology;
  const BodyTopology& t = b.topology;
  EXPECT_EQ(s.group_of_joint, t.group_of_joint);
  EXPECT_EQ(s.group_top, t.group_top);
  EXPECT_EQ(s.group_end, t.group_end);
  const BodyLandmarks& l = s.landmarks;
  const BodyLandmarks& m = t.landmarks;
  EXPECT_EQ(std::vector<int>({l.pelvis, l.head, l.left_wrist, l.right_wrist, l.left_ankle, l.right_ankle, l.left_elbow,
                              l.right_elbow, l.left_knee, l.right_knee, l.left_shoulder, l.right_shoulder, l.left_hip,
                              l.right_hip}),
            std::vector<int>({m.pelvis, m.head, m.left_wrist, m.right_wrist, m.left_ankle, m.right_ankle, m.left_elbow,
                              m.right_elbow, m.left_knee, m.right_knee, m.left_shoulder, m.right_shoulder, m.left_hip,
                              m.right_hip}));
  EXPECT_EQ(s.up_axis, t.up_axis);
  EXPECT_EQ(s.up_sign, t.up_sign);
  EXPECT_EQ(s.up_alignment, t.up_alignment);
  ExpectSameVector(s.forward, t.forward, "forward");
  EXPECT_EQ(s.rest_up_axis, t.rest_up_axis);
  EXPECT_EQ(s.rest_up_sign, t.rest_up_sign);
  EXPECT_EQ(s.leg_length, t.leg_length);
  EXPECT_EQ(s.standing_pelvis_height, t.standing_pelvis_height);
  EXPECT_EQ(s.floor_height, t.floor_height);
  EXPECT_EQ(s.unit, t.unit);
  EXPECT_EQ(s.unit_detected, t.unit_detected);
}

RigModel AnalysedRig(const testing::SyntheticRigOptions& options) {
  auto rig = BuildRigModel(testing::MakeWalkingClip(options, 40), {});
  EXPECT_TRUE(rig.ok()) << rig.status();
  return rig.ok() ? *rig : RigModel{};
}

// A small rig at the edges of what the codec must carry.
RigModel HandMadeRig() {
  using C = ChannelType;
  std::vector<Joint> joints(7);
  joints[0] = {"Hips\"quoted\\",
               -1,
               {0.0f, 96.5f, -0.0f},
               {C::kYrotation, C::kZposition, C::kXrotation, C::kXposition, C::kZrotation, C::kYposition},
               std::nullopt};
  joints[1] = {"Rücken/Ω", 0, {1e-8f, 10.0f, 0.1f}, {C::kXrotation, C::kYrotation, C::kZrotation}, std::nullopt};
  joints[2] = {"Kopf", 1, {0, 30, 0}, {}, Eigen::Vector3f(0.0f, 3.4e38f, -1.17549435e-38f)};  // no channels
  joints[3] = {"L.Arm", 1, {20, 0, 0}, {C::kZrotation}, Eigen::Vector3f(25, 0, 0)};
  joints[4] = {"R.Arm", 1, {-20, 0, 0}, {C::kYrotation, C::kXrotation}, Eigen::Vector3f(-25, 0, 0)};
  joints[5] = {"L.Leg", 0, {9, -6, 0}, {C::kZrotation, C::kXrotation, C::kYrotation}, Eigen::Vector3f(0, -85, 0)};
  joints[6] = {"R.Leg", 0, {-9, -6, 0}, {C::kZrotation, C::kXrotation, C::kYrotation}, Eigen::Vector3f(0, -85, 0)};
  RigModel rig;
  rig.skeleton = Skeleton(joints);
  EXPECT_TRUE(rig.skeleton.Validate().ok()) << rig.skeleton.Validate();
  rig.unit = LengthUnit::kInch;
  rig.to_y_up = Eigen::Quaternionf(Eigen::AngleAxisf(-1.5707963f, Eigen::Vector3f::UnitX()));
  for (int j = 0; j < 7; ++j) {
    rig.reference_rotations.push_back(
        Eigen::Quaternionf(Eigen::AngleAxisf(0.1f + 0.37f * j, Eigen::Vector3f(1.0f, -2.0f, 0.5f * j).normalized())));
  }
  rig.pelvis_up_local = Eigen::Vector3f(0.1f, 0.9f, -0.3f);
  BodyTopology& t = rig.topology;
  t.group_of_joint = {BodyGroup::kSpine,    BodyGroup::kSpine,   BodyGroup::kHead,    BodyGroup::kLeftArm,
                      BodyGroup::kRightArm, BodyGroup::kLeftLeg, BodyGroup::kRightLeg};
  t.group_top = {0, 2, 3, 4, 5, 6};
  t.group_end = {1, 2, 3, 4, 5, 6};
  t.landmarks = {.pelvis = 0,
                 .head = 2,
                 .left_wrist = 3,
                 .right_wrist = 4,
                 .left_ankle = 5,
                 .right_ankle = 6,
                 .left_elbow = 3,
                 .right_elbow = -1,
                 .left_knee = -1,
                 .right_knee = 6,
                 .left_shoulder = 3,
                 .right_shoulder = -1,
                 .left_hip = 5,
                 .right_hip = -1};
  t.up_axis = 2;
  t.up_sign = -1;
  t.up_alignment = 0.987654321f;
  t.forward = Eigen::Vector3f(0.6f, 0.0f, -0.8f);
  t.rest_up_axis = 0;
  t.rest_up_sign = -1;
  t.leg_length = 33.46f;
  t.standing_pelvis_height = 37.9f;
  t.floor_height = -0.25f;
  t.unit = rig.unit;
  t.unit_detected = false;
  return rig;
}

TEST(RigCodecTest, AnalysedRigsOfEveryVariantRoundTripExactly) {
  for (int bits = 0; bits < 32; bits += 3) {  // a spread of the 32 rig combinations
    for (double scale : {1.0, 0.01, 1.0 / 2.54}) {
      testing::SyntheticRigOptions options = testing::SyntheticRigFromBits(bits, bits % 2 ? "XYZ" : "ZXY");
      options.length_scale = scale;
      SCOPED_TRACE("rig bits " + std::to_string(bits) + ", scale " + std::to_string(scale));
      const RigModel rig = AnalysedRig(options);
      ASSERT_GT(rig.skeleton.num_joints(), 0);
      auto decoded = DecodeRig(EncodeRig(rig));
      ASSERT_TRUE(decoded.ok()) << decoded.status();
      ExpectSameRig(rig, *decoded);
      EXPECT_EQ(EncodeRig(*decoded), EncodeRig(rig));  // and the text is stable
    }
  }
}

TEST(RigCodecTest, AHandMadeRigAtTheEdgesRoundTripsExactly) {
  const RigModel rig = HandMadeRig();
  const std::string text = EncodeRig(rig);
  auto decoded = DecodeRig(text);
  ASSERT_TRUE(decoded.ok()) << decoded.status() << "\n" << text;
  ExpectSameRig(rig, *decoded);
  // The stored text is JSON with the format tag (what older and newer builds check first).
  EXPECT_EQ(json::parse(text).at("format"), 1);
}

TEST(RigCodecTest, RigsStoredBeforeElbowsAndKneesReadAsUnknown) {
  json old = json::parse(EncodeRig(HandMadeRig()));
  for (const char* key : {"left_elbow", "right_elbow", "left_knee", "right_knee", "left_shoulder", "right_shoulder",
                          "left_hip", "right_hip"}) {
    old["landmarks"].erase(key);
  }
  auto decoded = DecodeRig(old.dump());
  ASSERT_TRUE(decoded.ok()) << decoded.status();
  const BodyLandmarks& l = decoded->topology.landmarks;
  EXPECT_EQ(l.left_elbow, -1);
  EXPECT_EQ(l.right_elbow, -1);
  EXPECT_EQ(l.left_knee, -1);
  EXPECT_EQ(l.right_knee, -1);
  EXPECT_EQ(l.left_shoulder, -1);
  EXPECT_EQ(l.right_hip, -1);
  EXPECT_EQ(l.pelvis, 0);
  EXPECT_EQ(l.right_ankle, 6);
}

// One malformed variant of a good rig's JSON: a description and the edit.
struct Breakage {
  std::string what;
  std::function<void(json&)> edit;
};

TEST(RigCodecTest, MalformedRigsAreRefusedWithDataLoss) {
  for (const std::string& text : {std::string(), std::string("not json"), std::string("{"), std::string("[]"),
                                  std::string("null"), std::string("{}"), EncodeRig(HandMadeRig()).substr(0, 200)}) {
    auto decoded = DecodeRig(text);
    EXPECT_EQ(decoded.status().code(), absl::StatusCode::kDataLoss) << "'" << text << "': " << decoded.status();
  }
  const std::vector<Breakage> breakages = {
      {"format 2", [](json& j) { j["format"] = 2; }},
      {"format as text", [](json& j) { j["format"] = "1"; }},
      {"no format", [](json& j) { j.erase("format"); }},
      {"no joints", [](json& j) { j["joints"] = json::array(); }},
      {"joints missing", [](json& j) { j.erase("joints"); }},
      {"two roots", [](json& j) { j["joints"][3]["parent"] = -1; }},
      {"parent after child", [](json& j) { j["joints"][1]["parent"] = 4; }},
      {"own parent", [](json& j) { j["joints"][2]["parent"] = 2; }},
      {"duplicate name", [](json& j) { j["joints"][4]["name"] = j["joints"][3]["name"]; }},
      {"empty name", [](json& j) { j["joints"][1]["name"] = ""; }},
      {"name with a space", [](json& j) { j["joints"][1]["name"] = "left arm"; }},
      {"unknown channel", [](json& j) { j["joints"][1]["channels"][0] = "Wrotation"; }},
      {"repeated channel",
       [](json& j) {
         j["joints"][1]["channels"] = {"Xrotation", "Xrotation"};
       }},
      {"channel not text", [](json& j) { j["joints"][1]["channels"][0] = 3; }},
      {"short offset",
       [](json& j) {
         j["joints"][1]["offset"] = {1.0, 2.0};
       }},
      {"offset of text",
       [](json& j) {
         j["joints"][1]["offset"] = {"1", "2", "3"};
       }},
      {"null end site", [](json& j) { j["joints"][2]["end_site"] = nullptr; }},
      {"no reference rotation", [](json& j) { j["joints"][5].erase("reference_rotation"); }},
      {"short reference rotation",
       [](json& j) {
         j["joints"][5]["reference_rotation"] = {1.0, 0.0, 0.0};
       }},
      {"no group", [](json& j) { j["joints"][0].erase("group"); }},
      {"unknown unit", [](json& j) { j["unit"] = "furlong"; }},
      {"no unit", [](json& j) { j.erase("unit"); }},
      {"pelvis past the joints", [](json& j) { j["landmarks"]["pelvis"] = 7; }},
      {"negative wrist", [](json& j) { j["landmarks"]["left_wrist"] = -1; }},
      {"no head", [](json& j) { j["landmarks"].erase("head"); }},
      {"knee below -1", [](json& j) { j["landmarks"]["left_knee"] = -2; }},
      {"elbow past the joints", [](json& j) { j["landmarks"]["right_elbow"] = 7; }},
      {"landmark as text", [](json& j) { j["landmarks"]["pelvis"] = "0"; }},
      {"short group_top",
       [](json& j) {
         j["group_top"] = {0, 1, 2};
       }},
      {"no group_end", [](json& j) { j.erase("group_end"); }},
      {"no up", [](json& j) { j.erase("up"); }},
      {"up without sign", [](json& j) { j["up"].erase("sign"); }},
      {"no forward", [](json& j) { j.erase("forward"); }},
      {"leg length as text", [](json& j) { j["leg_length"] = "33"; }},
      {"no to_y_up", [](json& j) { j.erase("to_y_up"); }},
      {"unit_detected missing", [](json& j) { j.erase("unit_detected"); }},
  };
  const json good = json::parse(EncodeRig(HandMadeRig()));
  ASSERT_TRUE(DecodeRig(good.dump()).ok());
  for (const Breakage& breakage : breakages) {
    json broken = good;
    breakage.edit(broken);
    auto decoded = DecodeRig(broken.dump());
    EXPECT_EQ(decoded.status().code(), absl::StatusCode::kDataLoss) << breakage.what << ": " << decoded.status();
  }
}

// A group name this build does not know is refused (it was read as "spine": a rig written by a newer
// build, or a corrupted one, silently got a wrong body topology), like unknown channels and units.
TEST(RigCodecTest, UnknownBodyGroupsAreRefused) {
  json broken = json::parse(EncodeRig(HandMadeRig()));
  broken["joints"][3]["group"] = "tail";
  auto decoded = DecodeRig(broken.dump());
  EXPECT_EQ(decoded.status().code(), absl::StatusCode::kDataLoss)
      << "joint 3 read as group " << (decoded.ok() ? BodyGroupName(decoded->topology.group_of_joint[3]) : "");
}

// The topology's axes and group joints are range-checked like the landmarks (up.axis 3 was accepted
// and BodyTopology::up() then wrote v[3] of a 3-vector), and a parent index below -1 fails
// Skeleton::Validate (it indexed joints[-2]).
TEST(RigCodecTest, OutOfRangeTopologyIsRefused) {
  const json good = json::parse(EncodeRig(HandMadeRig()));
  const std::vector<Breakage> breakages = {
      {"up axis 3", [](json& j) { j["up"]["axis"] = 3; }},
      {"up axis -1", [](json& j) { j["up"]["axis"] = -1; }},
      {"up sign 0", [](json& j) { j["up"]["sign"] = 0; }},
      {"rest up axis 5", [](json& j) { j["rest_up"]["axis"] = 5; }},
      {"group_top past the joints", [](json& j) { j["group_top"][2] = 99; }},
      {"group_end negative", [](json& j) { j["group_end"][4] = -7; }},
      {"parent -2", [](json& j) { j["joints"][3]["parent"] = -2; }},
  };
  for (const Breakage& breakage : breakages) {
    json broken = good;
    breakage.edit(broken);
    EXPECT_EQ(DecodeRig(broken.dump()).status().code(), absl::StatusCode::kDataLoss) << breakage.what;
  }
}

}  // namespace
}  // namespace rig_codec_test
}  // namespace mocap::storage
