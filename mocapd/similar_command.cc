// `mocapd similar`: cross-skeleton similar-pose search on a store file (docs/method.md B; server/store_pose_search.h).
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "mocapd/commands.h"
#include "motion/core/str_cat.h"
#include "server/store_pose_search.h"
#include "tools/similar_json/similar_json.h"

namespace mocap {
void RegisterSimilarCommand(CLI::App& app, CommandRegistry& registry) {
  struct Options {
    SimilarOptions similar;
    std::string store, query, pose_file, frames, weights = "uniform", sampling = "resample",
                                                 scaling = "bone-directions";
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand("similar",
                                         "Find the poses most similar to a BVH frame's, across skeletons "
                                         "(any rig: no joint mapping needed)");
  command->add_option("--store", options->store, "Motion store file")->required();
  command->add_option("--database", options->similar.databases, "Database(s) to search (repeat for several)")
      ->required();
  command->add_option("--tenant", options->similar.tenant, "Tenant owning the databases (default: 'default')");
  auto* query =
      command->add_option("--query", options->query, "BVH file with the query pose(s)")->check(CLI::ExistingFile);
  auto* pose =
      command
          ->add_option("--query-pose", options->pose_file,
                       "JSON file with one pose as named joint positions and landmarks (see docs/similarity.md)")
          ->check(CLI::ExistingFile);
  query->excludes(pose);
  command->add_option("--frames", options->frames, "Query frames A:B (inclusive, the file's numbering); default all");
  command->add_option("--step", options->similar.frame_step, "Use every Nth query frame")->check(CLI::PositiveNumber);
  command->add_option("--top", options->similar.search.top_k, "Matches per query frame")->check(CLI::Range(1, 1000));
  command->add_option("--window", options->similar.search.window, "Frames compared around each frame (odd)")
      ->check(CLI::Range(1, 61));
  command->add_option("--weights", options->weights, "Group weights preset")
      ->check(CLI::IsMember({"uniform", "locomotion", "upper-body"}));
  command->add_option("--sampling", options->sampling, "Body points: resample chains or drop joints (the seed's rule)")
      ->check(CLI::IsMember({"resample", "drop"}));
  command
      ->add_option("--scaling", options->scaling,
                   "Body points: joint directions on a canonical body (posture only), each chain by its own "
                   "length, or all by the leg length (the seed's)")
      ->check(CLI::IsMember({"bone-directions", "per-chain", "body-scale"}));
  command->add_option("--suppress", options->similar.search.suppress_within_frames,
                      "Drop matches within N frames of a better match in the same clip");
  command->add_flag("--exact", options->similar.search.exact, "Compare with every frame (no prefilter)");
  command->add_flag("--json", options->json, "Print JSON");
  registry.Add(command, [options] {
    SimilarOptions& similar = options->similar;
    similar.store = options->store;
    similar.query = options->query;
    if (options->query.empty() && options->pose_file.empty()) {
      return ReportError(absl::InvalidArgumentError("give --query FILE.bvh or --query-pose FILE.json"));
    }
    if (!options->pose_file.empty()) {
      std::ifstream in(options->pose_file);
      nlohmann::json pose;
      try {
        pose = nlohmann::json::parse(in);
      } catch (const nlohmann::json::exception& error) {
        return ReportError(absl::InvalidArgumentError(StrCat(options->pose_file, ": not JSON: ", error.what())));
      }
      absl::StatusOr<v1::NamedPose> named = NamedPoseFromJson(pose);
      if (!named.ok()) return ReportError(named.status());
      similar.pose = std::move(*named);
    }
    if (!options->frames.empty()) {
      auto range = ParseFrameRange(options->frames);
      if (!range.ok()) return ReportError(range.status());
      similar.first_frame = range->first;
      similar.last_frame = range->second;
    }
    similar.search.weights = options->weights == "locomotion"   ? GroupWeights::Locomotion()
                             : options->weights == "upper-body" ? GroupWeights::UpperBody()
                                                                : GroupWeights::Uniform();
    similar.points.sampling =
        options->sampling == "drop" ? PointSampling::kDropNearestEndEffector : PointSampling::kResampleChains;
    similar.points.scaling = ParseChainScaling(options->scaling).value_or(ChainScaling::kBoneDirections);
    auto response = FindSimilarPosesInStore(similar);
    if (!response.ok()) return ReportError(response.status());
    const nlohmann::json result = SimilarResultsJson(similar.pose ? "pose" : options->query, *response);
    if (options->json) {
      std::cout << result.dump(2) << "\n";
      return 0;
    }
    PrintSimilarText(result, std::cout);
    return 0;
  });
}

}  // namespace mocap
