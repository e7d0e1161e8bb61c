// Accuracy and motion-quality metrics of a reconstruction against the captured clip (mocap-eval).
#pragma once

#include <string>
#include <vector>

#include "eval/clip_plausibility.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/reconstruct/plausibility.h"
#include "motion/reconstruct/reconstruction_database.h"
#include "motion/reconstruct/reconstruction_session.h"
#include "motion/skeleton/forward_kinematics.h"

namespace mocap::eval {

// Sums over frames; Mean() turns them into the reported figures.
struct Metrics : ClipPlausibility {
  double frames = 0;
  double joint_error_m = 0;       // Σ per-frame mean joint distance (world space, all joints)
  double lower_body_error_m = 0;  // legs and pelvis
  double upper_body_error_m = 0;  // spine, head and arms (pelvis excluded)
  double pelvis_error_m = 0;
  double ankle_error_m = 0;       // both ankle joints
  double wrist_error_m = 0;       // both wrist joints against the captured ones ("input fidelity")
  double angle_error_deg = 0;     // Σ per-frame mean local rotation error over joints
  double angle_error_sq_deg = 0;  // Σ per-frame mean squared error (for RMS)
  double planted_frames = 0;      // foot-frames where the captured foot is planted
  double skate_m = 0;             // Σ reconstructed ankle ground-plane motion over those
  double truth_skate_m = 0;       // the same for the captured ankle
  double jitter_frames = 0;
  double jitter = 0;  // Σ mean |third difference| / Δt³ over joints (m/s³)
  double truth_jitter = 0;
  double seconds = 0;  // engine wall time

  void Add(const Metrics& other);
  double Mean(double sum) const { return frames > 0 ? sum / frames : 0.0; }
};

// Contact rule for the captured foot (stated in the report): planted when its ankle moves slower
// than 0.2 m/s on the ground plane and sits within 5 cm of the database's planted ankle height.
inline constexpr double kTruthContactSpeed = 0.2;
inline constexpr double kTruthContactHeight = 0.05;

// `frames` must be one segment covering the clip's frames in order (frame_in_segment = clip frame).
Metrics Measure(const ReconstructionDatabase& database, const PreparedClip& truth_clip, const GlobalPoses& truth,
                const std::vector<ReconstructedFrame>& frames);

}  // namespace mocap::eval
