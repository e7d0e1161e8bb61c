#include "server/reconstruct_reactor.h"

#include <spdlog/spdlog.h>

#include "motion/core/str_cat.h"

namespace mocap {

ReconstructReactor::ReconstructReactor(ReconstructionState& state, grpc::CallbackServerContext* context)
    : state_(state), call_(state.service, context, "Reconstruct"), session_id_(state.NextSessionId()) {
  {
    std::lock_guard live(state_.live_mutex);
    state_.live.insert(this);
  }
  std::lock_guard lock(mutex_);
  if (state_.draining) {
    CompleteLocked(absl::UnavailableError("the server is shutting down; connect again"), true);
  }
  PumpLocked();
}

void ReconstructReactor::Post(std::function<void()> work) {
  // Called with mutex_ held.
  ++tasks_;
  state_.compute.Post([this, work = std::move(work)] {
    work();
    std::lock_guard lock(mutex_);
    --tasks_;
    PumpLocked();
  });
}

void ReconstructReactor::OnReadDone(bool ok) {
  const Clock::time_point arrival = Clock::now();
  std::lock_guard lock(mutex_);
  reading_ = false;
  last_read_ = arrival;
  if (completing_ || input_done_) return PumpLocked();
  if (!ok) {  // the client half-closed (or went away: OnCancel says so)
    input_done_ = true;
    if (!configured_) {
      CompleteLocked(absl::InvalidArgumentError("the stream ended before its config message"), false);
      return PumpLocked();
    }
    return Post([this] { EndInput(absl::OkStatus()); });
  }
  switch (request_.kind_case()) {
    case v1::ReconstructRequest::kConfig:
      if (configured_) {
        CompleteLocked(absl::InvalidArgumentError("config sent twice: one session per stream"), false);
        return PumpLocked();
      }
      configured_ = true;
      return Post([this, config = request_.config()] { HandleConfig(config); });
    case v1::ReconstructRequest::kSamples:
      if (!configured_) {
        CompleteLocked(absl::InvalidArgumentError("samples before the config: send SessionConfig first"), false);
        return PumpLocked();
      }
      return Post([this, request = std::move(request_), arrival]() mutable { Handle(std::move(request), arrival); });
    case v1::ReconstructRequest::kFinish:
      input_done_ = true;
      if (!configured_) {
        CompleteLocked(absl::InvalidArgumentError("finish before the config message"), false);
        return PumpLocked();
      }
      return Post([this] { EndInput(absl::OkStatus()); });
    default:
      CompleteLocked(absl::InvalidArgumentError("empty request: set config, samples or finish"), false);
      return PumpLocked();
  }
}

void ReconstructReactor::HandleConfig(const v1::SessionConfig& config) {
  absl::Status status = call_.Begin(&state_.sessions, "sessions_per_tenant");
  if (!status.ok()) return Deliver({}, status);
  {
    std::lock_guard lock(mutex_);
    ++tasks_;  // the database wait; AcquireSessionDatabase always answers
  }
  AcquireSessionDatabase(state_, call_, config.database(), [this, config](absl::StatusOr<ReconstructionDatabases::Database> database) {
    Replies replies;
    absl::Status status = database.status();
    if (status.ok()) {
      std::lock_guard session(session_mutex_);
      absl::StatusOr<std::unique_ptr<SessionDriver>> driver =
          SessionDriver::Create(config, *database, session_id_, state_.limits.session, state_.service.metrics);
      status = driver.status();
      if (driver.ok()) {
        driver_ = std::move(*driver);
        replies.emplace_back().mutable_started()->CopyFrom(driver_->started());
        spdlog::info("session={} request={} tenant={} database={} label=\"{}\" started: {} frames in database, latency {} frames",
                     session_id_, call_.request_id(), call_.tenant().name, config.database(), config.client_label(),
                     (*database)->num_frames(), driver_->started().latency_frames());
      }
    }
    Deliver(std::move(replies), status);
    std::lock_guard lock(mutex_);
    --tasks_;
    PumpLocked();
  });
}

void ReconstructReactor::Handle(v1::ReconstructRequest request, Clock::time_point arrival) {
  Replies replies;
  absl::Status status;
  {
    std::lock_guard session(session_mutex_);
    if (!driver_) return;  // the session ended before it started (drain, error)
    status = driver_->Push(request.samples(), &replies);
    driver_->RecordReplyLatency(std::chrono::duration<double, std::milli>(Clock::now() - arrival).count());
  }
  Deliver(std::move(replies), status);
}

void ReconstructReactor::EndInput(absl::Status final_status) {
  Replies replies;
  absl::Status status = final_status;
  {
    std::lock_guard session(session_mutex_);
    if (driver_) {
      absl::Status finished = driver_->Finish(&replies);
      if (!finished.ok()) status = finished;
      spdlog::info("session={} ended: {} frames, {} samples rejected", session_id_, driver_->frames_emitted(),
                   driver_->samples_rejected());
      driver_.reset();  // frees the session now; the database stays shared with others
    }
  }
  std::lock_guard lock(mutex_);
  if (!completing_) {
    for (v1::ReconstructResponse& reply : replies) outbox_.push_back(std::move(reply));
  }
  CompleteLocked(status, false);
}

void ReconstructReactor::Deliver(Replies replies, const absl::Status& status) {
  std::lock_guard lock(mutex_);
  if (completing_) return;  // the call's outcome is decided: later replies are not sent
  for (v1::ReconstructResponse& reply : replies) outbox_.push_back(std::move(reply));
  if (!status.ok()) CompleteLocked(status, false);
}

void ReconstructReactor::CompleteLocked(const absl::Status& status, bool discard_replies) {
  if (discard_replies) outbox_.clear();
  if (completing_) return;
  completing_ = true;
  input_done_ = true;
  final_status_ = call_.End(status);
}

void ReconstructReactor::PumpLocked() {
  if (finished_ || writing_) return;
  if (!outbox_.empty()) {
    writing_message_ = std::move(outbox_.front());
    outbox_.pop_front();
    writing_ = true;
    StartWrite(&writing_message_);
    return;
  }
  if (completing_) {
    // Compute tasks refer to this reactor: finish only when none is left. A read still
    // outstanding completes with ok = false after Finish.
    if (tasks_ == 0) {
      finished_ = true;
      Finish(final_status_);
    }
    return;
  }
  if (!reading_ && !input_done_ && tasks_ == 0) {
    reading_ = true;
    last_read_ = Clock::now();
    StartRead(&request_);
  }
}

void ReconstructReactor::OnWriteDone(bool ok) {
  std::lock_guard lock(mutex_);
  writing_ = false;
  if (!ok) CompleteLocked(absl::CancelledError("the client stopped reading"), true);
  PumpLocked();
}

void ReconstructReactor::OnCancel() {
  std::lock_guard lock(mutex_);
  CompleteLocked(absl::CancelledError("the client went away"), true);
  PumpLocked();
}

bool ReconstructReactor::IdleSince(Clock::time_point cutoff) {
  std::lock_guard lock(mutex_);
  return reading_ && !completing_ && last_read_ < cutoff;
}

void ReconstructReactor::EndIdle() {
  std::lock_guard lock(mutex_);
  CompleteLocked(absl::DeadlineExceededError(StrCat("no message from the client for ",
                                                    state_.limits.idle_timeout.count() / 1000.0,
                                                    " s (the server's idle limit): session ended")),
                 true);
  PumpLocked();
}

void ReconstructReactor::EndForShutdown() {
  std::lock_guard lock(mutex_);
  if (completing_) return;
  const absl::Status status = absl::UnavailableError("the server is shutting down: frames sent so far stand; connect again");
  if (!configured_ || input_done_) {
    if (!input_done_) CompleteLocked(status, false);
    return PumpLocked();
  }
  input_done_ = true;
  Post([this, status] { EndInput(status); });
}

void ReconstructReactor::OnDone() {
  {
    std::lock_guard live(state_.live_mutex);
    state_.live.erase(this);
  }
  delete this;
}

}  // namespace mocap
