#include "eval/device_input.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>

#include "eval/evaluation.h"

namespace mocap::eval {

std::vector<DeviceModel> StandardDevices() {
  return {
      {.name = "controllers_72hz", .rate_hz = 72, .quantisation_m = 0.01, .repeat_fraction = 0.5},
      {.name = "tracker_90hz", .rate_hz = 90, .jitter_m = 0.003, .quantisation_m = 0.001},
      {.name = "phone_ar", .rate_hz = 60, .jitter_m = 0.025, .drift_m_per_sqrt_s = 0.01},
      {.name = "dropouts", .rate_hz = 60, .jitter_m = 0.005, .gap_every_s = 4.0},
      {.name = "seated", .rate_hz = 90, .jitter_m = 0.003, .quantisation_m = 0.001, .posture = Posture::kSeated},
      {.name = "desk", .rate_hz = 90, .jitter_m = 0.003, .quantisation_m = 0.001, .posture = Posture::kAtADesk},
  };
}

std::vector<DeviceModel> DropoutDevices() {
  std::vector<DeviceModel> devices;
  for (const auto& [name, seconds] : std::vector<std::pair<const char*, double>>{{"dropout_0.2s", 0.2},
                                                                                 {"dropout_0.5s", 0.5},
                                                                                 {"dropout_1s", 1.0},
                                                                                 {"dropout_2s", 2.0},
                                                                                 {"dropout_5s", 5.0}}) {
    devices.push_back({.name = name, .rate_hz = 60, .jitter_m = 0.005, .dropout_s = seconds});
  }
  // One hand lost, the other tracked (issue #25 item 2): the same lengths as the dropouts above.
  for (const auto& [name, seconds] : std::vector<std::pair<const char*, double>>{
           {"left_hand_lost_1s", 1.0}, {"left_hand_lost_2s", 2.0}, {"left_hand_lost_5s", 5.0}}) {
    devices.push_back({.name = name, .rate_hz = 60, .jitter_m = 0.005, .left_hand_lost_s = seconds});
  }
  devices.push_back({.name = "left_controller_put_down", .rate_hz = 72, .jitter_m = 0.002, .left_set_down_s = 1.0});
  return devices;
}

std::vector<DeviceModel> HeldDevices() {
  return {
      {.name = "phone_in_hand", .rate_hz = 60, .jitter_m = 0.01, .grip_offset_m = 0.09},
      {.name = "phone_in_hand_undeclared",
       .rate_hz = 60,
       .jitter_m = 0.01,
       .grip_offset_m = 0.09,
       .grip_declared = false},
      {.name = "camera_30hz", .rate_hz = 30, .jitter_m = 0.015, .time_jitter_s = 0.008},
  };
}

namespace {

// The wrists of `landmarks` as `posture` would put them (device_input.h). `start`: the clip's
// first frame, whose pelvis height above its lower ankle sizes the chair and the desk.
std::array<Eigen::Vector3f, 2> WristsIn(Posture posture,
                                        const std::array<Eigen::Vector3f, kNumScoredLandmarks>& landmarks,
                                        const std::array<Eigen::Vector3f, kNumScoredLandmarks>& start) {
  std::array<Eigen::Vector3f, 2> wrists = {landmarks[kLeftWristLandmark], landmarks[kRightWristLandmark]};
  if (posture == Posture::kAsCaptured) return wrists;
  const float ankles = std::min(start[kLeftAnkleLandmark].y(), start[kRightAnkleLandmark].y());
  const float leg = start[kPelvisLandmark].y() - ankles;
  const Eigen::Vector3f travel = landmarks[kPelvisLandmark] - start[kPelvisLandmark];
  for (Eigen::Vector3f& wrist : wrists) {
    wrist.x() -= travel.x();
    wrist.z() -= travel.z();
    // A chair's seat at half the standing pelvis height; a hand that reached for the floor stops
    // there (no lower than the standing ankles).
    wrist.y() = std::max(wrist.y() - 0.5f * leg, ankles);
    if (posture == Posture::kAtADesk) wrist.y() = std::max(wrist.y(), ankles + 0.75f * leg);
  }
  return wrists;
}

}  // namespace

std::vector<WristSample> DeviceSamples(const LandmarkTruth& truth, const DeviceModel& device, double noise_cm,
                                       unsigned seed) {
  if (device.name.empty() || truth.num_frames() < 2) {
    return NoisyWristSamples(
        truth.num_frames(), truth.frame_time,
        [&](int f) {
          return std::array<Eigen::Vector3f, 2>{truth.positions[f][kLeftWristLandmark],
                                                truth.positions[f][kRightWristLandmark]};
        },
        noise_cm, seed);
  }
  std::mt19937 random(seed);
  std::normal_distribution<float> gaussian(0.0f, 1.0f);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double dt = device.rate_hz > 0 ? 1.0 / device.rate_hz : truth.frame_time;
  const double end = (truth.num_frames() - 1) * truth.frame_time;
  std::array<Eigen::Vector3f, 2> drift{Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()};
  auto noise_vector = [&](double sigma) {
    Eigen::Vector3f v;
    for (int axis = 0; axis < 3; ++axis) v[axis] = gaussian(random) * static_cast<float>(sigma);  // in axis order
    return v;
  };
  std::vector<WristSample> samples;
  double gap_until = -1;
  std::optional<Eigen::Vector3f> set_down;  // where the left controller lies
  for (long i = 0; i * dt <= end + 1e-9; ++i) {
    const double t = i * dt;
    for (auto& d : drift) d += noise_vector(device.drift_m_per_sqrt_s * std::sqrt(dt));
    if (device.gap_every_s > 0 && t > gap_until && uniform(random) < dt / device.gap_every_s) {
      gap_until = t + device.gap_min_s + (device.gap_max_s - device.gap_min_s) * uniform(random);
    }
    if (t < gap_until) continue;  // the tracker lost the hands: nothing is sent
    if (device.dropout_s > 0 && t >= 0.4 * end && t < 0.4 * end + device.dropout_s) continue;
    if (!samples.empty() && uniform(random) < device.repeat_fraction) {
      WristSample repeated = samples.back();  // the tracker did not update: same positions, new time
      repeated.time = t;
      samples.push_back(repeated);
      continue;
    }
    const std::array<Eigen::Vector3f, kNumScoredLandmarks> landmarks = LandmarksAt(truth, t);
    std::array<Eigen::Vector3f, 2> at = WristsIn(device.posture, landmarks, truth.positions.front());
    if (device.grip_offset_m > 0) {
      for (int hand = 0; hand < 2; ++hand) {
        const Eigen::Vector3f forearm = landmarks[kLeftWristLandmark + hand] - landmarks[kLeftElbowLandmark + hand];
        if (forearm.norm() > 1e-3f) at[hand] += static_cast<float>(device.grip_offset_m) * forearm.normalized();
      }
    }
    if (device.left_set_down_s > 0 && t >= device.left_set_down_s) {
      if (!set_down) set_down = at[0];
      at[0] = *set_down;
    }
    for (int hand = 0; hand < 2; ++hand) {
      at[hand] += drift[hand] + noise_vector(device.jitter_m);
      if (device.quantisation_m > 0) {
        const float q = static_cast<float>(device.quantisation_m);
        at[hand] = (at[hand] / q).array().round().matrix() * q;
      }
    }
    double stamp = t;
    if (device.time_jitter_s > 0) {
      // Arrival times: off by the jitter, never before the previous sample's.
      stamp = t + device.time_jitter_s * gaussian(random);
      if (!samples.empty()) stamp = std::max(stamp, samples.back().time + 1e-4);
      stamp = std::max(stamp, 0.0);
    }
    WristSample sample{.time = stamp, .left = at[0], .right = at[1]};
    if (device.left_hand_lost_s > 0 && t >= 0.4 * end && t < 0.4 * end + device.left_hand_lost_s) {
      sample.tracked[0] = false;  // what a lost tracker sends is not to be read
      sample.left = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
    }
    samples.push_back(sample);
  }
  return samples;
}

}  // namespace mocap::eval
