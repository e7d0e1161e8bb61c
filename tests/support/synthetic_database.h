// A reconstruction database built from synthetic walking clips (tests/support/synthetic_clip.h),
// and a test clip with its ground truth, for unit tests of docs/method.md A3–A7.
#pragma once

#include <memory>
#include <vector>

#include "motion/preprocess/clip_preprocessor.h"
#include "motion/reconstruct/local_pose_model.h"
#include "motion/reconstruct/reconstruction_database.h"
#include "motion/reconstruct/wrist_resampler.h"
#include "motion/skeleton/forward_kinematics.h"
#include "tests/support/synthetic_clip.h"

namespace mocap::testing {

struct SyntheticReconstructionSetup {
  RigModel rig;
  std::shared_ptr<const ReconstructionDatabase> database;
  PreparedClip test_clip;  // another walk, not in the database
  GlobalPoses truth;       // its forward kinematics (metres, Y up)
};

SyntheticReconstructionSetup MakeSyntheticReconstructionSetup(const SyntheticRigOptions& options = {},
                                                              int test_frames = 75);

// A setup of the default rig with a 30-frame test clip, made on first use and kept for the
// process (the fuzz targets build it once, not per input).
const SyntheticReconstructionSetup& SharedSyntheticReconstructionSetup();

// The test clip's wrists as timestamped samples (database rate, starting at `start_time`).
std::vector<WristSample> WristSamplesOf(const SyntheticReconstructionSetup& setup, double start_time = 0.0);

// A5's local model of test frame `frame`: the `neighbours` database frames nearest to its true
// wrists and ankles (eq. 8), `components` principal components.
LocalPoseModel LocalModelAtTestFrame(const SyntheticReconstructionSetup& setup, int frame, int neighbours = 60,
                                     int components = 6);

}  // namespace mocap::testing
