// A Reconstruct stream on the raw stub that misbehaves as the SDK never would: it sends one
// samples message first (no config), half-closes, drains the replies and returns the status.
#pragma once

#include <string>

#include <grpcpp/grpcpp.h>

#include "mocap/v1/reconstruction.grpc.pb.h"

namespace mocap::testing {

// `key` empty: no authorization metadata at all.
inline grpc::Status SamplesBeforeConfig(const std::string& address, const std::string& key,
                                        const v1::WristSample& sample) {
  auto stub = v1::Reconstruction::NewStub(grpc::CreateChannel(address, grpc::InsecureChannelCredentials()));
  grpc::ClientContext context;
  if (!key.empty()) context.AddMetadata("authorization", "Bearer " + key);
  auto stream = stub->Reconstruct(&context);
  v1::ReconstructRequest samples;
  *samples.mutable_samples()->add_samples() = sample;
  stream->Write(samples);
  stream->WritesDone();
  v1::ReconstructResponse reply;
  while (stream->Read(&reply)) {
  }
  return stream->Finish();
}

}  // namespace mocap::testing
