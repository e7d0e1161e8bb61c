// Client::OpenReconstruction (the Reconstruct stream) and Client::ReconstructTrajectory.
#include <mutex>

#include "client/src/client_impl.h"

namespace mocap::client {
namespace {

class Stream final : public ReconstructionStream {
 public:
  // Sends the config and waits for `started`.
  absl::Status Open(const Client::Impl& impl, const v1::SessionConfig& config) {
    impl.Prepare(context_, std::chrono::milliseconds(0));  // a live session has no deadline
    stream_ = impl.reconstruction->Reconstruct(&context_);
    v1::ReconstructRequest request;
    *request.mutable_config() = config;
    v1::ReconstructResponse reply;
    if (stream_->Write(request) && stream_->Read(&reply)) {
      if (reply.has_started()) {
        started_ = std::move(*reply.mutable_started());
        return absl::OkStatus();
      }
      context_.TryCancel();
      stream_->Finish();
      finished_ = true;
      return absl::InternalError("the server's first reply was not `started`");
    }
    stream_->WritesDone();
    finished_ = true;
    return FromGrpc(stream_->Finish());  // the server's reason
  }

  ~Stream() override {
    if (!finished_) {
      context_.TryCancel();
      stream_->Finish();
    }
  }

  const v1::SessionStarted& started() const override { return started_; }

  absl::Status Write(const std::vector<v1::WristSample>& samples) override {
    std::lock_guard lock(write_mutex_);
    if (input_closed_) return absl::FailedPreconditionError("the input is closed");
    v1::ReconstructRequest request;
    request.mutable_samples()->mutable_samples()->Add(samples.begin(), samples.end());
    if (!stream_->Write(request)) return absl::UnavailableError("the session has ended; Finish() says why");
    return absl::OkStatus();
  }

  absl::Status CloseInput() override {
    std::lock_guard lock(write_mutex_);
    if (!input_closed_) {
      input_closed_ = true;
      stream_->WritesDone();
    }
    return absl::OkStatus();
  }

  absl::StatusOr<std::optional<v1::ReconstructResponse>> Read() override {
    std::lock_guard lock(read_mutex_);
    if (read_done_) return std::nullopt;
    v1::ReconstructResponse reply;
    if (!stream_->Read(&reply)) {
      read_done_ = true;
      return std::nullopt;
    }
    if (reply.has_summary()) {
      summary_ = std::move(*reply.mutable_summary());
      read_done_ = true;
      return std::nullopt;
    }
    return reply;
  }

  absl::StatusOr<v1::SessionSummary> Finish(
      const std::function<void(const v1::ReconstructResponse&)>& on_reply) override {
    CloseInput().IgnoreError();  // always OK
    while (true) {
      absl::StatusOr<std::optional<v1::ReconstructResponse>> reply = Read();
      if (!reply.ok()) return reply.status();
      if (!*reply) break;
      if (on_reply) on_reply(**reply);
    }
    std::lock_guard lock(read_mutex_);
    if (!finished_) {
      finished_ = true;
      status_ = FromGrpc(stream_->Finish());
    }
    if (!status_.ok()) return status_;
    if (!summary_) return absl::InternalError("the session ended without a summary");
    return *summary_;
  }

  void Cancel() override { context_.TryCancel(); }

 private:
  grpc::ClientContext context_;
  std::unique_ptr<grpc::ClientReaderWriter<v1::ReconstructRequest, v1::ReconstructResponse>> stream_;
  v1::SessionStarted started_;
  std::mutex write_mutex_;
  bool input_closed_ = false;
  std::mutex read_mutex_;
  bool read_done_ = false, finished_ = false;
  std::optional<v1::SessionSummary> summary_;
  absl::Status status_;
};

}  // namespace

absl::StatusOr<std::unique_ptr<ReconstructionStream>> Client::OpenReconstruction(const v1::SessionConfig& config) {
  auto stream = std::make_unique<Stream>();
  absl::Status status = stream->Open(*impl_, config);
  if (!status.ok()) return status;
  return stream;
}

absl::StatusOr<v1::ReconstructTrajectoryResponse> Client::ReconstructTrajectory(
    const v1::SessionConfig& config, const std::vector<v1::WristSample>& samples, std::chrono::milliseconds deadline) {
  v1::ReconstructTrajectoryRequest request;
  *request.mutable_config() = config;
  request.mutable_samples()->Add(samples.begin(), samples.end());
  v1::ReconstructTrajectoryResponse response;
  absl::Status status = impl_->Unary(
      Client::Impl::Retry::kIdempotent,
      [&](grpc::ClientContext* c, const auto& r, auto* out) {
        return impl_->reconstruction->ReconstructTrajectory(c, r, out);
      },
      request, &response, deadline);
  if (!status.ok()) return status;
  return response;
}

}  // namespace mocap::client
