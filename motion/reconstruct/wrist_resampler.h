// Input conditioning for a reconstruction: timestamped wrist samples at any rate → samples on the
// database's frame grid (linear interpolation). A dropout up to `max_gap` seconds is bridged by
// interpolation; a longer one ends the segment and a new grid starts at the next sample.
// Non-finite samples and timestamps that do not increase are refused (the resampler's state is
// unchanged, so the caller may continue with the next good sample).
//
// A tracker that did not update resends its last position with a new time (controllers at 72 Hz,
// a phone whose pose estimate stalled). Taken as input, such a repeat stops the hand for a sample
// and makes it catch up at the next: a speed and acceleration the hand never had, which the A2 fit
// and the jump detector read as motion. So a tracked hand's exact repeat of its last new position
// within `kRepeatHoldSeconds` of that position's time is no sample of that hand: its grid frames
// wait for the hand's next new position and are interpolated towards it. A repeat later than that
// is input (a still hand on a quantised device repeats itself for as long as it is still). The
// wait adds at most `kRepeatHoldSeconds` of latency, only while a hand repeats; Flush gives what
// waits at the end of a stream. docs/method.md A2 has the figures that chose 0.1 s.
#pragma once

#include <array>
#include <deque>
#include <vector>

#include <Eigen/Core>

#include "absl/status/status.h"

namespace mocap {

struct WristSample {
  double time = 0.0;                               // seconds, any origin; strictly increasing
  Eigen::Vector3f left = Eigen::Vector3f::Zero();  // metres, world Y up
  Eigen::Vector3f right = Eigen::Vector3f::Zero();
  // False: the tracker lost that hand (its position is ignored; the session holds it by the other
  // hand, one_hand_bridge.h). A sample needs at least one tracked hand.
  std::array<bool, 2> tracked{true, true};  // left, right
};

// A hand whose position is still partly a guess although its input is real again: OneHandBridge's
// cross-fade after the hand comes back. `weight`: the guess's share of the position (1 → 0 over
// the fade; 0 otherwise); `seconds`: since the hand was last tracked before it was lost.
struct FadingGuess {
  float weight = 0;
  float seconds = 0;
};

struct GridSample {
  bool starts_segment = false;  // the previous segment (if any) ended before this sample
  bool bridged = false;         // interpolated across a dropout longer than two sample periods
  // Per hand (left, right), how long its input has not been real: across a bridged dropout the
  // seconds to the nearer real sample; for a hand held by the other (OneHandBridge) the seconds
  // since it was last tracked; 0 when tracked.
  std::array<float, 2> untracked_seconds{};
  std::array<FadingGuess, 2> fading_guess{};  // per hand, interpolated like the positions
  // Per hand: its device lies put down (hand_rest.h) and the position is OneHandBridge's guess;
  // the nearer input sample's.
  std::array<bool, 2> put_down{};
  double time = 0.0;
  Eigen::Vector3f left, right;
};

class WristResampler {
 public:
  static constexpr double kRepeatHoldSeconds = 0.1;  // 7 samples at 72 Hz, 3 at 30 Hz

  WristResampler(double frame_time, double max_gap_seconds);
  // InvalidArgument for a sample Push would refuse: a time not finite or not after the previous
  // sample's, a tracked hand's position not finite (a lost hand's is not read).
  absl::Status Check(const WristSample& sample) const;
  // Appends the grid samples this input sample completes. `untracked_seconds`, `fading_guess`:
  // the sample's own (OneHandBridge), interpolated onto the grid like its positions; `put_down`:
  // the sample's put-down hands, the nearer sample's on the grid.
  absl::Status Push(const WristSample& sample, std::vector<GridSample>* out,
                    std::array<float, 2> untracked_seconds = {}, std::array<FadingGuess, 2> fading_guess = {},
                    std::array<bool, 2> put_down = {});
  // Appends the grid samples still waiting for a repeating hand's next position, that hand held
  // at its last position (the end of the input: nothing newer will come).
  void Flush(std::vector<GridSample>* out);
  // Hand-samples taken for a tracker's repeat (not as input) since the resampler was made.
  long repeated_hand_samples() const { return repeated_hand_samples_; }
  // Forgets the input; what waits is dropped (Flush first to keep it).
  void Reset() {
    has_previous_ = false;
    waiting_.clear();
  }

 private:
  // A hand's last new position and its time (a repeat within kRepeatHoldSeconds is not one).
  struct Anchor {
    double time = 0.0;
    Eigen::Vector3f position = Eigen::Vector3f::Zero();
    bool real = false;  // tracked input, not a position OneHandBridge guessed or faded
  };
  bool IsRepeat(int side, const Eigen::Vector3f& position, double time, bool real) const;
  // Moves a hand's anchor to a new position, interpolating the waiting grid frames it completes.
  void Advance(int side, const Anchor& next);
  // Appends the waiting grid frames both hands' positions have reached (all with `flush`).
  void Release(bool flush, std::vector<GridSample>* out);

  // A grid time this close after a sample is that sample's: 1% of a frame (see Push).
  double Slack() const { return 0.01 * frame_time_; }

  double frame_time_, max_gap_;
  bool has_previous_ = false;
  WristSample previous_;
  std::array<float, 2> previous_untracked_{};
  std::array<FadingGuess, 2> previous_fading_{};
  std::array<bool, 2> previous_put_down_{};
  double typical_period_ = 0.0;
  long next_index_ = 0;  // next grid frame, counted from grid_origin_
  double grid_origin_ = 0.0;
  std::array<Anchor, 2> anchors_;
  std::deque<GridSample> waiting_;  // grid frames after a repeating hand's anchor, oldest first
  long repeated_hand_samples_ = 0;
};

}  // namespace mocap
