#include "server/session_driver.h"

#include <algorithm>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/core/units.h"

namespace mocap {

absl::StatusOr<std::unique_ptr<SessionDriver>> SessionDriver::Create(
    const v1::SessionConfig& config, std::shared_ptr<const ReconstructionDatabase> database, std::string session_id,
    const SessionLimits& limits, MetricsScope metrics, const std::atomic<bool>* cancel) {
  MOCAP_ASSIGN_OR_RETURN(ReconstructionOptions options, OptionsFromConfig(config));
  options.max_window_frames = limits.max_window_frames;
  MOCAP_ASSIGN_OR_RETURN(PerformerScale scale, ScaleForPerformer(*database, config.performer_height()));
  MOCAP_ASSIGN_OR_RETURN(InputFrame input_frame, InputFrameFromProto(config.input_frame()));
  // A device gripped beyond the wrist, in the database body's metres (the sizer maps the input so).
  options.grip_offset =
      std::min(kMaxGripOffset,
               static_cast<float>(input_frame.grip_offset * MetresPerUnit(input_frame.convention.unit) / scale.scale));
  MOCAP_ASSIGN_OR_RETURN(std::unique_ptr<ReconstructionSession> session,
                         ReconstructionSession::Create(database, options));
  std::unique_ptr<SessionDriver> driver(new SessionDriver(metrics));
  driver->session_ = std::move(session);
  driver->session_->SetCancelFlag(cancel);
  driver->session_->SetSliceYield(limits.slice_yield);
  driver->config_ = config;
  driver->scale_ = scale;
  bool size_online = false;
  if (config.estimate_performer_height() && config.performer_height() == 0.0f) {
    if (config.has_target_rig()) {
      return absl::InvalidArgumentError(
          "estimate_performer_height with a target_rig: the frames animate the target rig's own skeleton; declare "
          "performer_height instead");
    }
    // The whole trajectory is sized once, before it goes in; a stream follows the reach as it comes.
    const bool whole = options.mode == StreamMode::kSubInterval && options.window == 0;
    driver->estimate_height_ = whole;
    size_online = !whole;
  }
  driver->sizer_.emplace(DeviceReach(database->wrist_reach(), options.grip_offset), scale.scale,
                         BodySizerOptions{.online = size_online});
  driver->limits_ = limits;
  const FloorSpec& floor = input_frame.floor;
  driver->input_ = {input_frame, FrameTransform(input_frame.convention, floor.calibrate ? 0.0 : floor.height)};
  // The monitor's fractions were measured against RestPoseHeight (input_monitor.h).
  driver->monitor_ = std::make_unique<InputMonitor>(
      input_frame.convention, floor.calibrate,
      InputMonitorOptions{.body_height = RestPoseHeight(database->body()) * scale.scale});
  if (config.output_frame() == v1::OUTPUT_FRAME_INPUT && !IsNativeFrame(input_frame))
    driver->output_transform_ = driver->input_.transform;
  v1::SessionStarted& started = driver->started_;
  started.set_session_id(std::move(session_id));
  ToProto(*database, scale, started.mutable_skeleton());
  if (config.has_target_rig()) {  // issue #12: answer on the caller's rig
    MOCAP_ASSIGN_OR_RETURN(RetargetRig target, FromProto(config.target_rig()));
    MOCAP_ASSIGN_OR_RETURN(RetargetRig source, SourceRigOf(database->rig(), database->body().skeleton()));
    MOCAP_ASSIGN_OR_RETURN(driver->retargeter_, Retargeter::Create(std::move(source), std::move(target)));
    started.clear_skeleton();
    ToProto(driver->retargeter_->target(), started.mutable_skeleton());
  }
  // Last, whatever the rig: into the caller's frame (issue #12 part 1).
  if (driver->output_transform_) ToCallerFrame(*driver->output_transform_, started.mutable_skeleton());
  started.set_frame_rate(1.0 / database->frame_time());
  started.set_latency_frames(driver->session_->latency_frames());
  started.set_database_height(scale.database_height);
  started.set_database_frames(database->num_frames());
  *started.mutable_config() = EffectiveConfig(config, options);
  *started.mutable_config()->mutable_input_frame() = ToProto(input_frame, config.input_frame().preset());
  started.mutable_config()->clear_target_rig();  // the rig itself is `skeleton`; no echo of its text
  // Counted once every check has passed: a session refused here never started.
  driver->metrics_.SessionStarted();
  driver->counted_ = true;
  return driver;
}

SessionDriver::~SessionDriver() {
  if (counted_) metrics_.SessionEnded();
}

absl::Status SessionDriver::Reject(long index, double time, const std::string& reason,
                                   std::vector<v1::ReconstructResponse>* replies) {
  if (config_.strict()) {
    return absl::InvalidArgumentError(StrCat("sample ", index, " (time ", time, "): ", reason));
  }
  ++rejected_;
  metrics_.SamplesRejected(1);
  v1::SampleRejected* rejected = replies->emplace_back().mutable_rejected();
  rejected->set_sample_index(index);
  rejected->set_time(time);
  rejected->set_reason(reason);
  return absl::OkStatus();
}

void SessionDriver::StartSlice() {
  slice_deadline_ = std::chrono::steady_clock::now() + limits_.slice_budget;
  session_->SetSliceDeadline(slice_deadline_);
  pushed_in_slice_ = false;
}

bool SessionDriver::SliceOver() const {
  return std::chrono::steady_clock::now() >= slice_deadline_ ||
         (limits_.slice_yield != nullptr && limits_.slice_yield());
}

absl::Status SessionDriver::Push(const v1::WristSamples& samples, int begin, int end,
                                 std::vector<v1::ReconstructResponse>* replies) {
  StartSlice();
  for (int i = begin; i < end; ++i) {
    const v1::WristSample& sample = samples.samples(i);
    ++samples_;
    WristSample input;
    const SampleCheck check = FromProto(sample, config_.min_confidence(), input_, &input, &still_hands_);
    if (check.kind != SampleCheck::kAccepted) {
      MOCAP_RETURN_IF_ERROR(Reject(samples_ - 1, sample.time(), check.reason, replies));
      continue;
    }
    monitor_->Add(input, samples_ - 1, &ready_, &warnings_);
    MOCAP_RETURN_IF_ERROR(ReportInput(replies));
    MOCAP_RETURN_IF_ERROR(PushReady(replies));
  }
  MOCAP_RETURN_IF_ERROR(PushHeld(replies));
  AppendFrames(replies);
  return absl::OkStatus();
}

absl::Status SessionDriver::Continue(std::vector<v1::ReconstructResponse>* replies) {
  StartSlice();
  MOCAP_RETURN_IF_ERROR(PushHeld(replies));
  AppendFrames(replies);
  return absl::OkStatus();
}

absl::Status SessionDriver::PushReady(std::vector<v1::ReconstructResponse>* replies) {
  for (MonitoredSample& ready : ready_) {
    WristSample& input = ready.sample;
    if (!first_time_) first_time_ = input.time;
    if (input.time - *first_time_ > limits_.max_session_seconds) {
      return absl::ResourceExhaustedError(StrCat("session length limit: samples span more than ",
                                                 limits_.max_session_seconds, " s; start a new session"));
    }
    sizer_->Count(ready.sample);  // FromProto refused non-finite samples
    if (estimate_height_) {
      held_.push_back(std::move(ready));  // sized when the input ends, or once held this long
      if (held_.back().sample.time - held_.front().sample.time > limits_.max_reach_hold_seconds) SizeFromReach();
      continue;
    }
    // Behind the held samples still to push, or past the slice (a sample a slice at least): the
    // next task's.
    if (has_backlog() || (pushed_in_slice_ && SliceOver())) {
      held_.push_back(std::move(ready));
      continue;
    }
    MOCAP_RETURN_IF_ERROR(PushScaled(ready, replies));
    pushed_in_slice_ = true;
  }
  ready_.clear();
  return absl::OkStatus();
}

absl::Status SessionDriver::PushScaled(MonitoredSample& ready, std::vector<v1::ReconstructResponse>* replies) {
  const WristSample input = sizer_->Map(ready.sample);  // the performer's metres to the database body's
  absl::Status pushed = session_->Push(input, &pending_);
  if (absl::IsInvalidArgument(pushed)) return Reject(ready.index, input.time, std::string(pushed.message()), replies);
  return pushed;
}

void SessionDriver::SizeFromReach() {
  // The sizer has counted exactly the held samples yet. An error here is a database without
  // frames: no estimate.
  absl::StatusOr<ReachScale> reach =
      sizer_->reach().Scale(DeviceReach(session_->database().wrist_reach(), session_->options().grip_offset));
  if (reach.ok() && reach->input_scale < 1.0f) {
    scale_.scale = 1.0f / reach->input_scale;
    sizer_->SetScale(scale_.scale);
    resized_ = true;
  }
  estimate_height_ = false;
  held_next_ = 0;
}

bool SessionDriver::has_backlog() const {
  return (held_next_ < held_.size() && !estimate_height_) || session_->has_pending_frames();
}

absl::Status SessionDriver::PushHeld(std::vector<v1::ReconstructResponse>* replies) {
  while (has_backlog()) {
    if (session_->has_pending_frames()) {  // the frames a window decided, before the samples after it
      MOCAP_RETURN_IF_ERROR(session_->Continue(&pending_));
    } else {
      MOCAP_RETURN_IF_ERROR(PushScaled(held_[held_next_++], replies));
    }
    if (SliceOver()) break;
  }
  if (held_next_ == held_.size()) {
    std::vector<MonitoredSample>().swap(held_);
    held_next_ = 0;
  }
  return absl::OkStatus();
}

absl::Status SessionDriver::ReportInput(std::vector<v1::ReconstructResponse>* replies) {
  if (!monitor_->window_done() || (input_reported_ && warnings_.empty())) return absl::OkStatus();
  if (config_.strict() && !warnings_.empty()) {
    return absl::InvalidArgumentError(StrCat("input frame: ", warnings_.front().message));
  }
  const FrameConvention& convention = input_.frame.convention;
  const float floor_native = input_.transform.floor_native() + monitor_->calibrated_floor();
  if (!input_reported_ && output_transform_ && input_.frame.floor.calibrate) {
    output_transform_ = FrameTransform(convention, FloorHeightFromNative(convention, floor_native));
  }
  input_reported_ = true;
  v1::InputReport* report = replies->emplace_back().mutable_input_report();
  report->set_floor_height(static_cast<float>(FloorHeightFromNative(convention, floor_native)));
  report->set_floor_calibrated(input_.frame.floor.calibrate);
  for (const InputWarning& warning : warnings_) *report->add_warnings() = ToProto(warning);
  warnings_.clear();
  return absl::OkStatus();
}

absl::Status SessionDriver::Finish(std::vector<v1::ReconstructResponse>* replies) {
  bool done = false;
  while (!done) MOCAP_RETURN_IF_ERROR(FinishStep(replies, &done));
  return absl::OkStatus();
}

absl::Status SessionDriver::FinishStep(std::vector<v1::ReconstructResponse>* replies, bool* done) {
  *done = false;
  StartSlice();
  if (!input_ended_) {
    input_ended_ = true;
    monitor_->Finish(&ready_, &warnings_);
    MOCAP_RETURN_IF_ERROR(ReportInput(replies));
    MOCAP_RETURN_IF_ERROR(PushReady(replies));
    if (estimate_height_) SizeFromReach();
  }
  MOCAP_RETURN_IF_ERROR(PushHeld(replies));
  if (has_backlog()) {
    AppendFrames(replies);
    return absl::OkStatus();
  }
  MOCAP_RETURN_IF_ERROR(session_->Finish(&pending_));
  AppendFrames(replies);
  if (session_->has_pending_frames()) return absl::OkStatus();  // its last window, a slice at a time
  v1::SessionSummary* summary = replies->emplace_back().mutable_summary();
  ToProto(session_->statistics(), summary);
  summary->set_samples(samples_);
  summary->set_rejected_samples(rejected_);
  summary->set_frames(frames_emitted_);
  summary->set_mean_reply_ms(latency_count_ > 0 ? latency_sum_ms_ / static_cast<double>(latency_count_) : 0.0);
  summary->set_max_reply_ms(latency_max_ms_);
  summary->set_performer_height(scale_.database_height * sizer_->map().scale);
  summary->set_performer_height_estimated(resized_ || sizer_->resizes() > 0);
  absl::StatusOr<ReachScale> reach =
      sizer_->reach().Scale(DeviceReach(session_->database().wrist_reach(), session_->options().grip_offset));
  summary->set_reach_height(scale_.database_height / (reach.ok() ? reach->input_scale : 1.0f));
  *done = true;
  return absl::OkStatus();
}

void SessionDriver::RecordReplyLatency(double milliseconds) {
  metrics_.ReplyLatency(milliseconds / 1e3);
  latency_sum_ms_ += milliseconds;
  latency_max_ms_ = std::max(latency_max_ms_, milliseconds);
  ++latency_count_;
}

void SessionDriver::AppendFrames(std::vector<v1::ReconstructResponse>* replies) {
  for (size_t start = 0; start < pending_.size(); start += kFramesPerReply) {
    const size_t end = std::min(pending_.size(), start + kFramesPerReply);
    v1::ReconstructedFrames* frames = replies->emplace_back().mutable_frames();
    frames->mutable_frames()->Reserve(static_cast<int>(end - start));
    if (resized_ && !resized_sent_) {  // the body was sized after `started`: its skeleton
      ToProto(session_->database(), scale_, frames->mutable_skeleton());
      if (output_transform_) ToCallerFrame(*output_transform_, frames->mutable_skeleton());
      resized_sent_ = true;
    }
    for (size_t i = start; i < end; ++i) {
      v1::Frame* frame = frames->add_frames();
      // The client animates scale_'s skeleton: `started`'s, or the one sent above before any frame.
      ToProto(pending_[i], sizer_->MapAt(pending_[i].time), scale_.scale, config_.include_diagnostics(), frame);
      if (retargeter_) {
        retargeter_->Retarget(session_->database().body(), pending_[i].pose, &target_pose_);
        const int pelvis = retargeter_->target().topology.landmarks.pelvis;
        SetTargetPose(target_pose_, retargeter_->world_rotations()[pelvis], retargeter_->world_positions()[pelvis],
                      frame);
      }
      if (output_transform_) ToCallerFrame(*output_transform_, frame);  // last, whatever the rig
    }
  }
  frames_emitted_ += static_cast<long>(pending_.size());
  metrics_.FramesReconstructed(static_cast<std::int64_t>(pending_.size()));
  pending_.clear();
}

}  // namespace mocap
