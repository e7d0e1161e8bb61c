#include "server/reconstruct_reactor.h"

#include <algorithm>
#include <new>
#include <optional>

#include <spdlog/spdlog.h>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "server/log_text.h"
#include "server/raw_message.h"
#include "storage/tenant_directory.h"

namespace mocap {
namespace {

// Replies as the bytes the stream writes, made by the compute task that computed them.
absl::StatusOr<std::vector<grpc::ByteBuffer>> Encode(const std::vector<v1::ReconstructResponse>& replies) {
  std::vector<grpc::ByteBuffer> encoded(replies.size());
  for (std::size_t i = 0; i < replies.size(); ++i) MOCAP_RETURN_IF_ERROR(ToBytes(replies[i], &encoded[i]));
  return encoded;
}

}  // namespace

ReconstructReactor::ReconstructReactor(ReconstructionState& state, grpc::CallbackServerContext* context)
    : state_(state), call_(state.service, context, "Reconstruct"), session_id_(state.NextSessionId()) {
  {
    MutexLock live(&state_.live_mutex);
    state_.live.insert(this);
  }
  MutexLock lock(&mutex_);
  if (state_.draining) {
    CompleteLocked(absl::UnavailableError("the server is shutting down; connect again"), true);
  } else if (absl::Status key = call_.CheckKeyPresent(); !key.ok()) {
    CompleteLocked(key, true);  // refused before anything is read: a keyless stream holds nothing
  } else {
    // The key is checked and the tenant's session admitted before the first read.
    Post([this] { Authenticate(); });
  }
  PumpLocked();
}

void ReconstructReactor::Authenticate() {
  absl::Status status = call_.Begin(&state_.sessions, "sessions_per_tenant");
  if (!status.ok()) return Deliver({}, status);
  // The server's own capacity, after the tenant's: a refused key or tenant limit says so first.
  absl::StatusOr<std::vector<Tenant>> tenants = TenantDirectory(call_.store()).ListTenants();
  if (!tenants.ok()) return Deliver({}, tenants.status());
  const bool shared =
      std::count_if(tenants->begin(), tenants->end(), [](const Tenant& t) { return t.active_keys > 0; }) > 1;
  absl::StatusOr<StreamCapacity::Ticket> stream = state_.streams.Admit(call_.tenant().id, shared);
  if (!stream.ok()) {
    call_.metrics().Rejected("server_streams");
    return Deliver({}, stream.status());
  }
  pool_key_ = static_cast<WorkPool::Key>(call_.tenant().id) + 1;  // 0 is the pool's shared key
  MutexLock lock(&mutex_);
  stream_ticket_ = *std::move(stream);
  paced_ = shared && state_.pacer.enabled();
  AdvanceTo(Phase::kConfiguring);  // ignored when the call completed meanwhile
}

ReconstructReactor::TaskToken::TaskToken(ReconstructReactor& reactor) : reactor_(&reactor) { ++reactor.tasks_; }

ReconstructReactor::TaskToken::~TaskToken() {
  if (reactor_ == nullptr) return;  // moved from
  MutexLock lock(&reactor_->mutex_);
  --reactor_->tasks_;
  reactor_->PumpLocked();  // may Finish: the reactor is not touched after the lock is released
}

void ReconstructReactor::Post(std::function<void()> work) {
  // Called with mutex_ held.
  auto token = std::make_shared<TaskToken>(TaskToken(*this));
  state_.compute.Post(pool_key_.load(), [this, token, work = std::move(work)] {
    const TaskToken task = std::move(*token);  // released last, when this task returns or throws
    absl::Status failed;
    try {
      work();
    } catch (const std::exception& error) {
      failed = absl::InternalError(StrCat("reconstruction failed: ", error.what()));
    } catch (...) {
      failed = absl::InternalError("reconstruction failed");
    }
    if (!failed.ok()) {
      MutexLock lock(&mutex_);
      CompleteLocked(failed, true);
    }
  });
}

void ReconstructReactor::PostSliceLocked() {
  Post([this, samples = samples_, arrival = samples_arrival_] { HandleSlice(samples, arrival); });
}

void ReconstructReactor::OnReadDone(bool ok) {
  const Clock::time_point arrival = Clock::now();
  MutexLock lock(&mutex_);
  reading_ = false;
  last_read_ = arrival;
  if (ok && paced_) next_read_ = state_.pacer.Charge(pool_key_.load(), arrival);
  if (phase_ >= Phase::kInputDone) return PumpLocked();
  // Reads start only once authenticated, so the phase is kConfiguring or kStreaming here.
  const bool configured = phase_ == Phase::kStreaming;
  if (!ok) {  // the client half-closed (or went away: OnCancel says so)
    if (!configured) {
      CompleteLocked(absl::InvalidArgumentError("the stream ended before its config message"), false);
      return PumpLocked();
    }
    AdvanceTo(Phase::kInputDone);
    return Post([this] { EndInput(absl::OkStatus()); });
  }
  // Only the message's shape is looked at on gRPC's thread; what it holds is parsed on the pool.
  auto bytes = std::make_shared<SamplesReader>(read_buffer_);
  if (!bytes->samples_only()) return Post([this, bytes, arrival] { HandleRequest(*bytes, arrival); });
  if (!configured) {
    CompleteLocked(absl::InvalidArgumentError("samples before the config: send SessionConfig first"), false);
    return PumpLocked();
  }
  samples_ = std::move(bytes);
  samples_arrival_ = arrival;
  PumpLocked();
}

void ReconstructReactor::HandleRequest(SamplesReader& bytes, Clock::time_point arrival) {
  absl::StatusOr<v1::ReconstructRequest> request = bytes.ParseWhole();
  MutexLock lock(&mutex_);
  // The call may have ended, or its input, while the message was parsed; this task's end pumps.
  if (phase_ >= Phase::kInputDone) return;
  if (!request.ok()) return CompleteLocked(request.status(), false);
  DispatchLocked(*request, arrival);
}

void ReconstructReactor::DispatchLocked(v1::ReconstructRequest& request, Clock::time_point arrival) {
  const bool configured = phase_ == Phase::kStreaming;
  switch (request.kind_case()) {
    case v1::ReconstructRequest::kConfig:
      if (configured) {
        CompleteLocked(absl::InvalidArgumentError("config sent twice: one session per stream"), false);
        return PumpLocked();
      }
      AdvanceTo(Phase::kStreaming);
      return Post([this, config = std::move(*request.mutable_config())] { HandleConfig(config); });
    case v1::ReconstructRequest::kSamples: {
      if (!configured) {
        CompleteLocked(absl::InvalidArgumentError("samples before the config: send SessionConfig first"), false);
        return PumpLocked();
      }
      // Samples in another form than one field (repeated fields merged, unknown ones dropped by
      // the parser): written back as one, they are read as every samples message is.
      v1::ReconstructRequest only;
      only.mutable_samples()->Swap(request.mutable_samples());
      grpc::ByteBuffer bytes;
      if (absl::Status written = ToBytes(only, &bytes); !written.ok()) {
        CompleteLocked(written, false);
        return PumpLocked();
      }
      samples_ = std::make_shared<SamplesReader>(bytes);
      samples_arrival_ = arrival;
      return PumpLocked();
    }
    case v1::ReconstructRequest::kFinish:
      if (!configured) {
        CompleteLocked(absl::InvalidArgumentError("finish before the config message"), false);
        return PumpLocked();
      }
      AdvanceTo(Phase::kInputDone);
      return Post([this] { EndInput(absl::OkStatus()); });
    default:
      CompleteLocked(absl::InvalidArgumentError("empty request: set config, samples or finish"), false);
      return PumpLocked();
  }
}

void ReconstructReactor::HandleConfig(const v1::SessionConfig& config) {
  std::shared_ptr<TaskToken> wait;  // the database wait; AcquireSessionDatabase always answers
  {
    MutexLock lock(&mutex_);
    wait = std::make_shared<TaskToken>(TaskToken(*this));
  }
  AcquireSessionDatabase(
      state_, call_, config.database(),
      [this, config, wait](absl::StatusOr<ReconstructionDatabases::Database> database) {
        const TaskToken waited = std::move(*wait);  // released last, after Deliver
        Replies replies;
        absl::Status status = database.status();
        if (status.ok()) {
          MutexLock session(&session_mutex_);
          // This runs outside Post's catch: a throw here (an allocation a rig made impossible)
          // must still answer the call and release its task, or the call hangs and blocks
          // shutdown (issue #24 finding 5).
          absl::StatusOr<std::unique_ptr<SessionDriver>> driver = absl::InternalError("session setup failed");
          try {
            driver = SessionDriver::Create(config, *database, session_id_, state_.limits.session, call_.metrics(),
                                           &cancelled_);
          } catch (const std::bad_alloc&) {
            driver = absl::ResourceExhaustedError("session setup needs more memory than this server can give it");
          } catch (const std::exception& error) {
            driver = absl::InternalError(StrCat("session setup failed: ", error.what()));
          }
          status = driver.status();
          if (driver.ok()) {
            driver_ = std::move(*driver);
            session_started_ = true;
            replies.emplace_back().mutable_started()->CopyFrom(driver_->started());
            spdlog::info(
                "session={} request={} tenant={} database={} label=\"{}\" started: {} frames in database, latency {} "
                "frames",
                session_id_, call_.request_id(), call_.tenant().name, LogText(config.database()),
                LogText(config.client_label()), (*database)->num_frames(), driver_->started().latency_frames());
          }
        }
        Deliver(std::move(replies), status);
      });
}

void ReconstructReactor::HandleSlice(const std::shared_ptr<SamplesReader>& samples, Clock::time_point arrival) {
  Replies replies;
  absl::Status status;
  {
    MutexLock session(&session_mutex_);
    if (driver_) {  // null when the session ended before it started (drain, error)
      const absl::Status read = samples->Next(kSamplesPerTask);
      status = driver_->Push(samples->batch(), 0, samples->batch().samples_size(), &replies);
      if (status.ok()) status = read;  // the samples before a malformed one are taken
      if (samples->done() && status.ok())
        driver_->RecordReplyLatency(std::chrono::duration<double, std::milli>(Clock::now() - arrival).count());
    }
    MutexLock lock(&mutex_);
    if (driver_) backlog_ = driver_->has_backlog();
    // Wholly read (or no session to read it into): the next read may start once this task has
    // returned. A failed slice ends the call in Deliver, which drops samples_ too.
    if ((samples->done() || !driver_) && samples_ == samples) samples_.reset();
  }
  Deliver(std::move(replies), status);
}

void ReconstructReactor::ContinueBacklog() {
  Replies replies;
  absl::Status status;
  {
    MutexLock session(&session_mutex_);
    if (!driver_) return;
    status = driver_->Continue(&replies);
    MutexLock lock(&mutex_);
    backlog_ = driver_->has_backlog();
  }
  Deliver(std::move(replies), status);
}

void ReconstructReactor::EndInput(absl::Status final_status) {
  Replies replies;
  absl::Status status = final_status;
  bool done = true;
  {
    MutexLock session(&session_mutex_);
    if (driver_) {
      absl::Status finished = driver_->FinishStep(&replies, &done);
      if (!finished.ok()) {
        status = finished;
        done = true;
      }
      if (done) ReleaseDriverLocked();  // frees the session now; the database stays shared with others
    }
  }
  absl::StatusOr<std::vector<grpc::ByteBuffer>> encoded = Encode(replies);
  if (!encoded.ok()) {
    status = encoded.status();
    done = true;
  }
  MutexLock lock(&mutex_);
  if (phase_ < Phase::kCompleting && encoded.ok()) {
    for (grpc::ByteBuffer& reply : *encoded) outbox_.emplace_back().Swap(&reply);
    if (!done) {  // PumpLocked posts the next step as the replies are written
      finishing_ = final_status;
      return;
    }
  }
  finishing_.reset();
  CompleteLocked(status, false);
}

void ReconstructReactor::Deliver(Replies replies, const absl::Status& status) {
  absl::StatusOr<std::vector<grpc::ByteBuffer>> encoded = Encode(replies);
  MutexLock lock(&mutex_);
  if (phase_ >= Phase::kCompleting) return;  // the call's outcome is decided: later replies are not sent
  if (!encoded.ok()) return CompleteLocked(encoded.status(), false);
  for (grpc::ByteBuffer& reply : *encoded) outbox_.emplace_back().Swap(&reply);
  if (!status.ok()) CompleteLocked(status, false);
}

void ReconstructReactor::CompleteLocked(const absl::Status& status, bool discard_replies) {
  if (discard_replies) outbox_.clear();
  if (!AdvanceTo(Phase::kCompleting)) return;  // the first outcome stands
  samples_.reset();
  // A normal end (half-close, finish, shutdown) still computes the remaining frames: EndInput
  // runs before this. Anything else stops the session's compute now.
  if (!status.ok() && !absl::IsUnavailable(status)) cancelled_ = true;
  final_status_ = call_.End(status);
}

bool ReconstructReactor::AdvanceTo(Phase phase) {
  if (phase <= phase_) return false;
  phase_ = phase;
  return true;
}

void ReconstructReactor::PumpLocked() {
  if (phase_ == Phase::kFinished) return;
  if (!writing_ && !outbox_.empty()) {
    writing_message_.Swap(&outbox_.front());
    outbox_.pop_front();
    writing_ = true;
    StartWrite(&writing_message_);
  }
  if (phase_ == Phase::kCompleting) {
    // Compute tasks refer to this reactor: finish only when none is left and every queued reply
    // is written. A read still outstanding completes with ok = false after Finish.
    if (!writing_ && tasks_ == 0) {
      AdvanceTo(Phase::kFinished);
      Finish(final_status_);
    }
    return;
  }
  if (phase_ == Phase::kInputDone && finishing_) {
    // The end of the input, its next step once the previous one is done and its replies are few.
    if (tasks_ == 0 && outbox_.size() < kMaxQueuedReplies) Post([this, status = *finishing_] { EndInput(status); });
    return;
  }
  if (phase_ == Phase::kStreaming && backlog_) {
    // Held samples the session takes before anything newer, a slice at a time (as a message is).
    if (tasks_ == 0 && outbox_.size() < kMaxQueuedReplies) Post([this] { ContinueBacklog(); });
    return;
  }
  if (samples_) {
    // The message in progress: its next slice once the previous one is done and few of its
    // replies wait to be written (a client that does not read holds its own session back).
    if (tasks_ == 0 && outbox_.size() < kMaxQueuedReplies) PostSliceLocked();
    return;
  }
  const bool reads = phase_ == Phase::kConfiguring || phase_ == Phase::kStreaming;
  if (reads && !writing_ && outbox_.empty() && !reading_ && tasks_ == 0) {
    if (paced_ && Clock::now() < next_read_) return WaitToReadLocked();
    reading_ = true;
    last_read_ = Clock::now();
    StartRead(&read_buffer_);
  }
}

void ReconstructReactor::WaitToReadLocked() {
  // Not cancelled when the call completes: a wait is at most one message's share of the budget per
  // stream of the tenant (64 sessions at --tenant-message-rate 1,000 or more: 64 ms), and Finish
  // waits for it. The alarm takes the system clock; a wake a little early waits again.
  call_.metrics().ReadPaced();
  auto waiting = std::make_shared<TaskToken>(TaskToken(*this));
  const auto deadline = std::chrono::system_clock::now() +
                        std::chrono::duration_cast<std::chrono::system_clock::duration>(next_read_ - Clock::now());
  read_alarm_.emplace();  // an earlier alarm has fired (its wait was a task): dropping it is safe
  read_alarm_->Set(deadline, [waiting](bool) { const TaskToken waited = std::move(*waiting); });
}

void ReconstructReactor::OnWriteDone(bool ok) {
  MutexLock lock(&mutex_);
  writing_ = false;
  if (!ok) CompleteLocked(absl::CancelledError("the client stopped reading"), true);
  PumpLocked();
}

void ReconstructReactor::OnCancel() {
  MutexLock lock(&mutex_);
  // gRPC does not say why: the client cancelled or disconnected, its deadline passed, or the
  // transport refused a message over the size limit (the client was told RESOURCE_EXHAUSTED).
  CompleteLocked(
      absl::CancelledError("call cancelled: by the client, its deadline, a lost connection or a message over "
                           "the server's size limit"),
      true);
  PumpLocked();
}

bool ReconstructReactor::IdleSince(Clock::time_point cutoff) {
  MutexLock lock(&mutex_);
  return reading_ && phase_ < Phase::kCompleting && last_read_ < cutoff;
}

void ReconstructReactor::EndIdle() {
  MutexLock lock(&mutex_);
  CompleteLocked(
      absl::DeadlineExceededError(StrCat("no message from the client for ", state_.limits.idle_timeout.count() / 1000.0,
                                         " s (the server's idle limit): session ended")),
      true);
  PumpLocked();
}

void ReconstructReactor::EndForShutdown() {
  MutexLock lock(&mutex_);
  if (phase_ >= Phase::kCompleting) return;
  const absl::Status status =
      absl::UnavailableError("the server is shutting down: frames sent so far stand; connect again");
  if (phase_ != Phase::kStreaming) {
    // Before the config there is no session to finish; after the input it is being finished.
    if (phase_ < Phase::kStreaming) CompleteLocked(status, false);
    return PumpLocked();
  }
  AdvanceTo(Phase::kInputDone);
  samples_.reset();  // the rest of a message in progress is dropped: frames sent so far stand
  Post([this, status] { EndInput(status); });
}

void ReconstructReactor::ReleaseDriverLocked() {
  if (!driver_) return;
  frames_emitted_ = driver_->frames_emitted();
  samples_rejected_ = driver_->samples_rejected();
  driver_.reset();
}

void ReconstructReactor::BeforeDelete() {
  {
    MutexLock session(&session_mutex_);
    ReleaseDriverLocked();
    MutexLock lock(&mutex_);
    if (session_started_) {
      spdlog::info("session={} request={} ended code={}: {} frames, {} samples rejected", session_id_,
                   call_.request_id(), GrpcCodeName(final_status_.error_code()), frames_emitted_, samples_rejected_);
    }
  }
  MutexLock live(&state_.live_mutex);
  state_.live.erase(this);
}

}  // namespace mocap
