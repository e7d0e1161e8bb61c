// Reconstruct streams on the raw stub that misbehave as the SDK never would: messages in an order
// or a wire form the SDK does not send.
#pragma once

#include <future>
#include <string>
#include <vector>

#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>

#include "mocap/v1/reconstruction.grpc.pb.h"
#include "server/raw_message.h"

namespace mocap::testing {

// What a raw stream was answered: its status and the frames it was sent.
struct RawOutcome {
  grpc::Status status;
  int frames = 0;
};

// Sends `requests` in order on one stream, half-closes and drains the replies. `key` empty: no
// authorization metadata at all.
inline RawOutcome SendRaw(const std::string& address, const std::string& key,
                          const std::vector<v1::ReconstructRequest>& requests) {
  auto stub = v1::Reconstruction::NewStub(grpc::CreateChannel(address, grpc::InsecureChannelCredentials()));
  grpc::ClientContext context;
  if (!key.empty()) context.AddMetadata("authorization", "Bearer " + key);
  auto stream = stub->Reconstruct(&context);
  for (const v1::ReconstructRequest& request : requests)
    if (!stream->Write(request)) break;
  stream->WritesDone();
  RawOutcome outcome;
  v1::ReconstructResponse reply;
  while (stream->Read(&reply)) outcome.frames += reply.frames().frames_size();
  outcome.status = stream->Finish();
  return outcome;
}

// One ReconstructTrajectory call whose request is `request` as bytes, whatever they are. `*response`
// is the answer parsed, when the call succeeded.
inline grpc::Status CallTrajectoryRaw(const std::string& address, const std::string& key, const std::string& request,
                                      v1::ReconstructTrajectoryResponse* response) {
  grpc::GenericStub stub(grpc::CreateChannel(address, grpc::InsecureChannelCredentials()));
  grpc::ClientContext context;
  if (!key.empty()) context.AddMetadata("authorization", "Bearer " + key);
  grpc::Slice slice(request);
  const grpc::ByteBuffer sent(&slice, 1);
  grpc::ByteBuffer received;
  std::promise<grpc::Status> done;  // the generic stub's unary call is asynchronous only
  stub.UnaryCall(&context, "/mocap.v1.Reconstruction/ReconstructTrajectory", grpc::StubOptions(), &sent, &received,
                 [&](grpc::Status status) { done.set_value(std::move(status)); });
  const grpc::Status status = done.get_future().get();
  if (status.ok() && !FromBytes(received, response, "ReconstructTrajectoryResponse").ok())
    return grpc::Status(grpc::StatusCode::INTERNAL, "the answer is no ReconstructTrajectoryResponse");
  return status;
}

inline grpc::Status SamplesBeforeConfig(const std::string& address, const std::string& key,
                                        const v1::WristSample& sample) {
  v1::ReconstructRequest samples;
  *samples.mutable_samples()->add_samples() = sample;
  return SendRaw(address, key, {samples}).status;
}

}  // namespace mocap::testing
