// Messages as the bytes a raw gRPC method reads and writes (Reconstruct, ReconstructTrajectory):
// parsed and serialized by the compute task that needs them, under the caller's tenant, rather
// than by gRPC on its own threads for everyone (issue #24: a 3.5 MB message held a completion
// thread ~40 ms).
#pragma once

#include <grpcpp/impl/codegen/proto_utils.h>
#include <grpcpp/support/byte_buffer.h>
#include <grpcpp/support/proto_buffer_reader.h>

#include "absl/status/status.h"
#include "motion/core/str_cat.h"

namespace mocap {

// `message` as bytes into `*bytes`.
template <typename Message>
absl::Status ToBytes(const Message& message, grpc::ByteBuffer* bytes) {
  bool own_buffer = false;
  const grpc::Status status = grpc::SerializationTraits<Message>::Serialize(message, bytes, &own_buffer);
  if (!status.ok()) return absl::InternalError(StrCat("a message could not be serialized: ", status.error_message()));
  return absl::OkStatus();
}

// `bytes` parsed into `*message` (which is cleared first); no bytes at all, which gRPC may hand
// over as no buffer, is a message with no field set. InvalidArgument naming `what` otherwise.
template <typename Message>
absl::Status FromBytes(const grpc::ByteBuffer& bytes, Message* message, const char* what) {
  message->Clear();
  if (!bytes.Valid() || bytes.Length() == 0) return absl::OkStatus();
  grpc::ByteBuffer copy(bytes);  // shares the slices: ProtoBufferReader reads a non-const buffer
  grpc::ProtoBufferReader reader(&copy);
  if (!reader.status().ok() || !message->ParseFromZeroCopyStream(&reader))
    return absl::InvalidArgumentError(StrCat("a request message could not be parsed as a ", what));
  return absl::OkStatus();
}

}  // namespace mocap
