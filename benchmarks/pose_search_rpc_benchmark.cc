// PoseSearch over gRPC on the standard database (issue #11): per query frame, the time a client
// waits for FindSimilarPoses (one call per query frame: the middle frame of each held-out clip of
// the standard split, top 10, window 1, fast path), and the time per query frame of
// StreamSimilarPoses over whole held-out clips. Compare with the in-process figure of
// mocap_similarity_benchmark (PoseIndex::Search alone). Run through benchmarks/pose_search_rpc.sh,
// which serves a store of the standard split's database:
//   mocap_pose_search_rpc_benchmark --address HOST:PORT --key KEY --database NAME [--clips N]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "eval/standard_split.h"
#include "mocap/client.h"

namespace {

double Percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const size_t index = std::min(values.size() - 1, static_cast<size_t>(p / 100.0 * static_cast<double>(values.size())));
  return values[index];
}

double Ms(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  std::string address, key, database = "bandai-namco-2";
  int clips = 0, stream_clips = 20;
  CLI::App app{"PoseSearch RPC latency per query frame on the standard database"};
  app.add_option("--address", address, "Server address")->required();
  app.add_option("--key", key, "API key (default: $MOCAP_API_KEY)");
  app.add_option("--database", database, "Database holding the standard split's database takes");
  app.add_option("--clips", clips, "Held-out clips queried (0: all)");
  app.add_option("--stream-clips", stream_clips, "Held-out clips streamed whole");
  CLI11_PARSE(app, argc, argv);
  if (key.empty() && std::getenv("MOCAP_API_KEY")) key = std::getenv("MOCAP_API_KEY");

  auto split = mocap::eval::LoadStandardSplit();
  if (!split.ok()) {
    std::fprintf(stderr, "%s\n", split.status().ToString().c_str());
    return 77;
  }
  auto client = mocap::client::Client::Connect(address, {.api_key = key});
  if (!client.ok()) return 1;
  std::vector<mocap::v1::BvhQuery> queries;
  for (const auto& file : split->test_files) {
    if (clips > 0 && static_cast<int>(queries.size()) >= clips) break;
    auto query = mocap::client::ReadBvhQuery(file);
    if (!query.ok()) return 1;
    queries.push_back(*std::move(query));
  }
  auto request_for = [&](const mocap::v1::BvhQuery& query) {
    mocap::v1::FindSimilarPosesRequest request;
    request.add_databases(database);
    *request.mutable_bvh() = query;
    request.set_top_k(10);
    return request;
  };

  // Warm-up: the first call waits for the database's pose index.
  const auto warm = std::chrono::steady_clock::now();
  {
    auto request = request_for(queries.front());
    request.mutable_bvh()->set_first_frame(0);
    request.mutable_bvh()->set_last_frame(0);
    auto response = (*client)->FindSimilarPoses(request);
    if (!response.ok()) {
      std::fprintf(stderr, "warm-up: %s\n", response.status().ToString().c_str());
      return 1;
    }
  }
  std::fprintf(stderr, "first call (index build included): %.0f ms\n", Ms(warm));

  // One call per query frame: the middle frame of each held-out clip (frame count from the header).
  std::vector<double> unary_ms;
  for (const auto& query : queries) {
    const std::string& text = query.bvh();
    const size_t at = text.find("Frames:");
    const int frames = at == std::string::npos ? 1 : std::atoi(text.c_str() + at + 7);
    auto request = request_for(query);
    request.mutable_bvh()->set_first_frame(frames / 2);
    request.mutable_bvh()->set_last_frame(frames / 2);
    const auto start = std::chrono::steady_clock::now();
    auto response = (*client)->FindSimilarPoses(request);
    if (!response.ok() || response->results_size() != 1) {
      std::fprintf(stderr, "FindSimilarPoses: %s\n", response.status().ToString().c_str());
      return 1;
    }
    unary_ms.push_back(Ms(start));
  }

  // Whole clips streamed: time per query frame of each call.
  std::vector<double> stream_ms_per_frame;
  long stream_frames = 0;
  for (int i = 0; i < std::min<int>(stream_clips, static_cast<int>(queries.size())); ++i) {
    int frames = 0;
    const auto start = std::chrono::steady_clock::now();
    absl::Status status =
        (*client)->StreamSimilarPoses(request_for(queries[i]), [&](const mocap::v1::FindSimilarPosesResponse& part) {
          frames += part.results_size();
          return true;
        });
    if (!status.ok()) {
      std::fprintf(stderr, "StreamSimilarPoses: %s\n", status.ToString().c_str());
      return 1;
    }
    stream_ms_per_frame.push_back(Ms(start) / std::max(1, frames));
    stream_frames += frames;
  }
  std::printf("FindSimilarPoses, one query frame per call (%zu calls): p50 %.2f ms, p99 %.2f ms, max %.2f ms\n",
              unary_ms.size(), Percentile(unary_ms, 50), Percentile(unary_ms, 99), Percentile(unary_ms, 100));
  std::printf(
      "StreamSimilarPoses, whole clips (%zu calls, %ld query frames): per query frame p50 %.2f ms, p99 %.2f ms\n",
      stream_ms_per_frame.size(), stream_frames, Percentile(stream_ms_per_frame, 50),
      Percentile(stream_ms_per_frame, 99));
  return 0;
}
