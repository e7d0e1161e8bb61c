// Client::Impl: the channel, stubs and call helpers shared by the SDK's source files.
#pragma once

#include <chrono>
#include <memory>
#include <thread>

#include <grpcpp/grpcpp.h>

#include "client/src/status_mapping.h"
#include "mocap/client.h"
#include "mocap/v1/motion_store.grpc.pb.h"
#include "mocap/v1/reconstruction.grpc.pb.h"
#include "mocap/v1/server_status.grpc.pb.h"

namespace mocap::client {

struct Client::Impl {
  ConnectOptions options;
  std::shared_ptr<grpc::Channel> channel;
  std::unique_ptr<v1::MotionStore::Stub> store;
  std::unique_ptr<v1::ServerStatus::Stub> status;
  std::unique_ptr<v1::Reconstruction::Stub> reconstruction;

  // Adds the key; a deadline of 0 means none (streams).
  void Prepare(grpc::ClientContext& context, std::chrono::milliseconds deadline) const {
    if (!options.api_key.empty()) context.AddMetadata("authorization", "Bearer " + options.api_key);
    if (deadline.count() > 0) context.set_deadline(std::chrono::system_clock::now() + deadline);
  }
  void Prepare(grpc::ClientContext& context, bool with_deadline) const {
    Prepare(context, with_deadline ? options.deadline : std::chrono::milliseconds(0));
  }

  // Whether a call may be sent again after UNAVAILABLE. UNAVAILABLE can come after the server
  // acted (it went away before answering), so only calls that are safe to repeat are retried;
  // gRPC itself already retries calls that never left the client (transparent retry).
  enum class Retry { kIdempotent, kNever };

  // One unary call with deadline (default: options.deadline); idempotent calls are retried on
  // UNAVAILABLE up to options.max_attempts times.
  template <typename Request, typename Response, typename Method>
  absl::Status Unary(Retry retry, Method method, const Request& request, Response* response,
                     std::chrono::milliseconds deadline = std::chrono::milliseconds(0)) const {
    std::chrono::milliseconds backoff = options.retry_backoff;
    const int attempts = retry == Retry::kIdempotent ? options.max_attempts : 1;
    for (int attempt = 1;; ++attempt) {
      grpc::ClientContext context;
      Prepare(context, deadline.count() > 0 ? deadline : options.deadline);
      const grpc::Status status = method(&context, request, response);
      if (status.error_code() != grpc::StatusCode::UNAVAILABLE || attempt >= attempts) {
        return FromGrpc(status);
      }
      std::this_thread::sleep_for(backoff);
      backoff *= 2;
    }
  }
};

}  // namespace mocap::client
