#include "server/samples_reader.h"

#include <google/protobuf/io/coded_stream.h>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "server/raw_message.h"

namespace mocap {
namespace {

// Wire types and tags (protobuf's encoding): ReconstructRequest.samples is field 2 and
// WristSamples.samples field 1, both length-delimited.
constexpr std::uint32_t kVarint = 0, kFixed64 = 1, kLengthDelimited = 2, kFixed32 = 5;
constexpr std::uint32_t Tag(std::uint32_t field, std::uint32_t wire_type) { return field << 3 | wire_type; }
constexpr std::uint32_t kRequestSamplesTag = Tag(v1::ReconstructRequest::kSamplesFieldNumber, kLengthDelimited);
constexpr std::uint32_t kSampleTag = Tag(v1::WristSamples::kSamplesFieldNumber, kLengthDelimited);

}  // namespace

SamplesReader::SamplesReader(grpc::ByteBuffer& bytes) {
  bytes_.Swap(&bytes);
  if (!bytes_.Valid()) return;  // no bytes: ParseWhole
  const std::size_t size = bytes_.Length();
  stream_.emplace(&bytes_);
  if (!stream_->status().ok()) return;
  coded_.emplace(&*stream_);
  std::uint32_t length = 0;
  if (coded_->ReadTag() != kRequestSamplesTag || !coded_->ReadVarint32(&length)) return;
  // The one field must fill the message; otherwise protobuf's rules (the last of a oneof's
  // fields wins, a repeated one merges) decide, and ParseWhole applies them.
  if (static_cast<std::size_t>(coded_->CurrentPosition()) + length != size) return;
  coded_->PushLimit(static_cast<int>(length));
  samples_only_ = true;
  done_ = length == 0;
}

absl::StatusOr<v1::ReconstructRequest> SamplesReader::ParseWhole() {
  done_ = true;
  coded_.reset();  // the shape's read is over: the whole message is parsed from its first byte
  stream_.reset();
  v1::ReconstructRequest request;
  MOCAP_RETURN_IF_ERROR(FromBytes(bytes_, &request, "ReconstructRequest"));
  return request;
}

bool SamplesReader::SkipField(std::uint32_t tag) {
  std::uint64_t varint = 0;
  std::uint32_t length = 0;
  switch (tag & 7) {
    case kVarint:
      return coded_->ReadVarint64(&varint);
    case kFixed64:
      return coded_->Skip(8);
    case kLengthDelimited:
      return coded_->ReadVarint32(&length) && coded_->Skip(static_cast<int>(length));
    case kFixed32:
      return coded_->Skip(4);
    default:
      return false;  // groups (no client sends them) and invalid wire types
  }
}

absl::Status SamplesReader::Next(int max) {
  batch_.Clear();  // keeps the element objects: no allocation after the first slice
  if (!samples_only_ || done_) return absl::OkStatus();
  auto malformed = [&] {
    done_ = true;
    return absl::InvalidArgumentError(StrCat("a samples message is malformed at its sample ",
                                             samples_read_ + batch_.samples_size(),
                                             " (counting from 0): it is not a WristSamples message"));
  };
  while (batch_.samples_size() < max && coded_->BytesUntilLimit() > 0) {
    const std::uint32_t tag = coded_->ReadTag();
    if (tag == kSampleTag) {
      std::uint32_t length = 0;
      if (!coded_->ReadVarint32(&length) || length > static_cast<std::uint32_t>(coded_->BytesUntilLimit()))
        return malformed();
      const auto limit = coded_->PushLimit(static_cast<int>(length));
      if (!batch_.add_samples()->MergeFromCodedStream(&*coded_) || coded_->BytesUntilLimit() != 0) {
        batch_.mutable_samples()->RemoveLast();
        return malformed();
      }
      coded_->PopLimit(limit);
    } else if (tag == 0 || !SkipField(tag)) {
      return malformed();
    }
  }
  samples_read_ += batch_.samples_size();
  done_ = coded_->BytesUntilLimit() == 0;
  return absl::OkStatus();
}

}  // namespace mocap
