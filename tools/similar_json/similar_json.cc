#include "tools/similar_json/similar_json.h"

#include <stdexcept>

namespace mocap {
namespace {

nlohmann::json GroupsJson(const v1::GroupValues& values) {
  return {{"spine", values.spine()},         {"head", values.head()},         {"left_arm", values.left_arm()},
          {"right_arm", values.right_arm()}, {"left_leg", values.left_leg()}, {"right_leg", values.right_leg()}};
}

}  // namespace

nlohmann::json SimilarResultsJson(const std::string& query, const v1::FindSimilarPosesResponse& response) {
  nlohmann::json results = nlohmann::json::array();
  for (const v1::QueryFrameMatches& frame : response.results()) {
    nlohmann::json matches = nlohmann::json::array();
    for (const v1::PoseMatch& match : frame.matches()) {
      matches.push_back({{"database", match.database()},
                         {"clip_id", match.clip_id()},
                         {"file", match.file_name()},
                         {"frame", match.frame()},
                         {"database_frame", match.database_frame()},
                         {"distance", match.distance()},
                         {"group_distances", GroupsJson(match.group_distances())},
                         {"alignment",
                          {{"yaw_degrees", match.alignment().yaw_degrees()},
                           {"x_body_scales", match.alignment().x_body_scales()},
                           {"z_body_scales", match.alignment().z_body_scales()}}}});
    }
    nlohmann::json result = {{"query_frame", frame.query_frame()}, {"matches", std::move(matches)}};
    if (frame.has_novelty()) {
      result["novelty"] = frame.novelty();
      result["no_similar_pose"] = frame.no_similar_pose();
    }
    results.push_back(std::move(result));
  }
  return {
      {"query", query}, {"window", response.window()}, {"exact", response.exact()}, {"results", std::move(results)}};
}

absl::StatusOr<std::pair<int, int>> ParseFrameRange(const std::string& text) {
  const size_t colon = text.find(':');
  try {
    size_t used = 0;
    const int first = std::stoi(text.substr(0, colon), &used);
    if (used != (colon == std::string::npos ? text.size() : colon)) throw std::invalid_argument(text);
    if (colon == std::string::npos) return std::pair{first, first};
    const std::string rest = text.substr(colon + 1);
    const int last = std::stoi(rest, &used);
    if (used != rest.size()) throw std::invalid_argument(text);
    return std::pair{first, last};
  } catch (const std::exception&) {
    return absl::InvalidArgumentError("--frames takes A:B or A");
  }
}

void PrintSimilarText(const nlohmann::json& results, std::ostream& out) {
  for (const auto& entry : results["results"]) {
    out << "query frame " << entry["query_frame"];
    if (entry.contains("novelty")) {
      out << " (novelty " << entry["novelty"].get<double>()
          << (entry["no_similar_pose"].get<bool>() ? ": no similar pose here, the nearest only" : "") << ")";
    }
    out << ":\n";
    for (const auto& match : entry["matches"]) {
      out << "  " << match["distance"].get<double>() << "  " << match["database"].get<std::string>() << "/"
          << match["file"].get<std::string>() << " frame " << match["frame"] << "\n";
    }
  }
}

absl::StatusOr<v1::NamedPose> NamedPoseFromJson(const nlohmann::json& pose) {
  try {
    v1::NamedPose out;
    for (const auto& entry : pose.at("joints")) {
      v1::NamedJoint* joint = out.add_joints();
      joint->set_name(entry.at("name").get<std::string>());
      if (entry.contains("parent") && !entry.at("parent").is_null())
        joint->set_parent(entry.at("parent").get<std::string>());
      const auto& p = entry.at("position");
      joint->mutable_position()->set_x(p.at(0).get<float>());
      joint->mutable_position()->set_y(p.at(1).get<float>());
      joint->mutable_position()->set_z(p.at(2).get<float>());
    }
    out.set_up(pose.value("up", std::string("+Y")));
    const auto& named = pose.at("landmarks");
    v1::NamedLandmarks* landmarks = out.mutable_landmarks();
    landmarks->set_pelvis(named.at("pelvis").get<std::string>());
    landmarks->set_head(named.at("head").get<std::string>());
    landmarks->set_left_wrist(named.at("left_wrist").get<std::string>());
    landmarks->set_right_wrist(named.at("right_wrist").get<std::string>());
    landmarks->set_left_ankle(named.at("left_ankle").get<std::string>());
    landmarks->set_right_ankle(named.at("right_ankle").get<std::string>());
    // Optional: where the limbs bend and their upper bones start.
    for (auto [key, field] : {std::pair{"left_elbow", &v1::NamedLandmarks::mutable_left_elbow},
                              std::pair{"right_elbow", &v1::NamedLandmarks::mutable_right_elbow},
                              std::pair{"left_knee", &v1::NamedLandmarks::mutable_left_knee},
                              std::pair{"right_knee", &v1::NamedLandmarks::mutable_right_knee},
                              std::pair{"left_shoulder", &v1::NamedLandmarks::mutable_left_shoulder},
                              std::pair{"right_shoulder", &v1::NamedLandmarks::mutable_right_shoulder},
                              std::pair{"left_hip", &v1::NamedLandmarks::mutable_left_hip},
                              std::pair{"right_hip", &v1::NamedLandmarks::mutable_right_hip}}) {
      if (named.contains(key)) *(landmarks->*field)() = named.at(key).get<std::string>();
    }
    return out;
  } catch (const nlohmann::json::exception& error) {
    return absl::InvalidArgumentError(std::string("pose JSON: ") + error.what());
  }
}

void AppendSimilarResults(const v1::FindSimilarPosesResponse& part, v1::FindSimilarPosesResponse* into) {
  into->set_window(part.window());
  into->set_exact(part.exact());
  for (const v1::QueryFrameMatches& frame : part.results()) *into->add_results() = frame;
}

}  // namespace mocap
