// The runs mocap-eval makes: the full method, the three baselines (nearest neighbour, average of
// the 10 nearest, wrists-only pose model), and the ablations of issue #3 (window L, noise σ, lag D).
#pragma once

#include <string>
#include <vector>

#include "motion/reconstruct/reconstruction_options.h"

namespace mocap::eval {

struct Experiment {
  std::string name;
  std::string group;  // "main", "window", "noise", "lag"
  double x = 0;       // the ablated value (L, σ in cm, D)
  ReconstructionOptions options;
  double noise_cm = 0.5;
};

std::vector<Experiment> MakeExperiments(const ReconstructionOptions& base, double noise_cm, bool ablations);

}  // namespace mocap::eval
