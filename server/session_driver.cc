#include "server/session_driver.h"

#include <algorithm>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"

namespace mocap {

absl::StatusOr<std::unique_ptr<SessionDriver>> SessionDriver::Create(const v1::SessionConfig& config,
                                                                     std::shared_ptr<const ReconstructionDatabase> database,
                                                                     std::string session_id, const SessionLimits& limits,
                                                                     ServerMetrics& metrics, const std::atomic<bool>* cancel) {
  MOCAP_ASSIGN_OR_RETURN(ReconstructionOptions options, OptionsFromConfig(config));
  options.max_window_frames = limits.max_window_frames;
  MOCAP_ASSIGN_OR_RETURN(PerformerScale scale, ScaleForPerformer(*database, config.performer_height()));
  MOCAP_ASSIGN_OR_RETURN(std::unique_ptr<ReconstructionSession> session, ReconstructionSession::Create(database, options));
  std::unique_ptr<SessionDriver> driver(new SessionDriver(metrics));
  metrics.SessionStarted();
  driver->session_ = std::move(session);
  driver->session_->SetCancelFlag(cancel);
  driver->config_ = config;
  driver->scale_ = scale;
  driver->limits_ = limits;
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
  started.set_frame_rate(1.0 / database->frame_time());
  started.set_latency_frames(driver->session_->latency_frames());
  started.set_database_height(scale.database_height);
  started.set_database_frames(database->num_frames());
  *started.mutable_config() = EffectiveConfig(config, options);
  started.mutable_config()->clear_target_rig();  // the rig itself is `skeleton`; no echo of its text
  return driver;
}

SessionDriver::~SessionDriver() { metrics_.SessionEnded(); }

absl::Status SessionDriver::Reject(const v1::WristSample& sample, const std::string& reason,
                                   std::vector<v1::ReconstructResponse>* replies) {
  if (config_.strict()) {
    return absl::InvalidArgumentError(StrCat("sample ", samples_ - 1, " (time ", sample.time(), "): ", reason));
  }
  ++rejected_;
  metrics_.SamplesRejected(1);
  v1::SampleRejected* rejected = replies->emplace_back().mutable_rejected();
  rejected->set_sample_index(samples_ - 1);
  rejected->set_time(sample.time());
  rejected->set_reason(reason);
  return absl::OkStatus();
}

absl::Status SessionDriver::Push(const v1::WristSamples& samples, int begin, int end,
                                 std::vector<v1::ReconstructResponse>* replies) {
  for (int i = begin; i < end; ++i) {
    const v1::WristSample& sample = samples.samples(i);
    ++samples_;
    WristSample input;
    const SampleCheck check = FromProto(sample, config_.min_confidence(), scale_, &input);
    if (check.kind != SampleCheck::kAccepted) {
      MOCAP_RETURN_IF_ERROR(Reject(sample, check.reason, replies));
      continue;
    }
    if (!first_time_) first_time_ = sample.time();
    if (sample.time() - *first_time_ > limits_.max_session_seconds) {
      return absl::ResourceExhaustedError(StrCat("session length limit: samples span more than ",
                                                 limits_.max_session_seconds, " s; start a new session"));
    }
    absl::Status pushed = session_->Push(input, &pending_);
    if (absl::IsInvalidArgument(pushed)) {
      MOCAP_RETURN_IF_ERROR(Reject(sample, std::string(pushed.message()), replies));
    } else {
      MOCAP_RETURN_IF_ERROR(pushed);
    }
  }
  AppendFrames(replies);
  return absl::OkStatus();
}

absl::Status SessionDriver::Finish(std::vector<v1::ReconstructResponse>* replies) {
  MOCAP_RETURN_IF_ERROR(session_->Finish(&pending_));
  AppendFrames(replies);
  v1::SessionSummary* summary = replies->emplace_back().mutable_summary();
  ToProto(session_->statistics(), summary);
  summary->set_samples(samples_);
  summary->set_rejected_samples(rejected_);
  summary->set_frames(frames_emitted_);
  summary->set_mean_reply_ms(latency_count_ > 0 ? latency_sum_ms_ / static_cast<double>(latency_count_) : 0.0);
  summary->set_max_reply_ms(latency_max_ms_);
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
    for (size_t i = start; i < end; ++i) {
      v1::Frame* frame = frames->add_frames();
      ToProto(pending_[i], scale_, config_.include_diagnostics(), frame);
      if (!retargeter_) continue;
      retargeter_->Retarget(session_->database().body(), pending_[i].pose, &target_pose_);
      const int pelvis = retargeter_->target().topology.landmarks.pelvis;
      SetTargetPose(target_pose_, retargeter_->world_rotations()[pelvis], retargeter_->world_positions()[pelvis], frame);
    }
  }
  frames_emitted_ += static_cast<long>(pending_.size());
  metrics_.FramesReconstructed(static_cast<std::int64_t>(pending_.size()));
  pending_.clear();
}

}  // namespace mocap
