// The truth-free plausibility of reconstructed clips (motion/reconstruct/plausibility.h) as
// mocap-eval sums it over clips, for both joint (eval_metrics.h) and landmark
// (landmark_metrics.h) scoring, and its figures in the JSON reports.
#pragma once

#include <algorithm>

#include <nlohmann/json.hpp>

#include "motion/reconstruct/plausibility.h"

namespace mocap::eval {

struct ClipPlausibility {
  PlausibilityStats plausibility;
  double clips = 0;
  double truth_pelvis_speed_max = 0;  // m/s, the fastest capture
  double clips_over_allowed_speed = 0;
  double worst_speed_over_allowed = 0;  // the largest output max / allowed over clips
  // The same for the ankles (either; a foot that teleports is as visible as a body that does).
  double truth_ankle_speed_max = 0;
  double clips_feet_over_allowed_speed = 0;
  double worst_ankle_speed_over_allowed = 0;

  // One clip: its output's measures against its capture's fastest pelvis and ankle, which allow
  // AllowedSpeed() (issue #22).
  void SetClip(PlausibilityStats stats, double truth_pelvis_max, double truth_ankle_max) {
    plausibility = std::move(stats);
    clips = 1;
    truth_pelvis_speed_max = truth_pelvis_max;
    worst_speed_over_allowed = plausibility.pelvis_speed.max() / AllowedSpeed(static_cast<float>(truth_pelvis_max));
    clips_over_allowed_speed = worst_speed_over_allowed > 1.0 ? 1 : 0;
    truth_ankle_speed_max = truth_ankle_max;
    worst_ankle_speed_over_allowed = plausibility.ankle_speed.max() / AllowedSpeed(static_cast<float>(truth_ankle_max));
    clips_feet_over_allowed_speed = worst_ankle_speed_over_allowed > 1.0 ? 1 : 0;
  }
  void AddPlausibility(const ClipPlausibility& o) {
    plausibility.Merge(o.plausibility);
    clips += o.clips;
    truth_pelvis_speed_max = std::max(truth_pelvis_speed_max, o.truth_pelvis_speed_max);
    clips_over_allowed_speed += o.clips_over_allowed_speed;
    worst_speed_over_allowed = std::max(worst_speed_over_allowed, o.worst_speed_over_allowed);
    truth_ankle_speed_max = std::max(truth_ankle_speed_max, o.truth_ankle_speed_max);
    clips_feet_over_allowed_speed += o.clips_feet_over_allowed_speed;
    worst_ankle_speed_over_allowed = std::max(worst_ankle_speed_over_allowed, o.worst_ankle_speed_over_allowed);
  }
};

inline nlohmann::json PlausibilityJson(const ClipPlausibility& m) {
  const PlausibilityStats& p = m.plausibility;
  const Histogram& hands = p.hand_distance;
  return {
      {"pelvis_speed_max_m_per_s", p.pelvis_speed.max()},
      {"pelvis_speed_p99_m_per_s", p.pelvis_speed.Quantile(0.99)},
      {"capture_pelvis_speed_max_m_per_s", m.truth_pelvis_speed_max},
      {"pelvis_acceleration_max_m_per_s2", p.pelvis_acceleration_max},
      {"frames_faster_than_database", p.frames_over_speed_limit},
      {"clips", m.clips},
      {"clips_faster_than_allowed", m.clips_over_allowed_speed},
      {"worst_speed_over_allowed", m.worst_speed_over_allowed},
      {"ankle_speed_max_m_per_s", p.ankle_speed.max()},
      {"ankle_speed_p99_m_per_s", p.ankle_speed.Quantile(0.99)},
      {"capture_ankle_speed_max_m_per_s", m.truth_ankle_speed_max},
      {"clips_feet_faster_than_allowed", m.clips_feet_over_allowed_speed},
      {"worst_ankle_speed_over_allowed", m.worst_ankle_speed_over_allowed},
      {"hand_to_input_p50_cm", 100 * hands.Quantile(0.5)},
      {"hand_to_input_p99_cm", 100 * hands.Quantile(0.99)},
      {"hand_to_input_max_cm", 100 * hands.max()},
      {"hand_frames_in_reach", hands.count()},
      {"hand_frames_out_of_reach", p.hand_frames_out_of_reach},
      {"hand_to_input_out_of_reach_max_cm", 100 * p.hand_distance_out_of_reach_max},
      {"lower_foot_height_p99_cm", 100 * p.lower_foot_height.Quantile(0.99)},
      {"lower_foot_height_max_cm", 100 * p.lower_foot_height.max()},
      {"ground_penetration_max_cm", 100 * p.penetration_max},
      {"penetrating_frames", p.penetrating_frames},
      {"implausible_input_frames", p.flagged_frames},
      {"motion_limited_frames", p.motion_limited_frames},
      {"put_down_hand_frames", p.put_down_hand_frames},
  };
}

}  // namespace mocap::eval
