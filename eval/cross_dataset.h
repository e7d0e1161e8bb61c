// Tests beyond the lab (issue #22): clips on any rig, rate and unit, scored on body landmarks
// (landmark_metrics.h), and the cross-dataset protocol of shared/data/README: database = all of
// bandai-namco-2; tests = every bandai-namco-1 clip, every cmu-cc clip and the other-rigs clips
// that move.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "eval/datasets/shared_data.h"
#include "eval/evaluation.h"
#include "eval/experiments.h"
#include "eval/landmark_metrics.h"

namespace mocap::eval {

struct LandmarkTestClip {
  std::string name;     // file name
  std::string source;   // the set it comes from ("bandai-namco-1", "cmu-cc", "other-rigs", "named")
  std::string content;  // what it shows, within the source ("walk", "dance", "xia", ...)
  LandmarkTruth truth;
};

// One clip on its own rig: unit detected, turned Y up, at its own frame rate, cut to `max_frames`
// (0 = whole). FailedPrecondition when the analysis finds no place for a scored landmark.
absl::StatusOr<LandmarkTestClip> LoadLandmarkTestClip(const std::filesystem::path& file, std::string source,
                                                      std::string content, int max_frames);

// Whether any landmark leaves its first-frame place by 5 cm or more (other-rigs' T-poses do not).
bool Moves(const LandmarkTruth& truth);

struct LandmarkTestSet {
  std::vector<LandmarkTestClip> clips;
  std::vector<std::string> left_out;  // "file: why", for clips that do not move or cannot be scored
};

// Named files, source "named", content from the file name's labels (else "other"). `body_scale`:
// every performer this much larger (each landmark's position scaled about the origin, so the bones
// and the root's path over the floor grow alike): people of other sizes from one set of takes.
absl::StatusOr<LandmarkTestSet> LoadLandmarkTests(const std::vector<std::filesystem::path>& files, int max_frames,
                                                  float body_scale = 1.0f);
// The protocol's tests (unpacking the sets as needed); NotFound when a set is unavailable.
absl::StatusOr<LandmarkTestSet> LoadCrossDatasetTests(const datasets::DataLocation& data, int max_frames);

struct LandmarkClipResult {
  std::string name, source, content;
  LandmarkBodySize size;  // the performer's
  LandmarkMetrics metrics;
  float input_scale = 1.0f;                 // what the input was multiplied by (PerformerSize)
  float truth_scale = 1.0f;                 // the oracle's factor: database body / the performer's
  std::vector<float> fit_scales, fit_cost;  // kDatabaseFit's fit at each candidate scale
};

struct LandmarkExperimentResult {
  Experiment experiment;
  LandmarkMetrics overall;
  std::map<std::string, LandmarkMetrics> by_source;
  std::map<std::string, LandmarkMetrics> by_content;  // keyed "source/content"
  std::vector<LandmarkClipResult> clips;              // in test order
  ConfidenceSummary confidence;                       // the expected landmark errors against the actual
  std::map<std::string, ConfidenceSummary> confidence_by_source;
};

// Every test's wrists (its own rate, plus the experiment's noise, one seed per clip) through every
// experiment, scored on landmarks. The "full" run's confidence samples go to
// `confidence_samples` unless it is empty.
absl::StatusOr<std::vector<LandmarkExperimentResult>> RunLandmarkEvaluation(
    const EvaluationDatabases& databases, const std::vector<LandmarkTestClip>& tests,
    const std::vector<Experiment>& experiments, unsigned seed, int threads,
    const std::filesystem::path& confidence_samples, const std::function<void(const std::string&)>& progress);

}  // namespace mocap::eval
