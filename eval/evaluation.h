// mocap-eval's engine: loads a database and test clips, reconstructs every test clip's wrists
// (forward kinematics plus Gaussian noise, fixed seed) with every experiment, and measures.
#pragma once

#include <array>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "eval/confidence_calibration.h"
#include "eval/eval_metrics.h"
#include "eval/experiments.h"
#include "motion/reconstruct/reconstruction_database.h"

namespace mocap::eval {

struct TestClip {
  std::string name;     // file name
  std::string content;  // content label (e.g. "walk"), prefixed by the set for extra sets
  PreparedClip clip;
  GlobalPoses truth;
};

// How many of `tests` reach beyond the database's bodies (InputScaleFromReach < 1 on their clean
// wrists): the clips the service would size larger as a whole trajectory.
int ClipsSizedByReach(const ReconstructionDatabase& database, const std::vector<TestClip>& tests);

struct ClipResult {
  std::string name;  // test file name
  std::string content;
  Metrics metrics;
};

struct ExperimentResult {
  Experiment experiment;
  Metrics overall;
  std::map<std::string, Metrics> by_content;
  std::vector<ClipResult> clips;  // in test order
  ConfidenceSummary confidence;   // the expected landmark errors against the actual
};

// Database from BVH files (all cores), built as the service builds it. The rig comes from the
// first file.
absl::StatusOr<std::shared_ptr<const ReconstructionDatabase>> LoadDatabase(
    const std::vector<std::filesystem::path>& files);

// The databases an evaluation searches, built from the same files: the method's, as the service
// builds it (the travelling frames also played backwards), and the captured frames alone, which the lookup
// baselines search, as a plain motion-matching lookup of the imported motion would
// (Experiment::captured_only).
struct EvaluationDatabases {
  std::shared_ptr<const ReconstructionDatabase> method, captured;
  // The captured frames' whole A1 features, in row order (the databases keep only what the
  // reconstruction reads of them: DatabaseFrame).
  std::vector<FrameFeatures> captured_features;
  const std::shared_ptr<const ReconstructionDatabase>& For(const Experiment& experiment) const {
    return experiment.captured_only ? captured : method;
  }
};
absl::StatusOr<EvaluationDatabases> LoadDatabases(const std::vector<std::filesystem::path>& files,
                                                  const DatabaseBuildOptions& options = {});
// Test clips on `rig`, cut to `max_frames` (0 = whole). Clips on another rig are an error.
// `body_scale` ≠ 1 makes each performer that much larger (every bone and the root's path; the
// rotations kept): people of other sizes on the database's own motion (mocap-eval --test-body-scale).
absl::StatusOr<std::vector<TestClip>> LoadTestClips(const std::vector<std::filesystem::path>& files,
                                                    const RigModel& rig, int max_frames,
                                                    const std::string& content_prefix, float body_scale = 1.0f);

// The input a test gives the engine: `frames` samples `frame_time` apart from time 0, the wrists of
// each frame (left, right; metres, Y up) plus Gaussian noise of σ `noise_cm` drawn from `seed`.
std::vector<WristSample> NoisyWristSamples(int frames, double frame_time,
                                           const std::function<std::array<Eigen::Vector3f, 2>(int)>& wrists,
                                           double noise_cm, unsigned seed);

struct EvaluationConfig {
  unsigned seed = 1;
  int threads = 2;
  std::filesystem::path
      bvh_dir;  // where the "full" run's reconstructions go (the captured clips in truth/); empty = nowhere
  // Where the "full" run's confidence samples go (WriteConfidenceSamples); empty = nowhere.
  std::filesystem::path confidence_samples;
};

absl::StatusOr<std::vector<ExperimentResult>> RunEvaluation(const EvaluationDatabases& databases,
                                                            const std::vector<TestClip>& tests,
                                                            const std::vector<Experiment>& experiments,
                                                            const EvaluationConfig& config,
                                                            const std::function<void(const std::string&)>& progress);

}  // namespace mocap::eval
