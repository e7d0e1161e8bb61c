#include "eval/experiments.h"

#include "motion/core/str_cat.h"

namespace mocap::eval {

std::vector<Experiment> MakeExperiments(const ReconstructionOptions& base, double noise_cm, bool ablations) {
  std::vector<Experiment> runs;
  auto add = [&](std::string name, std::string group, double x, ReconstructionOptions options, double noise,
                 bool captured_only = false) {
    runs.push_back(
        {.name = std::move(name),
         .group = std::move(group),
         .x = x,
         .options = options,
         .noise_cm = noise,
         // The baselines are a plain lookup (or pose model) at the database's size.
         .size = options.method == ReconstructionMethod::kFull ? PerformerSize::kService : PerformerSize::kDatabase,
         .captured_only = captured_only});
  };
  add("full", "main", 0, base, noise_cm);
  ReconstructionOptions nn = base;
  nn.method = ReconstructionMethod::kNearestNeighbour;
  nn.joint_smoothing_sigma = 0.0f;  // a plain lookup, as motion matching would return it
  nn.hand_target_sigma = -1.0f;
  nn.motion_guard.enabled = false;  // nor does a lookup guard its motion
  add("nearest_neighbour", "main", 0, nn, noise_cm, true);
  ReconstructionOptions average = nn;
  average.method = ReconstructionMethod::kNearestAverage;  // K = options.average_neighbours (10)
  add("nearest_average", "main", 0, average, noise_cm, true);
  ReconstructionOptions wrists = base;
  wrists.method = ReconstructionMethod::kWristsOnly;
  wrists.hand_target_sigma = -1.0f;  // the patent's baseline: the pose model alone
  wrists.motion_guard.enabled = false;
  add("wrists_only", "main", 0, wrists, noise_cm, true);
  if (!ablations) return runs;
  add("full_captured_only", "main", 0, base, noise_cm, true);  // without the reversed copies
  ReconstructionOptions alike = base;
  alike.pose_neighbour_kernel = 0.0f;  // A5's K2 examples weighed alike (before stop 84)
  add("full_neighbours_alike", "main", 0, alike, noise_cm);
  alike.mode = StreamMode::kFixedLag;
  alike.lag = 5;
  add("lag_5_neighbours_alike", "main", 0, alike, noise_cm);
  ReconstructionOptions no_lean = base;
  no_lean.reach_lean.max_angle = 0.0f;  // the arm IK alone, without the torso's lean
  add("full_no_reach_lean", "main", 0, no_lean, noise_cm);
  ReconstructionOptions no_collars = base;
  no_collars.reach_lean.max_collar_angle = 0.0f;  // the torso leans without the shoulders moving first
  add("full_no_collars", "main", 0, no_collars, noise_cm);
  ReconstructionOptions no_shift = base;
  no_shift.reach_lean.max_shift = 0.0f;  // the lean alone: the body does not step towards the input
  add("full_no_reach_shift", "main", 0, no_shift, noise_cm);
  ReconstructionOptions horizontal = base;
  horizontal.reach_lean.vertical_shift = false;  // the shift over the ground only
  add("full_horizontal_shift", "main", 0, horizontal, noise_cm);
  ReconstructionOptions sinking = base;
  sinking.feet_above_floor = false;  // ankles left where the solve put them, under the floor or not
  add("full_feet_under_floor", "main", 0, sinking, noise_cm);
  ReconstructionOptions trunk_in_floor = base;
  trunk_in_floor.solver.floor_weight = 0.0f;  // A6 without E_floor: the trunk may go under the floor
  add("full_body_under_floor", "main", 0, trunk_in_floor, noise_cm);
  trunk_in_floor.mode = StreamMode::kFixedLag;
  trunk_in_floor.lag = 5;
  add("lag_5_body_under_floor", "main", 0, trunk_in_floor, noise_cm);
  ReconstructionOptions sudden = base;
  sudden.reach_lean.turn_smoothing_seconds = 0.0f;  // the torso's turn follows the input at once
  add("full_unsmoothed_lean", "main", 0, sudden, noise_cm);
  ReconstructionOptions jittery = base;
  jittery.jittery_body_ratio = 0.0f;  // the joint filter widens for weak input only, not a jittering body
  add("full_jittery_body", "main", 0, jittery, noise_cm);
  ReconstructionOptions faster = base;
  faster.reach_lean.max_shift_speed = 0.5f;  // the shift twice as fast
  add("full_shift_speed_0.5", "main", 0, faster, noise_cm);
  ReconstructionOptions gaussian = base;
  gaussian.joint_low_pass = false;  // the joint filter a Gaussian of σ = 1 frame, as at a fixed lag
  add("full_gaussian_joint_filter", "main", 0, gaussian, noise_cm);
  ReconstructionOptions patent_prior = base;
  patent_prior.unfamiliar_prior.max_factor = 1.0f;  // the prior at its configured weight in every session
  add("full_no_unfamiliar_prior", "main", 0, patent_prior, noise_cm);
  patent_prior.mode = StreamMode::kFixedLag;
  patent_prior.lag = 5;
  add("lag_5_no_unfamiliar_prior", "main", 0, patent_prior, noise_cm);
  ReconstructionOptions wide_ankle_filter = base;
  wide_ankle_filter.ankle_path.smoothing_sigma_frames = 2.0f;  // the A4 path's filter before stop 79
  add("full_ankle_sigma_2", "main", 0, wide_ankle_filter, noise_cm);
  for (int lag : {0, 5}) {
    ReconstructionOptions o = base;
    o.mode = StreamMode::kFixedLag;
    o.lag = lag;
    o.ankle_path.edge_fit_speed = -1.0f;  // the ankle filter repeats the path's newest frame (before stop 67)
    add(StrCat("lag_", lag, "_clamped_ankle_edges"), "main", 0, o, noise_cm);
    o = base;
    o.mode = StreamMode::kFixedLag;
    o.lag = lag;
    o.footskate.stream_plant_ankles = false;  // A6 given the decided ankles unplanted (before stop 74)
    add(StrCat("lag_", lag, "_unplanted_ankles"), "main", 0, o, noise_cm);
    o = base;
    o.mode = StreamMode::kFixedLag;
    o.lag = lag;
    o.footskate.resume_where_released = false;  // a contact resumed mid-release pinned at the solve (before stop 78)
    add(StrCat("lag_", lag, "_resumed_at_solve"), "main", 0, o, noise_cm);
    o = base;
    o.mode = StreamMode::kFixedLag;
    o.lag = lag;
    o.footskate.stream_stands_on_either_hand = false;  // feet held by the hands' midpoint alone (before stop 82)
    add(StrCat("lag_", lag, "_midpoint_stands"), "main", 0, o, noise_cm);
    o = base;
    o.mode = StreamMode::kFixedLag;
    o.lag = lag;
    o.pelvis_edge_fit = false;  // the joint filter repeats the newest frame for the pelvis too (before stop 86)
    add(StrCat("lag_", lag, "_clamped_pelvis"), "main", 0, o, noise_cm);
  }
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

std::vector<Experiment> MakeDeviceExperiments(const ReconstructionOptions& base, bool every_run) {
  std::vector<Experiment> main = MakeExperiments(base, 0.0, every_run);
  std::vector<Experiment> runs;
  std::vector<DeviceModel> devices = StandardDevices();
  for (const DeviceModel& dropout : DropoutDevices()) devices.push_back(dropout);
  for (const DeviceModel& held : HeldDevices()) devices.push_back(held);
  for (const DeviceModel& device : devices) {
    for (const Experiment& e : main) {
      if (e.group == "noise" || (!every_run && e.name != "full" && e.name != "nearest_neighbour")) continue;
      ReconstructionOptions options = e.options;
      // A device held in the hand is declared as its user would (`--grip-offset`).
      if (device.grip_declared) options.grip_offset = static_cast<float>(device.grip_offset_m);
      runs.push_back({.name = StrCat(e.name, "@", device.name),
                      .group = "device",
                      .options = options,
                      .noise_cm = 0.0,
                      .device = device,
                      .size = e.size,
                      .captured_only = e.captured_only});
    }
  }
  return runs;
}

}  // namespace mocap::eval
