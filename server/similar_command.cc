#include "server/similar_command.h"

#include <cmath>

#include "motion/bvh/bvh_reader.h"
#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/skeleton/forward_kinematics.h"
#include "storage/motion_store.h"
#include "storage/tenant_directory.h"

namespace mocap {
namespace {

struct LoadedDatabase {
  DatabaseSummary summary;
  std::vector<ClipSummary> clips;
  PoseIndex index;
};

absl::StatusOr<LoadedDatabase> LoadDatabase(MotionStore& store, TenantId tenant, const std::string& name,
                                            const BodyPointOptions& points) {
  LoadedDatabase loaded;
  MOCAP_ASSIGN_OR_RETURN(loaded.summary, store.FindDatabase(name, tenant));
  MOCAP_ASSIGN_OR_RETURN(RigModel rig, store.LoadRig(loaded.summary.id));
  MOCAP_ASSIGN_OR_RETURN(loaded.clips, store.ListClips(loaded.summary.id));
  loaded.index = PoseIndex(points);
  const BodyChains chains = MakeBodyChains(rig.skeleton, rig.topology);
  for (const ClipSummary& clip : loaded.clips) {
    MOCAP_ASSIGN_OR_RETURN(StoredClip stored, store.LoadClip(clip.id, rig));
    ClipPoints clip_points = MakeClipPoints(ForwardKinematics(stored.skeleton, stored.motion), chains, points);
    clip_points.name = clip.source_name;
    clip_points.clip_id = clip.id;
    loaded.index.AddClip(std::move(clip_points));
  }
  MOCAP_RETURN_IF_ERROR(loaded.index.Build());
  return loaded;
}

nlohmann::json GroupDistances(const PoseDistance& distance) {
  nlohmann::json out = nlohmann::json::object();
  for (int g = 0; g < kNumBodyGroups; ++g) out[std::string(BodyGroupName(static_cast<BodyGroup>(g)))] = distance.per_group[g];
  return out;
}

// Matches of all databases merged by distance, as JSON.
nlohmann::json MatchesJson(const std::vector<LoadedDatabase>& databases, std::vector<std::pair<PoseMatch, int>> merged,
                           int top_k) {
  std::sort(merged.begin(), merged.end(),
            [](const auto& a, const auto& b) { return a.first.distance.total < b.first.distance.total; });
  if (static_cast<int>(merged.size()) > top_k) merged.resize(top_k);
  nlohmann::json matches = nlohmann::json::array();
  for (const auto& [match, d] : merged) {
    const LoadedDatabase& database = databases[d];
    const ClipSummary& clip = database.clips[match.clip];
    const double source_frame = match.frame / database.summary.frame_rate * clip.source_frame_rate;
    matches.push_back({{"database", database.summary.name},
                       {"clip_id", clip.id},
                       {"file", clip.source_name},
                       {"frame", static_cast<int>(std::lround(source_frame))},
                       {"database_frame", match.frame},
                       {"distance", match.distance.total},
                       {"group_distances", GroupDistances(match.distance)},
                       {"alignment", {{"yaw_degrees", match.distance.alignment.yaw * 180.0 / M_PI},
                                      {"x_body_scales", match.distance.alignment.x},
                                      {"z_body_scales", match.distance.alignment.z}}}});
  }
  return matches;
}

// A single pose given as named joint positions (see SimilarOptions::pose).
absl::StatusOr<ClipPoints> PoseQueryPoints(const nlohmann::json& pose, const BodyPointOptions& points) {
  try {
    std::vector<Joint> joints;
    std::vector<Eigen::Vector3f> positions;
    for (const auto& entry : pose.at("joints")) {
      Joint joint;
      joint.name = entry.at("name").get<std::string>();
      if (entry.contains("parent") && !entry.at("parent").is_null()) {
        const std::string parent = entry.at("parent").get<std::string>();
        for (size_t i = 0; i < joints.size(); ++i) {
          if (joints[i].name == parent) joint.parent = static_cast<int>(i);
        }
        if (joint.parent < 0) {
          return absl::InvalidArgumentError(StrCat("pose joint '", joint.name, "': parent '", parent,
                                                   "' must be listed before it"));
        }
      }
      const auto& p = entry.at("position");
      positions.emplace_back(p.at(0).get<float>(), p.at(1).get<float>(), p.at(2).get<float>());
      if (!positions.back().allFinite()) return absl::InvalidArgumentError(StrCat("pose joint '", joint.name, "' is not finite"));
      joints.push_back(std::move(joint));
    }
    Skeleton skeleton(std::move(joints));
    if (absl::Status status = skeleton.Validate(); !status.ok()) {
      return absl::InvalidArgumentError(StrCat("pose: ", status.message()));
    }
    const std::string up = pose.value("up", std::string("+Y"));
    if (up.size() != 2 || (up[0] != '+' && up[0] != '-') || up[1] < 'X' || up[1] > 'Z') {
      return absl::InvalidArgumentError("pose 'up' must be one of +X, -X, +Y, -Y, +Z, -Z");
    }
    Eigen::Vector3f up_vector = Eigen::Vector3f::Zero();
    up_vector[up[1] - 'X'] = up[0] == '+' ? 1.0f : -1.0f;
    const Eigen::Quaternionf to_y_up = Eigen::Quaternionf::FromTwoVectors(up_vector, Eigen::Vector3f::UnitY());
    GlobalPoses poses;
    for (Eigen::ArrayXXf* a : {&poses.px, &poses.py, &poses.pz, &poses.qw, &poses.qx, &poses.qy, &poses.qz}) {
      a->setZero(1, skeleton.num_joints());
    }
    poses.qw.setOnes();
    for (int j = 0; j < skeleton.num_joints(); ++j) {
      const Eigen::Vector3f p = to_y_up * positions[j];  // the unit does not matter: points are in leg lengths
      poses.px(0, j) = p.x();
      poses.py(0, j) = p.y();
      poses.pz(0, j) = p.z();
    }
    const auto& named = pose.at("landmarks");
    auto landmark = [&](const char* key) -> absl::StatusOr<int> {
      const int joint = skeleton.Find(named.at(key).get<std::string>());
      if (joint < 0) return absl::InvalidArgumentError(StrCat("pose landmark '", key, "' names no joint"));
      return joint;
    };
    BodyLandmarks landmarks;
    MOCAP_ASSIGN_OR_RETURN(landmarks.pelvis, landmark("pelvis"));
    MOCAP_ASSIGN_OR_RETURN(landmarks.head, landmark("head"));
    MOCAP_ASSIGN_OR_RETURN(landmarks.left_wrist, landmark("left_wrist"));
    MOCAP_ASSIGN_OR_RETURN(landmarks.right_wrist, landmark("right_wrist"));
    MOCAP_ASSIGN_OR_RETURN(landmarks.left_ankle, landmark("left_ankle"));
    MOCAP_ASSIGN_OR_RETURN(landmarks.right_ankle, landmark("right_ankle"));
    MOCAP_ASSIGN_OR_RETURN(BodyChains chains, ChainsFromLandmarks(skeleton, landmarks));
    return MakeClipPoints(poses, chains, points);
  } catch (const nlohmann::json::exception& error) {
    return absl::InvalidArgumentError(StrCat("pose JSON: ", error.what()));
  }
}

}  // namespace

absl::StatusOr<nlohmann::json> RunSimilar(const SimilarOptions& options) {
  if (options.databases.empty()) return absl::InvalidArgumentError("name at least one database");
  if (options.frame_step < 1) return absl::InvalidArgumentError("frame step must be at least 1");
  MOCAP_ASSIGN_OR_RETURN(std::unique_ptr<MotionStore> store,
                         MotionStore::Open(options.store, StoreOpenOptions{.create_if_missing = false}));
  MOCAP_ASSIGN_OR_RETURN(const TenantId tenant, ResolveTenant(*store, options.tenant));
  std::optional<ClipPoints> pose_points;
  if (options.pose) {
    if (options.search.window != 1) return absl::InvalidArgumentError("a single pose has no window: use --window 1");
    MOCAP_ASSIGN_OR_RETURN(pose_points, PoseQueryPoints(*options.pose, options.points));
  }
  BvhClip query_clip;
  if (!pose_points) {
    MOCAP_ASSIGN_OR_RETURN(query_clip, ReadBvhFile(options.query));
  }

  std::vector<LoadedDatabase> databases;
  for (const std::string& name : options.databases) {
    MOCAP_ASSIGN_OR_RETURN(LoadedDatabase loaded, LoadDatabase(*store, tenant, name, options.points));
    databases.push_back(std::move(loaded));
  }
  if (pose_points) {
    std::vector<std::pair<PoseMatch, int>> merged;
    for (size_t d = 0; d < databases.size(); ++d) {
      MOCAP_ASSIGN_OR_RETURN(std::vector<PoseMatch> matches, databases[d].index.Search(*pose_points, 0, options.search));
      for (const PoseMatch& match : matches) merged.emplace_back(match, static_cast<int>(d));
    }
    return nlohmann::json{{"query", "pose"}, {"window", 1}, {"exact", options.search.exact},
                          {"results", nlohmann::json::array({{{"query_frame", 0}, {"matches", MatchesJson(databases, merged, options.search.top_k)}}})}};
  }
  // The query on its own rig, resampled to each database's rate (databases may differ).
  absl::StatusOr<RigModel> query_rig = BuildRigModel(query_clip, {});
  if (!query_rig.ok()) {
    return absl::Status(query_rig.status().code(), StrCat(options.query.string(), ": ", query_rig.status().message()));
  }
  const int file_frames = query_clip.num_frames();
  const int first = options.first_frame.value_or(0);
  const int last = options.last_frame.value_or(file_frames - 1);
  if (first < 0 || last >= file_frames || first > last) {
    return absl::InvalidArgumentError(StrCat("query frames ", first, ":", last, " are outside the file's 0:", file_frames - 1));
  }

  nlohmann::json results = nlohmann::json::array();
  std::vector<ClipPoints> query_points;  // per database
  for (const LoadedDatabase& database : databases) {
    MOCAP_ASSIGN_OR_RETURN(PreparedClip prepared, PrepareClip(query_clip, *query_rig, {.frame_rate = database.summary.frame_rate}));
    query_points.push_back(MakeClipPoints(ForwardKinematics(prepared.skeleton, prepared.motion),
                                          MakeBodyChains(query_rig->skeleton, query_rig->topology), options.points));
  }
  for (int file_frame = first; file_frame <= last; file_frame += options.frame_step) {
    std::vector<std::pair<PoseMatch, int>> merged;  // match, database
    for (size_t d = 0; d < databases.size(); ++d) {
      const double rate = databases[d].summary.frame_rate;
      const int frame = std::min<int>(static_cast<int>(std::lround(file_frame * query_clip.frame_time * rate)),
                                      static_cast<int>(query_points[d].points.rows()) - 1);
      MOCAP_ASSIGN_OR_RETURN(std::vector<PoseMatch> matches, databases[d].index.Search(query_points[d], frame, options.search));
      for (const PoseMatch& match : matches) merged.emplace_back(match, static_cast<int>(d));
    }
    results.push_back({{"query_frame", file_frame}, {"matches", MatchesJson(databases, merged, options.search.top_k)}});
  }
  return nlohmann::json{{"query", options.query.string()}, {"window", options.search.window},
                        {"exact", options.search.exact}, {"results", results}};
}

}  // namespace mocap
