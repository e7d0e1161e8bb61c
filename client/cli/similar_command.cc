#include "client/cli/similar_command.h"

#include <fstream>
#include <iostream>

#include "tools/similar_json/similar_json.h"

namespace mocap::cli {
namespace {

struct SimilarCliOptions {
  std::vector<std::string> databases;
  std::string query, pose_file, frames, weights = "uniform", sampling = "resample", scaling = "bone-directions";
  int step = 1, top = 10, window = 1, suppress = 0;
  bool exact = false;
};

absl::StatusOr<v1::FindSimilarPosesRequest> MakeRequest(const SimilarCliOptions& o) {
  v1::FindSimilarPosesRequest request;
  for (const std::string& database : o.databases) request.add_databases(database);
  if (o.query.empty() == o.pose_file.empty())
    return absl::InvalidArgumentError("give --query FILE.bvh or --query-pose FILE.json");
  if (!o.pose_file.empty()) {
    std::ifstream in(o.pose_file);
    if (!in) return absl::NotFoundError(o.pose_file + ": cannot open file");
    nlohmann::json pose;
    try {
      pose = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& error) {
      return absl::InvalidArgumentError(o.pose_file + ": not JSON: " + error.what());
    }
    absl::StatusOr<v1::NamedPose> named = NamedPoseFromJson(pose);
    if (!named.ok()) return named.status();
    *request.mutable_poses()->add_poses() = std::move(*named);
  } else {
    absl::StatusOr<v1::BvhQuery> bvh = client::ReadBvhQuery(o.query);
    if (!bvh.ok()) return bvh.status();
    if (!o.frames.empty()) {
      absl::StatusOr<std::pair<int, int>> range = ParseFrameRange(o.frames);
      if (!range.ok()) return range.status();
      bvh->set_first_frame(range->first);
      bvh->set_last_frame(range->second);
    }
    bvh->set_frame_step(o.step);
    *request.mutable_bvh() = std::move(*bvh);
  }
  request.set_top_k(o.top);
  request.set_window(o.window);
  request.set_weights_preset(o.weights == "locomotion"   ? v1::GROUP_WEIGHTS_PRESET_LOCOMOTION
                             : o.weights == "upper-body" ? v1::GROUP_WEIGHTS_PRESET_UPPER_BODY
                                                         : v1::GROUP_WEIGHTS_PRESET_UNIFORM);
  request.set_suppress_within_frames(o.suppress);
  request.set_scaling(o.scaling == "per-chain"    ? v1::BODY_SCALING_PER_CHAIN
                      : o.scaling == "body-scale" ? v1::BODY_SCALING_BODY_SCALE
                                                  : v1::BODY_SCALING_BONE_DIRECTIONS);
  request.set_sampling(o.sampling == "drop" ? v1::CHAIN_SAMPLING_DROP : v1::CHAIN_SAMPLING_RESAMPLE);
  request.set_exact(o.exact);
  return request;
}

int Run(client::Client& client, const SimilarCliOptions& o, const GlobalOptions& global) {
  absl::StatusOr<v1::FindSimilarPosesRequest> request = MakeRequest(o);
  if (!request.ok()) return ReportError(request.status());
  // The streamed form: any query length, the answer collected as it comes.
  v1::FindSimilarPosesResponse response;
  absl::Status status = client.StreamSimilarPoses(*request, [&](const v1::FindSimilarPosesResponse& part) {
    AppendSimilarResults(part, &response);
    return true;
  });
  if (!status.ok()) return ReportError(status);
  const nlohmann::json results = SimilarResultsJson(o.pose_file.empty() ? o.query : "pose", response);
  if (global.json) {
    std::cout << results.dump(2) << "\n";
  } else {
    PrintSimilarText(results, std::cout);
  }
  return 0;
}

}  // namespace

void RegisterSimilar(CLI::App& app, Registry& registry) {
  auto global = registry.global;
  auto o = std::make_shared<SimilarCliOptions>();
  CLI::App* command = app.add_subcommand("similar",
                                         "Find the poses most similar to a BVH frame's in the server's "
                                         "databases, across skeletons (any rig: no joint mapping needed)");
  command->add_option("--database", o->databases, "Database(s) to search (repeat for several)")->required();
  auto* query = command->add_option("--query", o->query, "BVH file with the query pose(s)")->check(CLI::ExistingFile);
  auto* pose =
      command
          ->add_option("--query-pose", o->pose_file,
                       "JSON file with one pose as named joint positions and landmarks (see docs/similarity.md)")
          ->check(CLI::ExistingFile);
  query->excludes(pose);
  command->add_option("--frames", o->frames, "Query frames A:B (inclusive, the file's numbering); default all");
  command->add_option("--step", o->step, "Use every Nth query frame")->check(CLI::PositiveNumber);
  command->add_option("--top", o->top, "Matches per query frame")->check(CLI::Range(1, 100));
  command->add_option("--window", o->window, "Frames compared around each frame (odd)")->check(CLI::Range(1, 61));
  command->add_option("--weights", o->weights, "Group weights preset")
      ->check(CLI::IsMember({"uniform", "locomotion", "upper-body"}));
  command->add_option("--sampling", o->sampling, "Body points: resample chains or drop joints (the seed's rule)")
      ->check(CLI::IsMember({"resample", "drop"}));
  command
      ->add_option("--scaling", o->scaling,
                   "Body points: joint directions on a canonical body (posture only), each chain by its own "
                   "length, or all by the leg length (the seed's)")
      ->check(CLI::IsMember({"bone-directions", "per-chain", "body-scale"}));
  command->add_option("--suppress", o->suppress, "Drop matches within N frames of a better match in the same clip");
  command->add_flag("--exact", o->exact, "Compare with every frame (no prefilter)");
  registry.Add(command, [o, global](client::Client& client) { return Run(client, *o, *global); });
}

}  // namespace mocap::cli
