#include "mocap/client.h"

#include <fstream>
#include <thread>

#include <grpcpp/grpcpp.h>

#include "client/src/client_impl.h"
#include "client/src/status_mapping.h"

namespace mocap::client {

Client::Client(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Client::~Client() = default;

absl::StatusOr<std::unique_ptr<Client>> Client::Connect(const std::string& address, const ConnectOptions& options) {
  if (address.empty()) return absl::InvalidArgumentError("no server address");
  auto impl = std::make_unique<Impl>();
  impl->options = options;
  std::shared_ptr<grpc::ChannelCredentials> credentials = grpc::InsecureChannelCredentials();
  if (options.tls) {
    grpc::SslCredentialsOptions ssl;
    ssl.pem_root_certs = options.tls_root_certs_pem;
    credentials = grpc::SslCredentials(ssl);
  }
  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(options.max_receive_message_bytes);
  impl->channel = grpc::CreateCustomChannel(address, credentials, arguments);
  impl->store = v1::MotionStore::NewStub(impl->channel);
  impl->status = v1::ServerStatus::NewStub(impl->channel);
  impl->reconstruction = v1::Reconstruction::NewStub(impl->channel);
  return std::unique_ptr<Client>(new Client(std::move(impl)));
}

absl::StatusOr<v1::DatabaseSummary> Client::CreateDatabase(const std::string& name, double frame_rate) {
  v1::CreateDatabaseRequest request;
  request.set_name(name);
  request.set_frame_rate(frame_rate);
  v1::CreateDatabaseResponse response;
  absl::Status status = impl_->Unary(
      Client::Impl::Retry::kNever,
      [&](grpc::ClientContext* c, const auto& r, auto* out) { return impl_->store->CreateDatabase(c, r, out); },
      request, &response);
  if (!status.ok()) return status;
  return response.database();
}

absl::StatusOr<std::vector<v1::DatabaseSummary>> Client::ListDatabases() {
  v1::ListDatabasesResponse response;
  absl::Status status = impl_->Unary(
      Client::Impl::Retry::kIdempotent,
      [&](grpc::ClientContext* c, const auto& r, auto* out) { return impl_->store->ListDatabases(c, r, out); },
      v1::ListDatabasesRequest(), &response);
  if (!status.ok()) return status;
  return std::vector<v1::DatabaseSummary>(response.databases().begin(), response.databases().end());
}

absl::StatusOr<v1::DatabaseInfo> Client::DescribeDatabase(const std::string& name) {
  v1::DescribeDatabaseRequest request;
  request.set_name(name);
  v1::DescribeDatabaseResponse response;
  absl::Status status = impl_->Unary(
      Client::Impl::Retry::kIdempotent,
      [&](grpc::ClientContext* c, const auto& r, auto* out) { return impl_->store->DescribeDatabase(c, r, out); },
      request, &response);
  if (!status.ok()) return status;
  return response.info();
}

absl::Status Client::DeleteDatabase(const std::string& name) {
  v1::DeleteDatabaseRequest request;
  request.set_name(name);
  v1::DeleteDatabaseResponse response;
  return impl_->Unary(
      Client::Impl::Retry::kNever,
      [&](grpc::ClientContext* c, const auto& r, auto* out) { return impl_->store->DeleteDatabase(c, r, out); },
      request, &response);
}

absl::StatusOr<v1::ImportBvhResponse> Client::ImportFiles(const std::string& database,
                                                          const std::vector<std::filesystem::path>& files,
                                                          const ImportOptions& options,
                                                          const ImportProgressCallback& progress) {
  if (options.chunk_bytes == 0) return absl::InvalidArgumentError("chunk size must be positive");
  ImportProgress done{.files_total = static_cast<int>(files.size())};
  for (const auto& file : files) {
    std::error_code error;
    const auto size = std::filesystem::file_size(file, error);
    if (error) return absl::NotFoundError(file.string() + ": " + error.message());
    done.bytes_total += static_cast<std::int64_t>(size);
  }
  grpc::ClientContext context;
  impl_->Prepare(context, false);
  v1::ImportBvhResponse response;
  std::unique_ptr<grpc::ClientWriter<v1::ImportBvhRequest>> writer = impl_->store->ImportBvh(&context, &response);

  // A failed write means the server has ended the call; Finish says why.
  bool open = true;
  v1::ImportBvhRequest message;
  v1::ImportStart* start = message.mutable_start();
  start->set_database(database);
  start->set_frame_rate(options.frame_rate);
  start->set_source_unit(options.source_unit);
  start->set_batch_size(options.batch_size);
  start->set_keep_going(options.keep_going);
  start->set_retarget_other_rigs(options.retarget_other_rigs);
  open = writer->Write(message);
  std::string buffer(options.chunk_bytes, '\0');
  for (size_t i = 0; open && i < files.size(); ++i) {
    std::ifstream in(files[i], std::ios::binary);
    if (!in) {
      context.TryCancel();
      writer->Finish();
      return absl::NotFoundError(files[i].string() + ": cannot open file");
    }
    done.current_file = files[i].filename().string();
    do {
      in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      const std::streamsize got = in.gcount();
      message.Clear();
      v1::FileChunk* chunk = message.mutable_chunk();
      chunk->set_file_name(done.current_file);
      chunk->set_data(buffer.data(), static_cast<size_t>(got));
      chunk->set_end_of_file(in.peek() == std::char_traits<char>::eof());
      open = writer->Write(message);
      done.bytes_sent += got;
      if (chunk->end_of_file()) ++done.files_sent;
      if (progress) progress(done);
    } while (open && done.files_sent == static_cast<int>(i));
  }
  if (open) {
    message.Clear();
    message.mutable_end();
    open = writer->Write(message);
  }
  if (open) writer->WritesDone();
  const grpc::Status status = writer->Finish();
  if (!status.ok()) return FromGrpc(status);
  return response;
}

absl::StatusOr<std::vector<v1::Clip>> Client::ListClips(const std::string& database) {
  v1::ListClipsRequest request;
  request.set_database(database);
  v1::ListClipsResponse response;
  absl::Status status = impl_->Unary(
      Client::Impl::Retry::kIdempotent,
      [&](grpc::ClientContext* c, const auto& r, auto* out) { return impl_->store->ListClips(c, r, out); }, request,
      &response);
  if (!status.ok()) return status;
  return std::vector<v1::Clip>(response.clips().begin(), response.clips().end());
}

absl::StatusOr<std::string> Client::ExportClip(const std::string& database, std::int64_t clip_id) {
  v1::ExportClipRequest request;
  request.set_database(database);
  request.set_clip_id(clip_id);
  grpc::ClientContext context;
  impl_->Prepare(context, true);
  std::unique_ptr<grpc::ClientReader<v1::ExportClipResponse>> reader = impl_->store->ExportClip(&context, request);
  std::string text;
  v1::ExportClipResponse chunk;
  while (reader->Read(&chunk)) text += chunk.data();
  const grpc::Status status = reader->Finish();
  if (!status.ok()) return FromGrpc(status);
  return text;
}

absl::Status Client::DeleteClip(const std::string& database, std::int64_t clip_id) {
  v1::DeleteClipRequest request;
  request.set_database(database);
  request.set_clip_id(clip_id);
  v1::DeleteClipResponse response;
  return impl_->Unary(
      Client::Impl::Retry::kNever,
      [&](grpc::ClientContext* c, const auto& r, auto* out) { return impl_->store->DeleteClip(c, r, out); }, request,
      &response);
}

absl::StatusOr<std::string> Client::GetMetrics() {
  v1::GetMetricsResponse response;
  absl::Status status = impl_->Unary(
      Client::Impl::Retry::kIdempotent,
      [&](grpc::ClientContext* c, const auto& r, auto* out) { return impl_->status->GetMetrics(c, r, out); },
      v1::GetMetricsRequest(), &response);
  if (!status.ok()) return status;
  return response.text();
}

}  // namespace mocap::client
