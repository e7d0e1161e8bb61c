// The Reconstruct stream of one session (reconstruction_service.h): a state machine with at most
// one read, one write and one compute task outstanding (the config task and its database wait
// overlap briefly; each holds a TaskToken). Its phase (Phase) only moves forward:
//
//   kAuthenticating  open → [compute] authenticate, admit the tenant's session (nothing is read before)
//   kConfiguring     read config → [compute] find the database, wait for its index → write `started`
//   kStreaming       read samples → [compute] SessionDriver::Push of a few samples → write their frames →
//                    [compute] the next few ... → read next message
//   kInputDone       half-close, `finish` or drain → [compute] SessionDriver::FinishStep → frames →
//                    [compute] the next step ... → the last frames, summary
//   kCompleting      the final status is decided: the queued replies are written, compute tasks drain
//   kFinished        Finish(status) called
// Any phase before kCompleting jumps to it when the call's outcome is decided (an error, a cancel,
// the idle limit, a refusal); the first outcome stands.
// Messages are read as bytes (samples_reader.h): gRPC's threads only look at a message's shape,
// and a samples message is parsed kSamplesPerTask samples at a time, each slice a task posted
// under the tenant's key of the fair compute pool, which also writes its replies' bytes: a large
// message is answered incrementally and cannot hold a gRPC or compute thread, and another
// tenant's task waits for at most one task per thread. Any other message is parsed whole in a task. The next slice is
// posted only while few replies wait to be written, and the next message is read only after the
// replies to the previous one have been written, so a slow reader slows its own session and
// nothing queues without bound. Where several tenants share the server, a tenant's reads are paced
// to its message budget (message_pacer.h), so a flood of small messages slows its own clients
// through flow control rather than every tenant through the transport's threads. Once the call's outcome is decided
// (cancelled, idle, deadline, error) the session's cancel flag stops its compute within one frame. The reactor finishes
// only when no compute task refers to it: each holds a TaskToken.
#pragma once

#include <atomic>
#include <chrono>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <grpcpp/alarm.h>
#include <grpcpp/support/byte_buffer.h>

#include "motion/core/mutex.h"
#include "server/owned_reactor.h"
#include "server/reconstruction_service.h"
#include "server/samples_reader.h"

namespace mocap {

class ReconstructReactor : public OwnedReactor<grpc::ServerBidiReactor<grpc::ByteBuffer, grpc::ByteBuffer>> {
 public:
  ReconstructReactor(ReconstructionState& state, grpc::CallbackServerContext* context);

  void OnReadDone(bool ok) override;
  void OnWriteDone(bool ok) override;
  void OnCancel() override;

  // Watchdog and drain (any thread, with state.live_mutex held).
  // True when waiting for the client's next message since before `cutoff`.
  bool IdleSince(std::chrono::steady_clock::time_point cutoff);
  void EndIdle();
  void EndForShutdown();

 private:
  using Clock = std::chrono::steady_clock;
  using Replies = std::vector<v1::ReconstructResponse>;

  static constexpr int kSamplesPerTask = 4;
  static constexpr size_t kMaxQueuedReplies = 8;  // replies waiting to be written before a slice

  // The stream's lifecycle, in order (the file comment); it only moves forward (AdvanceTo).
  enum class Phase {
    kAuthenticating,  // the key is checked and the tenant admitted (a compute task); nothing is read yet
    kConfiguring,     // reads may start; the first message must be the config
    kStreaming,       // config received: samples are read, computed and answered
    kInputDone,       // half-close, `finish` or drain: no more reads, the remaining frames are computed
    kCompleting,      // the final status is decided: queued replies are written, no new work starts
    kFinished,        // Finish called
  };

  // One compute task (or the database wait) that refers to this reactor: counted in tasks_ while
  // it lives. Made with mutex_ held; released (destroyed, not moved from) with mutex_ NOT held, it
  // takes mutex_, drops the count and pumps the stream, which finishes the call once the last task
  // of a completing call is gone. Move-only. std::function (WorkPool::Post, AcquireSessionDatabase)
  // needs a copyable callable, so a token travels in a shared_ptr and the task that runs moves it
  // out first: the count drops when that task returns, however many copies of the callable remain
  // and wherever they are destroyed.
  class TaskToken {
   public:
    explicit TaskToken(ReconstructReactor& reactor) ABSL_EXCLUSIVE_LOCKS_REQUIRED(reactor.mutex_);
    TaskToken(TaskToken&& other) noexcept : reactor_(std::exchange(other.reactor_, nullptr)) {}
    TaskToken& operator=(TaskToken&&) = delete;
    ~TaskToken();

   private:
    ReconstructReactor* reactor_;  // null once moved from
  };

  // Runs `work` on the compute pool under this session's tenant; the reactor stays alive until
  // it has returned. An exception ends the call with INTERNAL.
  void Post(std::function<void()> work) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  // Posts the next slice of the samples message in progress.
  void PostSliceLocked() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  // The next slice of `samples`, which arrived at `arrival` (the reply latency of its last slice).
  void HandleSlice(const std::shared_ptr<SamplesReader>& samples, Clock::time_point arrival);
  // A message other than one samples field (a config, a finish), parsed whole on the pool.
  void HandleRequest(SamplesReader& bytes, Clock::time_point arrival);
  // What a parsed request asks for, in the stream's phase.
  void DispatchLocked(v1::ReconstructRequest& request, Clock::time_point arrival) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  void Authenticate();
  void HandleConfig(const v1::SessionConfig& config);
  // Frees the session, keeping its counts for the end-of-session line.
  void ReleaseDriverLocked() ABSL_EXCLUSIVE_LOCKS_REQUIRED(session_mutex_);
  // One line per session end, however it ended, with the code the client was sent (finding 8).
  void BeforeDelete() override;
  // The end of the input, one slice of it (SessionDriver::FinishStep); until the summary is made
  // the next slice is posted as replies are written, and `final_status` ends the call after it.
  void EndInput(absl::Status final_status);
  // Held samples the session has yet to take (SessionDriver::Continue), a slice at a time.
  void ContinueBacklog();
  // Queues replies; `status` not OK ends the call after them.
  void Deliver(Replies replies, const absl::Status& status);
  // Ends the call with `status` after the queued replies (dropped when `discard_replies`). The
  // first call wins.
  void CompleteLocked(const absl::Status& status, bool discard_replies) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  // Starts the next write, read or Finish, whichever is due.
  void PumpLocked() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  // Holds the next read until `next_read_` (the tenant's message budget, message_pacer.h): the
  // wait holds a TaskToken, whose release pumps the stream again.
  void WaitToReadLocked() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  // Moves the phase forward to `phase`; a move to the current or an earlier phase is ignored (a
  // later phase stands: e.g. authentication that ends after the call was cancelled). True when
  // the phase changed.
  bool AdvanceTo(Phase phase) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);

  ReconstructionState& state_;
  CallScope call_;
  const std::string session_id_;
  grpc::ByteBuffer read_buffer_;                      // the message being read, as bytes
  Mutex session_mutex_ ABSL_ACQUIRED_BEFORE(mutex_);  // the session itself (compute tasks)
  std::unique_ptr<SessionDriver> driver_ ABSL_GUARDED_BY(session_mutex_);
  bool session_started_ ABSL_GUARDED_BY(session_mutex_) = false;     // a driver was created: its end is logged
  std::int64_t frames_emitted_ ABSL_GUARDED_BY(session_mutex_) = 0;  // kept when the driver is freed
  std::int64_t samples_rejected_ ABSL_GUARDED_BY(session_mutex_) = 0;
  std::atomic<bool> cancelled_{false};  // set once the outcome is decided: stops the session's compute
  std::atomic<WorkPool::Key> pool_key_{WorkPool::kSharedKey};  // the tenant, once authenticated

  // Guarded by the base's mutex_ (owned_reactor.h).
  Phase phase_ ABSL_GUARDED_BY(mutex_) = Phase::kAuthenticating;
  // The gRPC operations in flight stay two booleans beside the phase, not part of it: they are
  // orthogonal to it and to each other (one read and one write at a time; a write overlaps compute
  // and reads, and a read may still be outstanding when the call completes: it ends with ok = false).
  bool reading_ ABSL_GUARDED_BY(mutex_) = false;
  bool writing_ ABSL_GUARDED_BY(mutex_) = false;
  StreamCapacity::Ticket stream_ticket_ ABSL_GUARDED_BY(mutex_);  // one of the server's live streams, until deleted
  // Live TaskTokens: compute tasks queued or running, a database wait, and a paced read's wait.
  int tasks_ ABSL_GUARDED_BY(mutex_) = 0;
  // Where several tenants share the server, the tenant's message budget paces this stream's reads:
  // the next read starts no sooner than `next_read_` (ReconstructionLimits::message_pacing).
  bool paced_ ABSL_GUARDED_BY(mutex_) = false;
  Clock::time_point next_read_ ABSL_GUARDED_BY(mutex_);
  std::optional<grpc::Alarm> read_alarm_ ABSL_GUARDED_BY(mutex_);
  grpc::Status final_status_ ABSL_GUARDED_BY(mutex_);
  std::deque<grpc::ByteBuffer> outbox_ ABSL_GUARDED_BY(mutex_);  // replies, serialized by the task that made them
  grpc::ByteBuffer writing_message_ ABSL_GUARDED_BY(mutex_);
  Clock::time_point last_read_ ABSL_GUARDED_BY(mutex_) = Clock::now();
  // The session has held samples to take before the next message (SessionDriver::has_backlog).
  bool backlog_ ABSL_GUARDED_BY(mutex_) = false;
  // The end of the input is being computed a slice at a time; the call then ends with this status.
  std::optional<absl::Status> finishing_ ABSL_GUARDED_BY(mutex_);
  // The samples message being read slice by slice (null when none or wholly read).
  std::shared_ptr<SamplesReader> samples_ ABSL_GUARDED_BY(mutex_);
  Clock::time_point samples_arrival_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace mocap
