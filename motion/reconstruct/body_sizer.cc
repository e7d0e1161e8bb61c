#include "motion/reconstruct/body_sizer.h"

#include <algorithm>
#include <cmath>

#include "motion/core/status_macros.h"

namespace mocap {

BodySizer::BodySizer(WristReach database, float initial_scale, const BodySizerOptions& options)
    : database_(database), options_(options) {
  SetScale(initial_scale);
}

void BodySizer::SetScale(float scale) {
  map_ = SizeMap{.scale = scale};
  target_ = ramp_from_ = scale;
  history_.clear();
}

// A sample out of time order is refused by the session: neither counted nor a step of the ease.
void BodySizer::Count(const WristSample& performer) {
  if (counted_ && !(performer.time > counted_time_)) return;
  reach_.Add(performer).IgnoreError();  // the caller refused non-finite tracked positions
  counted_ = true;
  counted_time_ = performer.time;
}

WristSample BodySizer::Map(const WristSample& performer) {
  if (!mapped_ || performer.time > mapped_time_) {
    if (!mapped_) next_check_ = performer.time + options_.reach.min_seconds;
    mapped_ = true;
    mapped_time_ = performer.time;
    if (options_.online) Resize(performer);
    if (history_.empty() || !(history_.back().map == map_)) history_.push_back({performer.time, map_});
  }
  WristSample database = performer;
  database.left = map_.ToDatabase(performer.left);
  database.right = map_.ToDatabase(performer.right);
  return database;
}

void BodySizer::Resize(const WristSample& sample) {
  if (sample.time >= next_check_) {
    next_check_ = sample.time + options_.check_seconds;
    absl::StatusOr<ReachScale> reach = reach_.Scale(database_, options_.reach);
    if (reach.ok() && reach->input_scale > 0.0f) {
      const float wanted = 1.0f / reach->input_scale;
      if (std::abs(wanted / target_ - 1.0f) >= options_.min_change) {
        ramp_from_ = map_.scale;  // from wherever an unfinished ease has got to
        ramp_start_ = sample.time;
        target_ = wanted;
        ++resizes_;
      }
    }
  }
  if (map_.scale == target_) return;
  // Where the hands are: the point the new map must keep in place. No tracked hand, no change yet.
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  int hands = 0;
  if (sample.tracked[0]) centre += sample.left, ++hands;
  if (sample.tracked[1]) centre += sample.right, ++hands;
  if (hands == 0) return;
  centre /= static_cast<float>(hands);
  const float eased = static_cast<float>(
      options_.ramp_seconds > 0.0 ? std::clamp((sample.time - ramp_start_) / options_.ramp_seconds, 0.0, 1.0) : 1.0);
  const float scale = eased >= 1.0f ? target_ : ramp_from_ + (target_ - ramp_from_) * eased;
  const Eigen::Vector3f kept = map_.ToDatabase(centre);
  map_.scale = scale;
  map_.offset = Eigen::Vector2f(kept.x() - centre.x() / scale, kept.z() - centre.z() / scale);
}

SizeMap BodySizer::MapAt(double time) {
  while (history_.size() > 1 && history_[1].from <= time) history_.pop_front();
  return history_.empty() ? map_ : history_.front().map;
}

absl::StatusOr<std::vector<ReconstructedFrame>> ReconstructSized(std::shared_ptr<const ReconstructionDatabase> database,
                                                                 const ReconstructionOptions& options,
                                                                 const std::vector<WristSample>& samples,
                                                                 BodySizer& sizer, std::vector<SizeMap>* maps) {
  MOCAP_ASSIGN_OR_RETURN(std::unique_ptr<ReconstructionSession> session,
                         ReconstructionSession::Create(std::move(database), options));
  std::vector<ReconstructedFrame> frames;
  maps->clear();
  auto collect = [&] {
    while (maps->size() < frames.size()) maps->push_back(sizer.MapAt(frames[maps->size()].time));
  };
  for (const WristSample& sample : samples) {
    MOCAP_RETURN_IF_ERROR(session->Push(sizer.ToDatabase(sample), &frames));
    collect();
  }
  MOCAP_RETURN_IF_ERROR(session->Finish(&frames));
  collect();
  return frames;
}

}  // namespace mocap
