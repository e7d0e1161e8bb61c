// The performer's size from how far the wrists reach (issue #22, docs/method.md "Performer's
// size"). A database's bodies held their wrists at most so far apart and so high; input whose
// wrists spend a good share of their time beyond that comes from a larger body, at least by the
// ratio. The bound is one-sided on purpose: wrists that stay within the database's reach say
// nothing about size (a small performer and a large one who keeps the hands low look alike), and
// every estimator tried that read size from where the wrists usually are took content for size
// (docs/evaluation.md, the size rows).
#pragma once

#include <array>
#include <span>

#include "absl/status/statusor.h"
#include "motion/preprocess/frame_features.h"
#include "motion/reconstruct/hand_rest.h"
#include "motion/reconstruct/wrist_resampler.h"

namespace mocap {

// The farthest a database's bodies held their wrists: apart (metres between the two) and up
// (the higher wrist above the ground), over every captured frame.
struct WristReach {
  float separation = 0.0f;
  float height = 0.0f;
};
WristReach MeasureWristReach(std::span<const FrameFeatures> frames);
// How far the database's bodies would hold devices gripped `grip_offset` metres beyond each wrist
// (ReconstructionOptions::grip_offset): that much higher, twice that further apart. Input of
// devices read against the wrists' reach sized every body up (mocap-eval's phone_in_hand: 15 of
// 173 clips to 1.0–1.16 ×).
inline WristReach DeviceReach(const WristReach& wrists, float grip_offset) {
  return {.separation = wrists.separation + 2.0f * grip_offset, .height = wrists.height + grip_offset};
}

struct ReachScaleOptions {
  // The input's reach: this quantile of its samples (a twentieth of the input beyond the database's
  // farthest, not one stretched moment or a tracker's outlier).
  float quantile = 0.95f;
  double min_seconds = 1.0;  // less input than this: no estimate (scale 1)
  float min_scale = 0.7f;    // at most a body 1.43 times the database's
};

struct ReachScale {
  // Multiply the input by it (≤ 1) to bring the performer to the database body; the output is
  // divided by it.
  float input_scale = 1.0f;
  float separation = 0.0f, height = 0.0f;  // the input's reach (the quantile), metres
};

// An input's reach as it streams in: 5 mm bins up to 5 m of separation and height (8 kB, no
// allocation), so a live session can tell at any time how large a body its wrists need.
// Samples in metres, Y up, ground at y = 0 (as the session takes them). Separation counts samples
// with both hands tracked, height every tracked hand.
class ReachHistogram {
 public:
  // InvalidArgument (and nothing added) for a non-finite tracked position.
  absl::Status Add(const WristSample& sample);
  // InvalidArgument for an empty database reach.
  absl::StatusOr<ReachScale> Scale(const WristReach& database, const ReachScaleOptions& options = {}) const;

 private:
  static constexpr float kBinMetres = 0.005f;
  static constexpr int kBins = 1000;
  // A hand still (within hand_rest.h's kStillRadius) this long may be a device put down: while it
  // is, the hands' separation is no evidence of arms (the person walks away from the device).
  static constexpr double kStillSeconds = 0.5;
  std::array<StillHand, 2> still_;
  std::array<int, kBins> separation_{}, height_{};
  long separation_count_ = 0, height_count_ = 0, samples_ = 0;
  double first_time_ = 0.0, last_time_ = 0.0;
};

// The same over a whole input at once.
absl::StatusOr<ReachScale> InputScaleFromReach(const WristReach& database, std::span<const WristSample> samples,
                                               const ReachScaleOptions& options = {});

}  // namespace mocap
