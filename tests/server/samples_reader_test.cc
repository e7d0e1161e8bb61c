#include "server/samples_reader.h"

#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <google/protobuf/util/message_differencer.h>
#include <grpcpp/support/slice.h>
#include <gtest/gtest.h>

namespace mocap {
namespace {

using google::protobuf::util::MessageDifferencer;

v1::WristSample Sample(int i) {
  v1::WristSample sample;
  sample.set_time(i / 60.0);
  sample.mutable_left()->set_x(0.1f * i);
  sample.mutable_left()->set_y(1.2f);
  sample.mutable_right()->set_z(-0.3f * i);
  if (i % 3 == 0) sample.set_left_confidence(0.5f);
  if (i % 2 == 0) sample.mutable_right_orientation()->set_w(1.0f);
  return sample;
}

v1::ReconstructRequest SamplesRequest(int count) {
  v1::ReconstructRequest request;
  for (int i = 0; i < count; ++i) *request.mutable_samples()->add_samples() = Sample(i);
  return request;
}

// The bytes cut into slices of `slice_size`, as the transport hands a large message over.
grpc::ByteBuffer Bytes(const std::string& bytes, std::size_t slice_size = 7) {
  std::vector<grpc::Slice> slices;
  for (std::size_t at = 0; at < bytes.size(); at += slice_size) slices.emplace_back(bytes.substr(at, slice_size));
  return grpc::ByteBuffer(slices.data(), slices.size());
}

TEST(SamplesReaderTest, ASamplesMessageIsReadASliceAtATimeAsProtobufParsesIt) {
  const v1::ReconstructRequest request = SamplesRequest(10);
  grpc::ByteBuffer bytes = Bytes(request.SerializeAsString());
  SamplesReader reader(bytes);
  EXPECT_EQ(bytes.Length(), 0u);  // taken
  ASSERT_TRUE(reader.samples_only());
  std::vector<int> sizes;
  int next = 0;
  while (!reader.done()) {
    ASSERT_TRUE(reader.Next(4).ok());
    sizes.push_back(reader.batch().samples_size());
    for (const v1::WristSample& sample : reader.batch().samples())
      EXPECT_TRUE(MessageDifferencer::Equals(sample, request.samples().samples(next++)));
  }
  EXPECT_THAT(sizes, testing::ElementsAre(4, 4, 2));
  EXPECT_EQ(reader.samples_read(), 10);
  ASSERT_TRUE(reader.Next(4).ok());  // past the end: nothing more
  EXPECT_EQ(reader.batch().samples_size(), 0);
}

TEST(SamplesReaderTest, AnEmptySamplesMessageIsDoneAtOnce) {
  v1::ReconstructRequest request;
  request.mutable_samples();
  grpc::ByteBuffer bytes = Bytes(request.SerializeAsString());
  SamplesReader reader(bytes);
  EXPECT_TRUE(reader.samples_only());
  EXPECT_TRUE(reader.done());
}

TEST(SamplesReaderTest, OtherMessagesAreParsedWhole) {
  v1::ReconstructRequest config;
  config.mutable_config()->set_database("walks");
  grpc::ByteBuffer bytes = Bytes(config.SerializeAsString());
  SamplesReader reader(bytes);
  EXPECT_FALSE(reader.samples_only());
  absl::StatusOr<v1::ReconstructRequest> parsed = reader.ParseWhole();
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  EXPECT_EQ(parsed->config().database(), "walks");

  v1::ReconstructRequest finish;
  finish.mutable_finish();
  grpc::ByteBuffer finish_bytes = Bytes(finish.SerializeAsString());
  SamplesReader finish_reader(finish_bytes);
  EXPECT_FALSE(finish_reader.samples_only());
  ASSERT_TRUE(finish_reader.ParseWhole().ok());
  EXPECT_TRUE(finish_reader.ParseWhole()->has_finish());
}

TEST(SamplesReaderTest, SamplesInTwoFieldsAreLeftToProtobufsMergeRules) {
  // Two samples fields back to back: protobuf merges them (6 samples); a reader of the first
  // field alone would drop the second, so the message is not read lazily.
  const std::string bytes = SamplesRequest(2).SerializeAsString() + SamplesRequest(4).SerializeAsString();
  grpc::ByteBuffer buffer = Bytes(bytes);
  SamplesReader reader(buffer);
  EXPECT_FALSE(reader.samples_only());
  absl::StatusOr<v1::ReconstructRequest> parsed = reader.ParseWhole();
  ASSERT_TRUE(parsed.ok());
  EXPECT_EQ(parsed->samples().samples_size(), 6);
}

TEST(SamplesReaderTest, UnknownFieldsAmongTheSamplesAreSkipped) {
  // WristSamples with unknown fields of every wire type between its samples.
  const v1::ReconstructRequest request = SamplesRequest(3);
  std::string inner;
  const auto sample_bytes = [&](int i) {
    const std::string sample = request.samples().samples(i).SerializeAsString();
    return std::string{'\x0a', static_cast<char>(sample.size())} + sample;
  };
  inner += sample_bytes(0);
  inner += std::string{'\x10', '\x96', '\x01'};           // field 2, varint 150
  inner += std::string{'\x19'} + std::string(8, '\x01');  // field 3, fixed64
  inner += sample_bytes(1);
  inner += std::string{'\x22', '\x03', 'a', 'b', 'c'};    // field 4, 3 bytes
  inner += std::string{'\x2d'} + std::string(4, '\x02');  // field 5, fixed32
  inner += sample_bytes(2);
  ASSERT_LT(inner.size(), 128u);
  const std::string bytes = std::string{'\x12', static_cast<char>(inner.size())} + inner;
  grpc::ByteBuffer buffer = Bytes(bytes, 5);
  SamplesReader reader(buffer);
  ASSERT_TRUE(reader.samples_only());
  ASSERT_TRUE(reader.Next(10).ok());
  ASSERT_EQ(reader.batch().samples_size(), 3);
  for (int i = 0; i < 3; ++i)
    EXPECT_TRUE(MessageDifferencer::Equals(reader.batch().samples(i), request.samples().samples(i)));
  EXPECT_TRUE(reader.done());
}

TEST(SamplesReaderTest, AMalformedSampleStopsTheReadAndNamesTheSample) {
  const v1::ReconstructRequest request = SamplesRequest(3);
  const std::string good = request.SerializeAsString();
  // A fourth sample whose length claims more bytes than the message has.
  std::string inner = good.substr(2);  // the WristSamples payload (under 128 bytes: a 1-byte length)
  ASSERT_LT(inner.size(), 120u);
  inner += std::string{'\x0a', '\x7f', '\x09'};
  const std::string bytes = std::string{'\x12', static_cast<char>(inner.size())} + inner;
  grpc::ByteBuffer buffer = Bytes(bytes);
  SamplesReader reader(buffer);
  ASSERT_TRUE(reader.samples_only());
  const absl::Status status = reader.Next(10);
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(status.message(), testing::HasSubstr("sample 3"));
  EXPECT_EQ(reader.batch().samples_size(), 3);  // the ones before it are kept
  EXPECT_TRUE(reader.done());
}

TEST(SamplesReaderTest, AnInvalidWireTypeOrTruncatedSampleIsMalformed) {
  const std::string sample = Sample(1).SerializeAsString();
  for (const std::string& inner : {std::string{'\x0b'},                                     // a group
                                   std::string{'\x0a', static_cast<char>(sample.size())} +  // cut short
                                       sample.substr(0, sample.size() - 2)}) {
    const std::string bytes = std::string{'\x12', static_cast<char>(inner.size())} + inner;
    grpc::ByteBuffer buffer = Bytes(bytes);
    SamplesReader reader(buffer);
    ASSERT_TRUE(reader.samples_only());
    EXPECT_EQ(reader.Next(4).code(), absl::StatusCode::kInvalidArgument);
  }
}

TEST(SamplesReaderTest, NoBytesAtAllAreARequestWithNothingSet) {
  for (grpc::ByteBuffer bytes : {grpc::ByteBuffer(), Bytes("")}) {
    SamplesReader reader(bytes);
    EXPECT_FALSE(reader.samples_only());
    absl::StatusOr<v1::ReconstructRequest> parsed = reader.ParseWhole();
    ASSERT_TRUE(parsed.ok()) << parsed.status();
    EXPECT_EQ(parsed->kind_case(), v1::ReconstructRequest::KIND_NOT_SET);  // the reactor says "empty request"
  }
}

TEST(SamplesReaderTest, BytesThatAreNoRequestAreRefusedWhenParsed) {
  grpc::ByteBuffer buffer = Bytes(std::string{'\x12', '\x50', '\x0a'});  // a samples field cut short
  SamplesReader reader(buffer);
  EXPECT_FALSE(reader.samples_only());
  EXPECT_EQ(reader.ParseWhole().status().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace mocap
