#include "server/pose_search_service.h"

#include "server/owned_reactor.h"

namespace mocap {
namespace {

// FindSimilarPoses: every query frame's matches in one response.
class FindReactor final : public OwnedReactor<grpc::ServerUnaryReactor>, private PoseSearchCall {
 public:
  FindReactor(PoseSearchState& state, grpc::CallbackServerContext* context, const v1::FindSimilarPosesRequest& request,
              v1::FindSimilarPosesResponse* response)
      : PoseSearchCall(state, context, "FindSimilarPoses", request, /*streaming=*/false), response_(response) {
    Start();
  }
  void OnCancel() override { Cancel(); }

 private:
  void Searchable() override {
    MutexLock lock(&mutex_);
    if (absl::Status status = SearchSlice(response_); !status.ok()) return Complete(status);
    if (done()) return Complete(absl::OkStatus());
    Post([this] { Searchable(); });
  }
  void Complete(absl::Status status) override {
    if (!status.ok()) response_->Clear();
    Finish(End(status));
  }
  v1::FindSimilarPosesResponse* response_;
};

// StreamSimilarPoses: one response per slice that finished query frames, one write in flight;
// the next slice is searched when the previous response has been written (a client that stops
// reading pauses the search once the transport holds what its flow-control window allows).
class StreamReactor final : public OwnedReactor<grpc::ServerWriteReactor<v1::FindSimilarPosesResponse>>,
                            private PoseSearchCall {
 public:
  StreamReactor(PoseSearchState& state, grpc::CallbackServerContext* context,
                const v1::FindSimilarPosesRequest& request)
      : PoseSearchCall(state, context, "StreamSimilarPoses", request, /*streaming=*/true) {
    Start();
  }
  void OnCancel() override { Cancel(); }
  void OnWriteDone(bool ok) override {
    MutexLock lock(&mutex_);
    if (!ok) return Complete(absl::CancelledError("the client stopped reading"));
    if (done()) return Complete(absl::OkStatus());
    Post([this] { Searchable(); });
  }

 private:
  void Searchable() override {
    MutexLock lock(&mutex_);
    part_.Clear();
    if (absl::Status status = SearchSlice(&part_); !status.ok()) return Complete(status);
    if (part_.results_size() > 0) return StartWrite(&part_);
    // The slice ended inside a frame's search: the next one goes on (nothing to write yet).
    if (done()) return Complete(absl::OkStatus());
    Post([this] { Searchable(); });
  }
  void Complete(absl::Status status) override { Finish(End(status)); }
  v1::FindSimilarPosesResponse part_;
};

}  // namespace

grpc::ServerUnaryReactor* PoseSearchService::FindSimilarPoses(grpc::CallbackServerContext* context,
                                                              const v1::FindSimilarPosesRequest* request,
                                                              v1::FindSimilarPosesResponse* response) {
  return new FindReactor(state_, context, *request, response);
}

grpc::ServerWriteReactor<v1::FindSimilarPosesResponse>* PoseSearchService::StreamSimilarPoses(
    grpc::CallbackServerContext* context, const v1::FindSimilarPosesRequest* request) {
  return new StreamReactor(state_, context, *request);
}

}  // namespace mocap
