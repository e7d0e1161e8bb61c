#include "server/trajectory_reactor.h"

#include <algorithm>
#include <exception>

#include "motion/core/str_cat.h"
#include "server/raw_message.h"

namespace mocap {

TrajectoryReactor::TrajectoryReactor(ReconstructionState& state, grpc::CallbackServerContext* context,
                                     const grpc::ByteBuffer* request, grpc::ByteBuffer* response)
    : state_(state),
      call_(state.service, context, "ReconstructTrajectory"),
      request_bytes_(request),
      response_bytes_(response) {
  state_.compute.Post([this] { Begin(); });
}

void TrajectoryReactor::Begin() {
  MutexLock lock(&mutex_);
  absl::Status status = call_.Begin();
  if (status.ok() && state_.draining) status = absl::UnavailableError("the server is shutting down; connect again");
  if (!status.ok()) return Complete(status);
  pool_key_ = static_cast<WorkPool::Key>(call_.tenant().id) + 1;  // 0 is the pool's shared key
  state_.compute.Post(pool_key_, [this] {
    MutexLock lock(&mutex_);
    Parse();
  });
}

void TrajectoryReactor::Parse() {
  if (cancelled_) return Complete(absl::CancelledError("the client went away or its deadline passed"));
  if (absl::Status parsed = FromBytes(*request_bytes_, &request_, "ReconstructTrajectoryRequest"); !parsed.ok())
    return Complete(parsed);
  AcquireSessionDatabase(
      state_, call_, request_.config().database(),
      [this](absl::StatusOr<ReconstructionDatabases::Database> database) { Start(std::move(database)); });
}

void TrajectoryReactor::Start(absl::StatusOr<ReconstructionDatabases::Database> database) {
  MutexLock lock(&mutex_);
  if (!database.ok()) return Complete(database.status());
  absl::StatusOr<std::unique_ptr<SessionDriver>> driver = SessionDriver::Create(
      request_.config(), *database, state_.NextSessionId(), state_.limits.session, call_.metrics(), &cancelled_);
  if (!driver.ok()) return Complete(driver.status());
  driver_ = std::move(*driver);
  *response_.mutable_started() = driver_->started();
  samples_.mutable_samples()->Swap(request_.mutable_samples());
  request_.Clear();
  PostSlice(0);
}

void TrajectoryReactor::PostSlice(int begin) {
  state_.compute.Post(pool_key_, [this, begin] {
    MutexLock lock(&mutex_);
    try {
      Slice(begin);
    } catch (const std::exception& error) {
      Complete(absl::InternalError(StrCat("reconstruction failed: ", error.what())));
    }
  });
}

void TrajectoryReactor::Slice(int begin) {
  if (cancelled_) return Complete(absl::CancelledError("the client went away or its deadline passed"));
  // One bounded step a task: held samples the session has yet to take, the next few samples, or
  // a step of the end of the input (issue #24: a sized whole trajectory was one task of minutes).
  const int size = samples_.samples_size();
  int next = begin;
  bool done = false;
  absl::Status status;
  if (driver_->has_backlog()) {
    status = driver_->Continue(&replies_);
  } else if (begin < size) {
    next = std::min(size, begin + kSamplesPerTask);
    status = driver_->Push(samples_, begin, next, &replies_);
  } else {
    status = driver_->FinishStep(&replies_, &done);
  }
  if (!status.ok()) return Complete(status);
  if (!done) return PostSlice(next);
  for (v1::ReconstructResponse& reply : replies_) {
    if (reply.has_frames()) {
      // The body sized at the end of the input: the response has one skeleton, the frames'.
      if (reply.frames().has_skeleton())
        response_.mutable_started()->mutable_skeleton()->Swap(reply.mutable_frames()->mutable_skeleton());
      for (v1::Frame& frame : *reply.mutable_frames()->mutable_frames()) response_.add_frames()->Swap(&frame);
    } else if (reply.has_rejected()) {
      response_.add_rejected()->Swap(reply.mutable_rejected());
    } else if (reply.has_summary()) {
      response_.mutable_summary()->Swap(reply.mutable_summary());
    } else if (reply.has_input_report()) {  // one report: the floor, every warning
      v1::InputReport* report = response_.mutable_input_report();
      report->set_floor_height(reply.input_report().floor_height());
      report->set_floor_calibrated(reply.input_report().floor_calibrated());
      for (v1::InputWarning& warning : *reply.mutable_input_report()->mutable_warnings())
        report->add_warnings()->Swap(&warning);
    }
  }
  // An answer over the send limit would fail in the transport after this call logged OK.
  const size_t bytes = response_.ByteSizeLong();
  if (bytes > static_cast<size_t>(state_.service.limits.max_message_bytes)) {
    return Complete(
        absl::ResourceExhaustedError(StrCat("the answer has ", bytes, " bytes, over the server's message limit of ",
                                            state_.service.limits.max_message_bytes,
                                            " bytes: send fewer samples per call, or stream them with Reconstruct")));
  }
  Complete(absl::OkStatus());
}

void TrajectoryReactor::Complete(absl::Status status) {
  driver_.reset();  // frees the session now; the response's bytes stay until gRPC has sent them
  replies_.clear();
  samples_.Clear();
  request_.Clear();
  if (status.ok()) status = ToBytes(response_, response_bytes_);
  response_.Clear();
  Finish(call_.End(status));
}

}  // namespace mocap
