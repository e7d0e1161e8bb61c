// The PoseSearch gRPC service (proto/mocap/v1/pose_search.proto) on the callback API: the
// similar-pose search of `mocapd similar` over the tenant's databases, unary and server
// streaming. Pose indices live in a per-database-version registry (built once, shared, rebuilt
// after an import); searches run on the compute pool the reconstruction sessions use, in slices
// of bounded time shared between tenants by cost (server/pose_search_call.h, server/work_pool.h).
#pragma once

#include "mocap/v1/pose_search.grpc.pb.h"
#include "server/pose_search_call.h"

namespace mocap {

class PoseSearchService final : public v1::PoseSearch::CallbackService {
 public:
  // `compute` must outlive the service; `max_cached_indexes` idle index versions are kept.
  PoseSearchService(ServiceContext& service, WorkPool& compute, int max_cached_indexes,
                    const PoseSearchLimits& limits = {})
      : state_(service, compute, max_cached_indexes, limits) {}

  grpc::ServerUnaryReactor* FindSimilarPoses(grpc::CallbackServerContext* context,
                                             const v1::FindSimilarPosesRequest* request,
                                             v1::FindSimilarPosesResponse* response) override;
  grpc::ServerWriteReactor<v1::FindSimilarPosesResponse>* StreamSimilarPoses(
      grpc::CallbackServerContext* context, const v1::FindSimilarPosesRequest* request) override;

  int index_builds() const { return state_.indexes.builds(); }

 private:
  PoseSearchState state_;
};

}  // namespace mocap
