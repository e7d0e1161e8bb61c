// `mocapd inspect FILE.bvh... [--json]`: what the importer understands about each file's skeleton.
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mocapd/commands.h"
#include "motion/bvh/bvh_inspection.h"

namespace mocap {
namespace {

nlohmann::json InspectionJson(const BvhInspection& inspection) {
  const BodyTopology& topology = inspection.topology;
  const Skeleton& skeleton = inspection.skeleton;
  const double metres = MetresPerUnit(topology.unit);
  auto name = [&](int joint) { return skeleton.joint(joint).name; };
  nlohmann::json report;
  report["file"] = inspection.file;
  report["joints"] = skeleton.num_joints();
  report["channels"] = skeleton.num_channels();
  report["frames"] = inspection.frames;
  report["frame_rate"] = inspection.frame_rate;
  report["duration_s"] = inspection.duration_seconds;
  report["root"] = name(0);
  report["up_axis"] = AxisName(topology.up_axis, topology.up_sign);
  report["up_alignment"] = topology.up_alignment;
  report["rest_pose_up_axis"] = AxisName(topology.rest_up_axis, topology.rest_up_sign);
  report["forward"] = {topology.forward.x(), topology.forward.y(), topology.forward.z()};
  report["units"] = {{"unit", std::string(UnitName(topology.unit))}, {"detected", topology.unit_detected}};
  report["body"] = {{"leg_length_m", topology.leg_length * metres},
                    {"standing_pelvis_height_m", topology.standing_pelvis_height * metres},
                    {"floor_height_m", topology.floor_height * metres}};
  const BodyLandmarks& l = topology.landmarks;
  report["landmarks"] = {{"pelvis", name(l.pelvis)},         {"head", name(l.head)},
                         {"left_wrist", name(l.left_wrist)}, {"right_wrist", name(l.right_wrist)},
                         {"left_ankle", name(l.left_ankle)}, {"right_ankle", name(l.right_ankle)}};
  // Where the limbs bend and their upper bones start (what a --query-pose may name).
  for (auto [key, joint] : {std::pair{"left_elbow", l.left_elbow}, std::pair{"right_elbow", l.right_elbow},
                            std::pair{"left_knee", l.left_knee}, std::pair{"right_knee", l.right_knee},
                            std::pair{"left_shoulder", l.left_shoulder}, std::pair{"right_shoulder", l.right_shoulder},
                            std::pair{"left_hip", l.left_hip}, std::pair{"right_hip", l.right_hip}}) {
    if (joint >= 0) report["landmarks"][key] = name(joint);
  }
  nlohmann::json groups = nlohmann::json::object();
  for (int g = 0; g < kNumBodyGroups; ++g) {
    groups[std::string(BodyGroupName(static_cast<BodyGroup>(g)))] = nlohmann::json::array();
  }
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    groups[std::string(BodyGroupName(topology.group_of_joint[j]))].push_back(name(j));
  }
  report["groups"] = groups;
  return report;
}

// The same report for people.
std::string InspectionText(const nlohmann::json& r) {
  std::ostringstream out;
  out << r["file"].get<std::string>() << "\n"
      << "  joints " << r["joints"] << ", channels " << r["channels"] << ", root " << r["root"].get<std::string>()
      << "\n"
      << "  frames " << r["frames"] << " at " << r["frame_rate"].get<double>() << " fps ("
      << r["duration_s"].get<double>() << " s)\n"
      << "  up axis " << r["up_axis"].get<std::string>() << " (alignment " << r["up_alignment"].get<double>()
      << "; rest pose " << r["rest_pose_up_axis"].get<std::string>() << ")\n"
      << "  units " << r["units"]["unit"].get<std::string>()
      << (r["units"]["detected"].get<bool>() ? " (detected)" : " (given)") << ", leg length "
      << r["body"]["leg_length_m"].get<double>() << " m, standing pelvis height "
      << r["body"]["standing_pelvis_height_m"].get<double>() << " m\n"
      << "  landmarks:";
  for (const auto& [key, value] : r["landmarks"].items()) out << " " << key << "=" << value.get<std::string>();
  out << "\n  groups:\n";
  for (const auto& [key, value] : r["groups"].items()) {
    out << "    " << key << " (" << value.size() << "):";
    for (const auto& joint : value) out << " " << joint.get<std::string>();
    out << "\n";
  }
  return out.str();
}

}  // namespace

void RegisterInspectCommand(CLI::App& app, CommandRegistry& registry) {
  struct Options {
    std::vector<std::string> files;
    bool json = false;
    std::string unit;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand("inspect",
                                         "Show what the importer finds in BVH files: body groups, "
                                         "landmarks, up axis, units, frame rate, frame count");
  command->add_option("files", options->files, "BVH files")->required()->check(CLI::ExistingFile);
  command->add_flag("--json", options->json, "Print JSON (one array of reports)");
  command->add_option("--units", options->unit, "Override unit detection")
      ->check(CLI::IsMember({"m", "cm", "mm", "in", "cmu"}));
  registry.Add(command, [options] {
    nlohmann::json all = nlohmann::json::array();
    int failures = 0;
    for (const std::string& file : options->files) {
      auto report = InspectBvhFile(file, ParseUnitOption(options->unit));
      if (!report.ok()) {
        ReportError(report.status());
        ++failures;
        continue;
      }
      if (options->json) {
        all.push_back(InspectionJson(*report));
      } else {
        std::cout << InspectionText(InspectionJson(*report));
      }
    }
    if (options->json) std::cout << all.dump(2) << "\n";
    return failures == 0 ? 0 : 1;
  });
}

}  // namespace mocap
