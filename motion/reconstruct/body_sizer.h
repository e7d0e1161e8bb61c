// The performer's size as a stream learns it (issue #22, docs/method.md "Performer's size by
// reach"). The session reconstructs the database's body; a performer of another size is brought to
// it on the way in and back on the way out. A whole trajectory is sized once from its reach
// (wrist_reach.h) before the first sample goes in; a live stream cannot wait, so `BodySizer` starts
// at the database's (or the declared) size and follows the reach as the wrists show it, easing each
// change in over a second so the body grows and never pops.
//
// The map keeps heights about the floor (y = 0) and, on the ground plane, moves its centre with the
// hands: when the size changes, the point under the hands' midpoint maps where it mapped before. A
// change of size about a fixed origin would move a performer five metres from it by tens of
// centimetres in one frame.
#pragma once

#include <deque>

#include <Eigen/Core>

#include "motion/reconstruct/reconstruction_session.h"
#include "motion/reconstruct/wrist_reach.h"
#include "motion/reconstruct/wrist_resampler.h"

namespace mocap {

// Performer's space to the database body's: q = p / scale + offset on the ground plane,
// q.y = p.y / scale.
struct SizeMap {
  float scale = 1.0f;                                // performer / database body
  Eigen::Vector2f offset = Eigen::Vector2f::Zero();  // (x, z) in the database body's space, metres

  Eigen::Vector3f ToDatabase(const Eigen::Vector3f& p) const {
    return {p.x() / scale + offset.x(), p.y() / scale, p.z() / scale + offset.y()};
  }
  Eigen::Vector3f ToPerformer(const Eigen::Vector3f& q) const {
    return {(q.x() - offset.x()) * scale, q.y() * scale, (q.z() - offset.y()) * scale};
  }
  bool operator==(const SizeMap&) const = default;
};

struct BodySizerOptions {
  // Follow the reach while the input streams in. Off: the size stays where it is set.
  bool online = false;
  // The first read after a quarter of a second, then every tenth, each change eased in over a
  // quarter: a body too small for its input meanwhile reaches and leans for it, so the sooner the
  // better (docs/method.md "Performer's size by reach"; a second each before stop 80). The
  // quantile over what has come so far is read again as more comes, so an early stretch is undone.
  ReachScaleOptions reach{.min_seconds = 0.25};
  double check_seconds = 0.1;  // how often the reach is read again
  // A change of size smaller than this (relative) is not worth a change of the body's proportions.
  float min_change = 0.02f;
  double ramp_seconds = 0.25;  // each change eases in over this long
};

class BodySizer {
 public:
  // `initial_scale`: performer / database body to start from (a declared height, or 1).
  BodySizer(WristReach database, float initial_scale, const BodySizerOptions& options = {});

  // Sets the size outright, before any sample went through (a whole trajectory sized from its
  // reach, wrist_reach.h).
  void SetScale(float scale);

  // Counts the sample into the reach, changes the size if the reach asks for it (online), and
  // returns the sample in the database body's space. The caller has checked that tracked positions
  // are finite.
  WristSample ToDatabase(const WristSample& performer) {
    Count(performer);
    return Map(performer);
  }
  // The two halves, for a caller that holds the input before it is sized: the reach counted as
  // samples arrive, the map taken when they go in.
  void Count(const WristSample& performer);
  WristSample Map(const WristSample& performer);

  // The map the input at `time` went through; the frames a session decides from that input go
  // back through it. Times must not decrease between calls (frames leave in order); older maps are
  // dropped.
  SizeMap MapAt(double time);

  const SizeMap& map() const { return map_; }
  const ReachHistogram& reach() const { return reach_; }
  int resizes() const { return resizes_; }

 private:
  void Resize(const WristSample& sample);

  WristReach database_;
  BodySizerOptions options_;
  ReachHistogram reach_;
  SizeMap map_;
  // The ease towards `target_`: from `ramp_from_` at `ramp_start_`.
  float target_ = 1.0f, ramp_from_ = 1.0f;
  double ramp_start_ = 0.0, next_check_ = 0.0, counted_time_ = 0.0, mapped_time_ = 0.0;
  bool counted_ = false, mapped_ = false;
  int resizes_ = 0;
  struct TimedMap {
    double from;  // input time from which `map` applies
    SizeMap map;
  };
  std::deque<TimedMap> history_;
};

// ReconstructOffline with the input sized by `sizer` on the way in; `maps` receives the map each
// frame's input went through (SizeMap::ToPerformer takes its positions to the performer's space).
absl::StatusOr<std::vector<ReconstructedFrame>> ReconstructSized(std::shared_ptr<const ReconstructionDatabase> database,
                                                                 const ReconstructionOptions& options,
                                                                 const std::vector<WristSample>& samples,
                                                                 BodySizer& sizer, std::vector<SizeMap>* maps);

}  // namespace mocap
