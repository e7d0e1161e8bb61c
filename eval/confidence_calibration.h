// How well the engine's expected landmark errors (motion/reconstruct/landmark_confidence.h, issue
// #25 item 1) predict the errors it makes: every scored (frame, landmark) gives a pair, summarised
// as Spearman rank correlations and a reliability table (predicted against actual error, binned
// on the predicted).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "absl/status/status.h"
#include "motion/reconstruct/reconstruction_session.h"

namespace mocap::eval {

struct ConfidenceSample {
  float predicted = 0, actual = 0;  // metres
  std::uint8_t landmark = 0;        // BodyLandmarkJoints order
  // What it was told from, for fitting the calibration (landmark_confidence.h ConfidenceCues).
  ConfidenceCues cues;
  int clip = 0;                           // test clip index
  int segment = 0, frame_in_segment = 0;  // where in the session (ReconstructedFrame's)
};

// The pair for each landmark of `frame` (predicted: its landmark_error, multiplied by `scale` as
// the output's positions were) against the truth's positions of the same landmarks.
void AddConfidenceSamples(const ReconstructedFrame& frame, float scale,
                          const std::array<Eigen::Vector3f, kNumBodyLandmarks>& output,
                          const std::array<Eigen::Vector3f, kNumBodyLandmarks>& truth,
                          std::vector<ConfidenceSample>* samples);

struct ReliabilityBin {
  double predicted = 0, actual = 0;  // mean, metres
  long count = 0;
};

struct ConfidenceSummary {
  long samples = 0;
  double spearman = 0;  // over every (frame, landmark) pair
  // Within each landmark alone (how much the cues say beyond which landmark it is), then their
  // mean.
  std::array<double, kNumBodyLandmarks> spearman_by_landmark{};
  double spearman_within_landmarks = 0;
  std::vector<ReliabilityBin> bins;  // equal counts, by predicted error
  // The largest factor between a bin's mean actual and mean predicted error (either way round).
  double worst_bin_ratio = 0;
};

// Empty summary (samples = 0) for no samples.
ConfidenceSummary SummariseConfidence(const std::vector<ConfidenceSample>& samples, int bins = 10);

// Where `--confidence-samples FILE` puts a run's samples: FILE for the full run, FILE's stem + "." +
// the run's name + its extension for the others (the device runs: dropout_2s → FILE.dropout_2s.csv).
std::filesystem::path ConfidenceSamplesFile(const std::filesystem::path& file, const std::string& run);

// One line per sample (clip, landmark name, predicted, actual, then the cues) for fitting the
// calibration offline (docs/method.md "Confidence").
absl::Status WriteConfidenceSamples(const std::vector<ConfidenceSample>& samples, const std::filesystem::path& file);

nlohmann::json ConfidenceJson(const ConfidenceSummary& summary);

// A markdown table, one row per (name, summary): pairs, Spearman (all pairs; within landmarks),
// the worst bin's actual / predicted, and each bin's actual / predicted.
std::string ConfidenceMarkdown(const std::vector<std::pair<std::string, const ConfidenceSummary*>>& rows);

// The reliability plot: each bin's mean actual error against its mean predicted, with the
// diagonal and the 1.5× band around it.
std::string ReliabilitySvg(const std::string& title, const ConfidenceSummary& summary);

}  // namespace mocap::eval
