// SessionDriver: one reconstruction session between the wire and the engine, whatever the
// transport (the Reconstruct stream or the unary ReconstructTrajectory): config → `started`,
// sample messages → frames and rejected samples, end of input → the last frames and the summary.
// Replies are mocap.v1 messages ready to send; frames go in batches of at most kFramesPerReply.
// Samples are converted from the client's declared input frame to native metres (and the floor
// calibrated, the input checked: InputMonitor) on the way in; replies go back into that frame
// unless config.output_frame asks for the server's.
// The driver keeps the server's session counters: a session is active from Create to destruction,
// and its frames, refused samples and reply latencies are counted as they happen.
//
// Thread safety: none; one caller at a time.
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "mocap/v1/reconstruction.pb.h"
#include "motion/frames/input_monitor.h"
#include "motion/reconstruct/body_sizer.h"
#include "motion/reconstruct/reconstruction_session.h"
#include "motion/retarget/retargeter.h"
#include "server/reconstruction_convert.h"
#include "server/server_metrics.h"

namespace mocap {

struct SessionLimits {
  double max_session_seconds = 4 * 3600.0;  // span of the input's timestamps
  // Whole-trajectory sessions (window 0) solve their ankle path in windows of at most this many
  // frames, so a session's memory stays bounded (ReconstructionOptions::max_window_frames).
  int max_window_frames = 600;  // 20 s at 30 fps: ~20 MB of ankle clouds at K1 = 500
  // estimate_performer_height holds the input until it ends to read its reach; past this span the
  // body is sized on what is held and the rest streams on (48 bytes a sample: ~17 MB at 60 Hz).
  double max_reach_hold_seconds = 600.0;
  // A call's work goes into the session a slice at a time: until this much time has passed (a
  // window's frames are solved a few at a time, so a slice is this plus about one frame's work).
  // Issue #24: ten minutes of held samples were one task of ~30 s, a 600-frame window ~0.4 s.
  std::chrono::microseconds slice_budget{20'000};
  // Ends a slice sooner, at the next frame or sample, when it returns true: the server passes
  // WorkPool::AnotherKeyWaits (another tenant's work waits for the thread). nullptr: never.
  bool (*slice_yield)() = nullptr;
};

class SessionDriver {
 public:
  static constexpr int kFramesPerReply = 256;

  // InvalidArgument for a bad config (the message names the field). Once `*cancel` is set (any
  // thread), Push and Finish return Cancelled within one frame's work; the flag must outlive
  // the driver (nullptr: never cancelled).
  static absl::StatusOr<std::unique_ptr<SessionDriver>> Create(const v1::SessionConfig& config,
                                                               std::shared_ptr<const ReconstructionDatabase> database,
                                                               std::string session_id, const SessionLimits& limits,
                                                               MetricsScope metrics,
                                                               const std::atomic<bool>* cancel = nullptr);
  ~SessionDriver();

  const v1::SessionStarted& started() const { return started_; }
  // Errors end the session: InvalidArgument for a refused sample with config.strict,
  // ResourceExhausted past the session length.
  // Samples [begin, end) of `samples`, so that callers can cut a large message into short tasks.
  absl::Status Push(const v1::WristSamples& samples, int begin, int end, std::vector<v1::ReconstructResponse>* replies);
  absl::Status Push(const v1::WristSamples& samples, std::vector<v1::ReconstructResponse>* replies) {
    return Push(samples, 0, samples.samples_size(), replies);
  }
  // Work a call left after a slice of SessionLimits::slice_budget (issue #24: such work in
  // one task held a compute thread for as long): held samples the body was sized on, and the
  // frames of a window the session decided at once (a whole trajectory's or A4's sub-interval:
  // up to ~0.3 s of solving), with the samples that came after them. Call Continue until there
  // is none before the next Push.
  bool has_backlog() const;
  absl::Status Continue(std::vector<v1::ReconstructResponse>* replies);
  // The end of the input, a slice at a time: the remaining frames, then the summary. Sets
  // `*done` once the summary is in `replies`; until then call it again (not Push).
  absl::Status FinishStep(std::vector<v1::ReconstructResponse>* replies, bool* done);
  // All of FinishStep at once. Call once.
  absl::Status Finish(std::vector<v1::ReconstructResponse>* replies);
  // Server-side latency of one sample message (reported in the summary and the metrics).
  void RecordReplyLatency(double milliseconds);

  long frames_emitted() const { return frames_emitted_; }
  long samples_rejected() const { return rejected_; }

 private:
  bool counted_ = false;  // in the session metrics (SessionStarted called)
  explicit SessionDriver(MetricsScope metrics) : metrics_(metrics) {}
  void AppendFrames(std::vector<v1::ReconstructResponse>* replies);
  absl::Status Reject(long index, double time, const std::string& reason,
                      std::vector<v1::ReconstructResponse>* replies);
  // The monitor's released samples into the session, its findings into an InputReport.
  absl::Status PushReady(std::vector<v1::ReconstructResponse>* replies);
  // One released sample into the session, through the sizer.
  absl::Status PushScaled(MonitoredSample& ready, std::vector<v1::ReconstructResponse>* replies);
  // config.estimate_performer_height, at the end of the input: the body's size from the wrists'
  // reach (wrist_reach.h); the held samples then go into the session through PushHeld.
  void SizeFromReach();
  // The slice a call may take: until limits_.slice_budget from now, the session's too, or less
  // when limits_.slice_yield says so.
  void StartSlice();
  bool SliceOver() const;
  // The backlog (has_backlog) into the session, in order, until the slice is over.
  absl::Status PushHeld(std::vector<v1::ReconstructResponse>* replies);
  absl::Status ReportInput(std::vector<v1::ReconstructResponse>* replies);

  MetricsScope metrics_;
  v1::SessionConfig config_;
  std::unique_ptr<ReconstructionSession> session_;
  PerformerScale scale_;
  bool estimate_height_ = false;       // hold the input until it ends, then size the body by reach
  std::vector<MonitoredSample> held_;  // while estimate_height_, then until pushed
  size_t held_next_ = 0;               // the first held sample not yet pushed, once sized
  bool input_ended_ = false;           // FinishStep has taken the monitor's last samples
  // Performer's space to the database body's and back; counts every accepted sample's reach.
  std::optional<BodySizer> sizer_;
  bool resized_ = false, resized_sent_ = false;  // the estimate changed the skeleton; told the client
  InputConversion input_;
  std::array<StillHand, 2> still_hands_;  // FromProto: a device left far from the other hand
  std::unique_ptr<InputMonitor> monitor_;
  std::vector<MonitoredSample> ready_;  // released by the monitor, not yet pushed
  std::vector<InputWarning> warnings_;  // found, not yet reported
  bool input_reported_ = false;
  std::optional<FrameTransform> output_transform_;  // native → caller; unset: the server's frame
  SessionLimits limits_;
  std::chrono::steady_clock::time_point slice_deadline_;
  bool pushed_in_slice_ = false;  // a sample went into the session in this slice
  v1::SessionStarted started_;
  std::vector<ReconstructedFrame> pending_;  // decided, not yet converted
  std::optional<Retargeter> retargeter_;     // config.target_rig: frames answered on that rig
  BodyPose target_pose_;
  long samples_ = 0, rejected_ = 0, frames_emitted_ = 0;
  std::optional<double> first_time_;  // of the first accepted sample
  double latency_sum_ms_ = 0.0, latency_max_ms_ = 0.0;
  long latency_count_ = 0;
};

}  // namespace mocap
