// Device-like input (issue #22): what real trackers send, made from a test clip's true wrists, so
// accuracy and plausibility can be measured where users are: controllers that quantise and repeat,
// phone AR that jitters and drifts, trackers that drop out.
#pragma once

#include <string>
#include <vector>

#include "eval/landmark_metrics.h"
#include "motion/reconstruct/wrist_resampler.h"

namespace mocap::eval {

// How the user holds the body the clip's wrists came from. Other than as captured, the input is no
// longer the capture's motion: accuracy is not measured, only what needs no truth (plausibility).
enum class Posture {
  kAsCaptured,
  kSeated,   // on a chair where the clip starts: the pelvis' travel over the ground taken out of the
             // wrists and the upper body lowered by half the standing pelvis height (above the ankles
             // at the start; no hand lower than those ankles)
  kAtADesk,  // seated, hands resting on a desk at 3/4 of the standing pelvis height where they
             // would go lower
};

struct DeviceModel {
  std::string name;                         // empty: the lab input (the clip's own rate, Gaussian noise)
  double rate_hz = 0;                       // samples per second (0: the clip's own frame rate)
  double jitter_m = 0;                      // Gaussian σ per axis and sample
  double drift_m_per_sqrt_s = 0;            // each hand's slow drift: a random walk of this σ per √second
  double quantisation_m = 0;                // positions rounded to this grid (0: none)
  double repeat_fraction = 0;               // samples where the tracker did not update: the previous one again
  double gap_every_s = 0;                   // dropouts, one on average every this many seconds (0: none)
  double gap_min_s = 0.1, gap_max_s = 2.0;  // each dropout's length, uniform
  double dropout_s = 0;                     // one dropout of this length from 40% into the clip (0: none)
  double left_hand_lost_s = 0;              // the left hand alone lost this long from 40% into the clip (0: none)
  // The left controller set down this many seconds into the clip, for good (0: never): its input
  // stays where the left wrist was then, with the device's jitter, while the person goes on.
  double left_set_down_s = 0;
  // The tracked point is the device's, held in the hand: this far beyond the wrist along the
  // forearm (elbow to wrist), where a phone's or a controller's centre sits in a closed grip.
  double grip_offset_m = 0;
  bool grip_declared = true;  // the run declares the grip (ReconstructionOptions::grip_offset), as its user would
  double time_jitter_s = 0;   // each sample's timestamp off by this σ (arrival times), kept increasing
  Posture posture = Posture::kAsCaptured;
  bool accuracy_measured() const { return posture == Posture::kAsCaptured; }
};

// The devices every report measures (named in docs/evaluation.md's table):
//   controllers_72hz  two VR controllers: 72 Hz, 1 cm quantisation, half the samples repeated
//   tracker_90hz      a 90 Hz optical tracker: 3 mm jitter, 1 mm quantisation
//   phone_ar          two phones' AR tracking: 60 Hz, 2.5 cm jitter, 1 cm/√s drift
//   dropouts          60 Hz, 5 mm jitter, a 0.1-2 s gap every 4 s on average
//   seated            tracker_90hz on a seated user (Posture::kSeated; plausibility only)
//   desk              tracker_90hz on a seated user's hands over a desk (Posture::kAtADesk; the same)
std::vector<DeviceModel> StandardDevices();
// One dropout of each length the tracking states are judged on (issue #25: 0.2-5 s), in input
// otherwise like `dropouts`' (60 Hz, 5 mm jitter): dropout_0.2s, dropout_0.5s, dropout_1s,
// dropout_2s, dropout_5s; and the left hand alone lost for 1, 2 and 5 s while the right is tracked
// (left_hand_lost_1s, _2s, _5s; the lost hand's samples are NaN, tracked = false); and the left
// controller set down 1 s into the clip, for good (left_controller_put_down: 72 Hz, 2 mm jitter).
std::vector<DeviceModel> DropoutDevices();
// Devices whose tracked point or clock is not the wrist's (issue #22: devices never seen):
//   phone_in_hand  a phone held in each hand: 60 Hz, 1 cm jitter, the point 9 cm beyond the wrist
//                  along the forearm, declared (--grip-offset 0.09); phone_in_hand_undeclared: not
//   camera_30hz    hand tracking from a camera: 30 Hz, 1.5 cm jitter, timestamps 8 ms off (σ)
std::vector<DeviceModel> HeldDevices();

// The samples `device` would send for `truth`'s wrists (from time 0 to the clip's end), drawn from
// `seed`. The lab input (device.name empty) is the clip's own frames plus noise of σ `noise_cm`.
std::vector<WristSample> DeviceSamples(const LandmarkTruth& truth, const DeviceModel& device, double noise_cm,
                                       unsigned seed);

}  // namespace mocap::eval
