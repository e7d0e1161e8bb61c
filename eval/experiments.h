// The runs mocap-eval makes: the full method, the three baselines (nearest neighbour, average of
// the 10 nearest, wrists-only pose model), and the ablations of issue #3 (window L, noise σ, lag D).
#pragma once

#include <string>
#include <vector>

#include "eval/device_input.h"
#include "motion/reconstruct/reconstruction_options.h"

namespace mocap::eval {

// Whose size the body takes (landmark tests; issue #22 "performer's size"): the database's (the
// method as specified), or the performer's, the input scaled to the database's body and the
// output back. kTruth is an oracle (the capture's own bone lengths): how much size can explain.
// kLowerWrist estimates it from the input alone: the median height of the lower wrist against the
// database's (hands hang at a height proportional to the body's).
// kWalkingWrists the same over the frames where the wrists' midpoint moves on at walking speed
// (≥ 0.6 m/s over the ground: the arms swing about where they hang); the database's size when the
// input has less than a second of such frames.
// kDatabaseFit: the factor that brings the input's wrist features nearest the database's
// (motion/reconstruct/performer_scale.h).
// kReach: one-sided, from how far the wrists reach (motion/reconstruct/wrist_reach.h): where they
// spend a twentieth of the input further apart or higher than the database's bodies ever held
// theirs, the performer is that much larger; otherwise the database's size.
// kOnline: the same bound as the input streams in (motion/reconstruct/body_sizer.h): the
// database's size until the reach asks for more, then eased towards it.
// kService: as the service sizes the body when no height is declared
// (SessionConfig.estimate_performer_height, on by default in `mocap reconstruct`): kReach for a
// whole trajectory, kOnline in the streaming modes, whose frames leave before the input has shown
// its reach.
// kDeclared: the service's SessionConfig.performer_height path, as a user who knows their height
// uses it: the performer's height (told from the capture's legs as EstimatedStature tells the
// database's) with a 3% error (σ, one draw per clip), against the database body's EstimatedStature.
enum class PerformerSize {
  kDatabase,
  kTruth,
  kLowerWrist,
  kWalkingWrists,
  kDatabaseFit,
  kDeclared,
  kReach,
  kOnline,
  kService
};

struct Experiment {
  std::string name;
  std::string group;  // "main", "window", "noise", "lag"
  double x = 0;       // the ablated value (L, σ in cm, D)
  ReconstructionOptions options;
  double noise_cm = 0.5;
  DeviceModel device;  // the input (landmark tests only; empty name: the lab's, noise_cm)
  PerformerSize size = PerformerSize::kService;
  // Search the captured frames only, without the travelling frames played backwards (DatabaseBuildOptions):
  // the lookup baselines, and the ablation row of the method without them.
  bool captured_only = false;
};

std::vector<Experiment> MakeExperiments(const ReconstructionOptions& base, double noise_cm, bool ablations);
// The full method and the nearest neighbour on each of StandardDevices()' and DropoutDevices()'
// input, group "device", named "full@DEVICE" and "nearest_neighbour@DEVICE"; with `every_run`,
// every run of MakeExperiments (ablations, windows and lags; not the noise levels, which the
// device replaces) as "RUN@DEVICE", for `--runs` to choose from.
std::vector<Experiment> MakeDeviceExperiments(const ReconstructionOptions& base, bool every_run = false);

}  // namespace mocap::eval
