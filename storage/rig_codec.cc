#include "storage/rig_codec.h"

#include <optional>

#include <nlohmann/json.hpp>

namespace mocap::storage {
namespace {

using nlohmann::json;

json Vec(const Eigen::Vector3f& v) { return json::array({v.x(), v.y(), v.z()}); }
Eigen::Vector3f ToVec(const json& j) { return {j.at(0).get<float>(), j.at(1).get<float>(), j.at(2).get<float>()}; }
json Quat(const Eigen::Quaternionf& q) { return json::array({q.w(), q.x(), q.y(), q.z()}); }
Eigen::Quaternionf ToQuat(const json& j) {
  return Eigen::Quaternionf(j.at(0).get<float>(), j.at(1).get<float>(), j.at(2).get<float>(), j.at(3).get<float>());
}

}  // namespace

std::string EncodeRig(const RigModel& rig) {
  json joints = json::array();
  for (int j = 0; j < rig.skeleton.num_joints(); ++j) {
    const Joint& joint = rig.skeleton.joint(j);
    json channels = json::array();
    for (ChannelType c : joint.channels) channels.push_back(std::string(ChannelName(c)));
    json entry = {{"name", joint.name},
                  {"parent", joint.parent},
                  {"offset", Vec(joint.offset)},
                  {"channels", channels},
                  {"group", std::string(BodyGroupName(rig.topology.group_of_joint[j]))},
                  {"reference_rotation", Quat(rig.reference_rotations[j])}};
    if (joint.end_site) entry["end_site"] = Vec(*joint.end_site);
    joints.push_back(entry);
  }
  const BodyTopology& t = rig.topology;
  const BodyLandmarks& l = t.landmarks;
  json out = {
      {"format", 1},
      {"joints", joints},
      {"unit", std::string(UnitName(rig.unit))},
      {"to_y_up", Quat(rig.to_y_up)},
      {"pelvis_up_local", Vec(rig.pelvis_up_local)},
      {"landmarks",
       {{"pelvis", l.pelvis},
        {"head", l.head},
        {"left_wrist", l.left_wrist},
        {"right_wrist", l.right_wrist},
        {"left_ankle", l.left_ankle},
        {"right_ankle", l.right_ankle},
        {"left_elbow", l.left_elbow},
        {"right_elbow", l.right_elbow},
        {"left_knee", l.left_knee},
        {"right_knee", l.right_knee},
        {"left_shoulder", l.left_shoulder},
        {"right_shoulder", l.right_shoulder},
        {"left_hip", l.left_hip},
        {"right_hip", l.right_hip}}},
      {"group_top", t.group_top},
      {"group_end", t.group_end},
      {"up", {{"axis", t.up_axis}, {"sign", t.up_sign}, {"alignment", t.up_alignment}}},
      {"rest_up", {{"axis", t.rest_up_axis}, {"sign", t.rest_up_sign}}},
      {"forward", Vec(t.forward)},
      {"leg_length", t.leg_length},
      {"standing_pelvis_height", t.standing_pelvis_height},
      {"floor_height", t.floor_height},
      {"unit_detected", t.unit_detected},
  };
  return out.dump();
}

absl::StatusOr<RigModel> DecodeRig(const std::string& text) {
  try {
    const json in = json::parse(text);
    if (in.at("format").get<int>() != 1) return absl::DataLossError("unknown rig format");
    RigModel rig;
    std::vector<Joint> joints;
    for (const json& entry : in.at("joints")) {
      Joint joint;
      joint.name = entry.at("name").get<std::string>();
      joint.parent = entry.at("parent").get<int>();
      joint.offset = ToVec(entry.at("offset"));
      for (const json& c : entry.at("channels")) {
        const std::string name = c.get<std::string>();
        bool found = false;
        for (int type = 0; type < 6; ++type) {
          if (ChannelName(static_cast<ChannelType>(type)) == name) {
            joint.channels.push_back(static_cast<ChannelType>(type));
            found = true;
          }
        }
        if (!found) return absl::DataLossError("rig has an unknown channel");
      }
      if (entry.contains("end_site")) joint.end_site = ToVec(entry.at("end_site"));
      rig.reference_rotations.push_back(ToQuat(entry.at("reference_rotation")));
      const std::string group = entry.at("group").get<std::string>();
      std::optional<BodyGroup> body_group;
      for (int g = 0; g < kNumBodyGroups; ++g) {
        if (BodyGroupName(static_cast<BodyGroup>(g)) == group) body_group = static_cast<BodyGroup>(g);
      }
      if (!body_group) return absl::DataLossError("rig has an unknown body group");
      rig.topology.group_of_joint.push_back(*body_group);
      joints.push_back(std::move(joint));
    }
    rig.skeleton = Skeleton(std::move(joints));
    if (absl::Status status = rig.skeleton.Validate(); !status.ok()) {
      return absl::DataLossError("stored rig is invalid: " + std::string(status.message()));
    }
    auto unit = ParseUnit(in.at("unit").get<std::string>());
    if (!unit) return absl::DataLossError("rig has an unknown unit");
    rig.unit = *unit;
    rig.topology.unit = *unit;
    rig.to_y_up = ToQuat(in.at("to_y_up"));
    rig.pelvis_up_local = ToVec(in.at("pelvis_up_local"));
    const json& l = in.at("landmarks");
    BodyLandmarks& landmarks = rig.topology.landmarks;
    landmarks = {l.at("pelvis"),      l.at("head"),       l.at("left_wrist"),
                 l.at("right_wrist"), l.at("left_ankle"), l.at("right_ankle")};
    for (int joint : {landmarks.pelvis, landmarks.head, landmarks.left_wrist, landmarks.right_wrist,
                      landmarks.left_ankle, landmarks.right_ankle}) {
      if (joint < 0 || joint >= rig.skeleton.num_joints()) return absl::DataLossError("rig landmark out of range");
    }
    // Elbows and knees: stored since issue #12, shoulders and hips since #11 (-1 in older rigs).
    for (auto [key, joint] :
         {std::pair{"left_elbow", &landmarks.left_elbow}, std::pair{"right_elbow", &landmarks.right_elbow},
          std::pair{"left_knee", &landmarks.left_knee}, std::pair{"right_knee", &landmarks.right_knee},
          std::pair{"left_shoulder", &landmarks.left_shoulder}, std::pair{"right_shoulder", &landmarks.right_shoulder},
          std::pair{"left_hip", &landmarks.left_hip}, std::pair{"right_hip", &landmarks.right_hip}}) {
      *joint = l.value(key, -1);
      if (*joint < -1 || *joint >= rig.skeleton.num_joints()) return absl::DataLossError("rig landmark out of range");
    }
    rig.topology.group_top = in.at("group_top").get<std::array<int, kNumBodyGroups>>();
    rig.topology.group_end = in.at("group_end").get<std::array<int, kNumBodyGroups>>();
    rig.topology.up_axis = in.at("up").at("axis");
    rig.topology.up_sign = in.at("up").at("sign");
    rig.topology.up_alignment = in.at("up").at("alignment");
    rig.topology.rest_up_axis = in.at("rest_up").at("axis");
    rig.topology.rest_up_sign = in.at("rest_up").at("sign");
    rig.topology.forward = ToVec(in.at("forward"));
    rig.topology.leg_length = in.at("leg_length");
    rig.topology.standing_pelvis_height = in.at("standing_pelvis_height");
    rig.topology.floor_height = in.at("floor_height");
    rig.topology.unit_detected = in.at("unit_detected");
    // Indices other code trusts (BodyTopology::up() indexes a 3-vector by the axis).
    const auto axis_ok = [](int axis, int sign) { return axis >= 0 && axis < 3 && (sign == 1 || sign == -1); };
    if (!axis_ok(rig.topology.up_axis, rig.topology.up_sign) ||
        !axis_ok(rig.topology.rest_up_axis, rig.topology.rest_up_sign)) {
      return absl::DataLossError("rig has an invalid up axis");
    }
    for (const auto* joints_of_groups : {&rig.topology.group_top, &rig.topology.group_end}) {
      for (int joint : *joints_of_groups) {
        if (joint < -1 || joint >= rig.skeleton.num_joints())
          return absl::DataLossError("rig group joint out of range");
      }
    }
    return rig;
  } catch (const nlohmann::json::exception& error) {
    return absl::DataLossError(std::string("stored rig is unreadable: ") + error.what());
  }
}

}  // namespace mocap::storage
