#include "eval/experiments.h"

#include "motion/core/str_cat.h"

namespace mocap::eval {

std::vector<Experiment> MakeExperiments(const ReconstructionOptions& base, double noise_cm, bool ablations) {
  std::vector<Experiment> runs;
  auto add = [&](std::string name, std::string group, double x, ReconstructionOptions options, double noise) {
    runs.push_back({std::move(name), std::move(group), x, options, noise});
  };
  add("full", "main", 0, base, noise_cm);
  ReconstructionOptions nn = base;
  nn.method = ReconstructionMethod::kNearestNeighbour;
  nn.joint_smoothing_sigma = 0.0f;  // a plain lookup, as motion matching would return it
  nn.hand_target_sigma = -1.0f;
  nn.motion_guard.enabled = false;  // nor does a lookup guard its motion
  add("nearest_neighbour", "main", 0, nn, noise_cm);
  ReconstructionOptions average = nn;
  average.method = ReconstructionMethod::kNearestAverage;  // K = options.average_neighbours (10)
  add("nearest_average", "main", 0, average, noise_cm);
  ReconstructionOptions wrists = base;
  wrists.method = ReconstructionMethod::kWristsOnly;
  wrists.hand_target_sigma = -1.0f;  // the patent's baseline: the pose model alone
  wrists.motion_guard.enabled = false;
  add("wrists_only", "main", 0, wrists, noise_cm);
  if (!ablations) return runs;
  for (int window : {10, 50, 100}) {
    ReconstructionOptions o = base;
    o.window = window;
    add(StrCat("window_", window), "window", window, o, noise_cm);
  }
  for (double noise : {0.0, 1.0, 2.0}) add(StrCat("noise_", noise, "cm"), "noise", noise, base, noise);
  for (int lag : {0, 5, 15, 30}) {
    ReconstructionOptions o = base;
    o.mode = StreamMode::kFixedLag;
    o.lag = lag;
    add(StrCat("lag_", lag), "lag", lag, o, noise_cm);
  }
  return runs;
}

std::vector<Experiment> MakeDeviceExperiments(const ReconstructionOptions& base) {
  std::vector<Experiment> main = MakeExperiments(base, 0.0, false);
  std::vector<Experiment> runs;
  for (const DeviceModel& device : StandardDevices()) {
    for (const Experiment& e : main) {
      if (e.name != "full" && e.name != "nearest_neighbour") continue;
      runs.push_back({StrCat(e.name, "@", device.name), "device", 0, e.options, 0.0, device, PerformerSize::kDatabase});
    }
  }
  return runs;
}

}  // namespace mocap::eval
