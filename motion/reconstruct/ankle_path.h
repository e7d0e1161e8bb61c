// Optimal ankle trajectory of docs/method.md A4: a shortest path through the ankle clouds. Nodes are
// the cloud candidates of every frame; every node at t−1 links to every node at t with cost
//   w = β·σ + (1−β)·d,  β = 0.5,
//   σ = ‖y_j^(t−1) + Δt·ẏ_j^(t−1) − y_k^t‖²   (motion prior: where the neighbour's velocity goes)
//   d = Σ_feet exp(w_s·‖y_j^(t−1) − y_k^t‖²) when that foot slides, else 0,
// a foot sliding, by default, when it moves more than `slide_distance` with both ends near the
// planted ankle height (SlideRule::kContact; the patent's rule, moving more than 2 cm while its
// height changes less than "0.14 cm", is SlideRule::kPatent), plus a node cost on each candidate's
// eq. 2 distance (`data_weight`; 0 = the patent's cost). Dynamic programming over the frames
// (O(L·K1²)), backtracking, then a Gaussian filter (Algorithm 1).
// Sub-intervals (§3.3.1): SolveAnkleWindow solves L frames starting from the previous window's
// last node, so a stream can emit windows as they fill.
#pragma once

#include <array>
#include <atomic>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "absl/status/statusor.h"
#include "motion/reconstruct/ankle_cloud.h"

namespace mocap {

enum class SlideRule {
  kPatent,   // moves > slide_distance while its height changes < slide_height (fires on a level swing too)
  kContact,  // moves > slide_distance while both ends are within contact_height of the planted ankle height
};

struct AnklePathOptions {
  float prior_weight = 0.5f;  // β
  // σ is a squared length; the patent does not give its unit. In metres a 2 cm miss costs 0.0004
  // while any slide costs ≥ 1, so σ is taken in centimetres (× 100²), which balances the terms.
  float prior_length_scale = 100.0f;
  SlideRule slide_rule = SlideRule::kContact;
  float slide_distance = 0.02f;        // metres between consecutive frames
  float slide_height = 0.014f;         // metres: the patent's "0.14 cm" read as 1.4 cm (see note)
  float planted_ankle_height = 0.08f;  // metres (the session sets the database's)
  float contact_height = 0.04f;        // metres above the planted height
  float slide_weight = 100.0f;         // w_s, 1/m²
  // Gaussian filter on the chosen path, frames; 0 = none. Whole clips and windows (a path decided
  // whole): chosen on the development split (stop 79, docs/method.md A4), σ 2 / 1.5 / 1 / 0.5 gave
  // 1.9965 / 1.9643 / 1.9485 / 1.9419 cm, foot skate 0.069 / 0.059 / 0.055 / 0.059 cm/frame: the
  // wider filter spread each footfall over the frames about it, so the foot landed late and crept
  // into place.
  float smoothing_sigma_frames = 1.0f;
  // The same in a stream (a fixed lag), whose path is stitched from each frame's best path and
  // changes its mind: there a narrower filter lets those changes through as fast feet. Lag 5, σ 2 /
  // 1.5 / 1 / 0.5: 2.1014 / 2.0870 / 2.0817 / 2.0753 cm, but clips whose feet outrun the capture's
  // 10 / 14 / 12 / 18; lag 0: 2.6581 / 2.6304 / 2.6204 / 2.6111 cm, skate 0.295 / 0.301 / 0.331 /
  // 0.370 cm/frame, feet over 87 / 95 / 110 / 131 clips.
  float stream_smoothing_sigma_frames = 2.0f;
  // Where that filter reaches past the path's newest frame (every frame a stream emits) or a
  // segment's ends, a foot moving faster than this (m/s, over the end's last step) is fitted by a
  // weighted line through the frames there are instead of repeating the end frame, which lags a
  // swinging foot (docs/method.md A4: standard split lag 0 2.94 → 2.64 cm, lag 5 2.17 → 2.11).
  // A still foot keeps the end frame: a line through a path's wobble only extrapolates it.
  // Negative: always repeat the end frame (before stop 67).
  float edge_fit_speed = 0.6f;
  // Node cost: this weight × the candidate's eq. 2 wrist distance (× prior_length_scale², the
  // σ term's units). The patent's edge cost has no data term, so every one of the K1 candidates
  // is as welcome as the nearest and the path may settle on poor wrist matches; 0 = the patent's.
  float data_weight = 0.01f;  // --dev-split: 0 / 0.003 / 0.01 / 0.03 / 0.1 → MPJPE 2.56 / 2.42 / 2.38 / 2.40 / 2.43 cm
};

using AnklePair = std::array<Eigen::Vector3f, 2>;  // [0] left, [1] right ankle, world metres

inline AnklePair AnklesOf(const AnkleCandidate& c) { return {c.position[0], c.position[1]}; }

struct AnkleWindowResult {
  std::vector<int> nodes;         // chosen candidate per frame of the window
  std::vector<AnklePair> ankles;  // its ankles (not smoothed)
  float cost = 0.0f;
};

// One DP step (Algorithm 1): the cheapest path cost to every node of `current` and its best
// predecessor in `previous`, whose path costs are `previous_cost`. Exact: the result of scanning
// every edge with AnkleEdgeCost (ties go to the lower path cost); see ankle_dag_step.cc for how it
// avoids most of that work.
void AnkleDagStep(const std::vector<AnkleCandidate>& previous, const std::vector<float>& previous_cost,
                  const std::vector<AnkleCandidate>& current, float frame_time, const AnklePathOptions& options,
                  std::vector<float>* cost, std::vector<int>* from);
// Adds each node's data cost (AnklePathOptions::data_weight) to its path cost.
void AddAnkleDataCost(const std::vector<AnkleCandidate>& cloud, const AnklePathOptions& options,
                      std::vector<float>* cost);
// Path costs of a window's first frame: edges from `start`, or all zero at a segment's start.
std::vector<float> AnkleStartCosts(const std::optional<AnkleCandidate>& start, const std::vector<AnkleCandidate>& first,
                                   float frame_time, const AnklePathOptions& options);

// A4's forward pass over one window, a frame at a time as its clouds arrive, so a stream spreads
// a window's DP over the samples that fill it (issue #24: a 600-frame window's DP was ~140 ms of
// one task at its end). The clouds stay the caller's; each call gets the same clouds the window's
// earlier calls got. SolveAnkleWindow is this over a whole window at once.
class AnkleWindowDp {
 public:
  AnkleWindowDp(double frame_time, const AnklePathOptions& options)
      : frame_time_(static_cast<float>(frame_time)), options_(options) {}
  // The window's first frame: `start` as in SolveAnkleWindow. Clears what the DP held.
  void Start(const std::optional<AnkleCandidate>& start, const std::vector<AnkleCandidate>& cloud);
  // The next frame, `previous` being the frame added before it.
  void Step(const std::vector<AnkleCandidate>& previous, const std::vector<AnkleCandidate>& cloud);
  int frames() const { return static_cast<int>(from_.size()); }
  // The cheapest path through the frames added (clouds[t] the cloud of frame t), ankles included.
  AnkleWindowResult Best(const std::vector<std::vector<AnkleCandidate>>& clouds) const;

 private:
  float frame_time_;
  AnklePathOptions options_;
  std::vector<float> cost_, next_cost_;  // the newest frame's path costs, and Step's scratch
  std::vector<std::vector<int>> from_;   // per frame: each node's best predecessor
};

// One window: clouds[t] for its frames; `start` is the previous window's last chosen candidate
// (the only start node), or nullopt at the beginning of a segment. InvalidArgument for an empty
// window or an empty cloud.
// Cancelled (checked between DAG steps) once `*cancel` is set.
absl::StatusOr<AnkleWindowResult> SolveAnkleWindow(const std::vector<std::vector<AnkleCandidate>>& clouds,
                                                   const std::optional<AnkleCandidate>& start, double frame_time,
                                                   const AnklePathOptions& options,
                                                   const std::atomic<bool>* cancel = nullptr);

// Whole trajectory in windows of `window` frames (0 = all frames at once, the global optimum),
// then smoothed.
absl::StatusOr<std::vector<AnklePair>> SolveAnklePath(const std::vector<std::vector<AnkleCandidate>>& clouds,
                                                      int window, double frame_time, const AnklePathOptions& options);

// Gaussian filter over frames.
// One filtered frame: `kernel` (GaussianKernel) centred on t over ankles[0, available). Where the
// kernel reaches past an end, a foot whose step at that end is longer than `edge_fit_step`
// (metres; AnklePathOptions::edge_fit_speed × the frame time, negative = never) is the value at t
// of a line fitted through the frames there are with the kernel's weights (local linear
// regression: the Gaussian itself in the interior, unbiased for steady motion at an end), its
// height kept within the heights those frames had; other feet repeat the end frame.
AnklePair SmoothAnkleAt(const std::vector<AnklePair>& ankles, const std::vector<float>& kernel, int t, int available,
                        float edge_fit_step = -1.0f);
std::vector<AnklePair> SmoothAnkles(const std::vector<AnklePair>& ankles, float sigma_frames,
                                    float edge_fit_step = -1.0f);

}  // namespace mocap
