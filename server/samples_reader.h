// A Reconstruct request read as bytes, its samples parsed a few at a time (issue #24: fair shares
// by cost). Typed, gRPC parses a message on its own completion-queue thread before the reactor
// sees it: an 80,000-sample message (3.5 MB) held such a thread for ~40 ms, and every tenant's
// stream shares those threads (perf, stop 70: beside a flood of such messages the victim's p99
// was 9× its figure alone, the server's own reply within 11 ms). Read raw, a samples message is
// only checked for its shape where it arrives (a tag and a length); its samples are parsed on
// the compute pool a slice at a time under the sending tenant's share, into one reused batch, and
// its bytes are freed in one piece.
#pragma once

#include <cstdint>
#include <optional>

#include <absl/status/status.h>
#include <absl/status/statusor.h>
#include <grpcpp/support/byte_buffer.h>
#include <grpcpp/support/proto_buffer_reader.h>

#include "mocap/v1/reconstruction.pb.h"

namespace mocap {

class SamplesReader {
 public:
  // Takes the request's bytes (`bytes` is left empty) and looks at its shape.
  explicit SamplesReader(grpc::ByteBuffer& bytes);
  SamplesReader(const SamplesReader&) = delete;
  SamplesReader& operator=(const SamplesReader&) = delete;

  // The request is one `samples` field, the form every client sends: Next reads its samples.
  // Anything else (a config, a finish, fields repeated or unknown) is parsed whole by ParseWhole.
  bool samples_only() const { return samples_only_; }

  // The whole request, with protobuf's own parser (its rules for repeated and unknown fields).
  absl::StatusOr<v1::ReconstructRequest> ParseWhole();

  // Parses up to `max` more samples into batch() (cleared first: its elements are reused). An
  // error names the first sample it could not read; nothing after it is read.
  absl::Status Next(int max);
  const v1::WristSamples& batch() const { return batch_; }
  // Every sample has been read (or the bytes were malformed).
  bool done() const { return done_; }
  std::int64_t samples_read() const { return samples_read_; }

 private:
  // Skips one field of `tag` that is not a sample (protobuf ignores such fields).
  bool SkipField(std::uint32_t tag);

  grpc::ByteBuffer bytes_;
  // Declared after bytes_ and in this order: each is destroyed before what it reads.
  std::optional<grpc::ProtoBufferReader> stream_;
  std::optional<google::protobuf::io::CodedInputStream> coded_;
  bool samples_only_ = false;
  bool done_ = false;
  std::int64_t samples_read_ = 0;
  v1::WristSamples batch_;
};

}  // namespace mocap
