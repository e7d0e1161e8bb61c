// Client::FindSimilarPoses and Client::StreamSimilarPoses (the PoseSearch service).
#include <fstream>
#include <sstream>

#include "client/src/client_impl.h"
#include "mocap/v1/pose_search.grpc.pb.h"

namespace mocap::client {

absl::StatusOr<v1::BvhQuery> ReadBvhQuery(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return absl::NotFoundError(path.string() + ": cannot open file");
  std::stringstream text;
  text << in.rdbuf();
  v1::BvhQuery query;
  query.set_bvh(text.str());
  query.set_file_name(path.filename().string());
  return query;
}

absl::StatusOr<v1::FindSimilarPosesResponse> Client::FindSimilarPoses(const v1::FindSimilarPosesRequest& request,
                                                                      std::chrono::milliseconds deadline) {
  // A stub is a thin view of the shared channel: cheap to make per call.
  std::unique_ptr<v1::PoseSearch::Stub> stub = v1::PoseSearch::NewStub(impl_->channel);
  v1::FindSimilarPosesResponse response;
  absl::Status status = impl_->Unary(
      Client::Impl::Retry::kIdempotent,
      [&](grpc::ClientContext* c, const auto& r, auto* out) { return stub->FindSimilarPoses(c, r, out); }, request,
      &response, deadline);
  if (!status.ok()) return status;
  return response;
}

absl::Status Client::StreamSimilarPoses(const v1::FindSimilarPosesRequest& request,
                                        const std::function<bool(const v1::FindSimilarPosesResponse&)>& on_part,
                                        std::chrono::milliseconds deadline) {
  std::unique_ptr<v1::PoseSearch::Stub> stub = v1::PoseSearch::NewStub(impl_->channel);
  grpc::ClientContext context;
  impl_->Prepare(context, deadline);
  std::unique_ptr<grpc::ClientReader<v1::FindSimilarPosesResponse>> reader =
      stub->StreamSimilarPoses(&context, request);
  v1::FindSimilarPosesResponse part;
  while (reader->Read(&part)) {
    if (on_part && !on_part(part)) {
      context.TryCancel();
      break;
    }
  }
  return FromGrpc(reader->Finish());
}

}  // namespace mocap::client
