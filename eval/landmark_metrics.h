// Scoring a reconstruction on body landmarks (issue #22, shared/data/README "Beyond the lab"): the
// test clip may be on any rig, at any rate and in any unit, so the reconstruction (on the
// database's rig) and the capture (on its own) are compared where both rigs have the same body
// point, found by the name-free analysis (motion/skeleton/body_topology.h): pelvis, head,
// shoulders, elbows, wrists, hips, knees, ankles, at the test clip's own frame times.
#pragma once

#include <array>
#include <span>
#include <string>
#include <vector>

#include "eval/clip_plausibility.h"
#include "eval/confidence_calibration.h"
#include "motion/reconstruct/body_sizer.h"
#include "motion/reconstruct/reconstruction_database.h"
#include "motion/reconstruct/reconstruction_session.h"
#include "motion/skeleton/body_topology.h"

namespace mocap::eval {

// The scored landmarks, in this order; the groups pair left and right.
inline constexpr int kNumScoredLandmarks = kNumBodyLandmarks;
inline constexpr int kNumLandmarkGroups = 8;
inline constexpr std::array<const char*, kNumLandmarkGroups> kLandmarkGroupNames = {
    "pelvis", "head", "shoulders", "elbows", "wrists", "hips", "knees", "ankles"};
// Group of each scored landmark (pelvis, head, then left/right of each pair).
inline constexpr std::array<int, kNumScoredLandmarks> kLandmarkGroup = {0, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7};
inline constexpr int kLeftWristLandmark = 6, kRightWristLandmark = 7, kPelvisLandmark = 0;
inline constexpr int kLeftAnkleLandmark = 12, kRightAnkleLandmark = 13;
inline constexpr int kLeftElbowLandmark = 4;  // and the right one next

// The joints of `landmarks` in scoring order (BodyLandmarkJoints); -1 where the rig's analysis found none.
inline std::array<int, kNumScoredLandmarks> ScoredLandmarkJoints(const BodyLandmarks& landmarks) {
  return BodyLandmarkJoints(landmarks);
}

// A captured clip seen through its landmarks: world metres, Y up, frames `frame_time` apart from
// time 0.
struct LandmarkTruth {
  double frame_time = 0;
  std::vector<std::array<Eigen::Vector3f, kNumScoredLandmarks>> positions;  // per frame
  int num_frames() const { return static_cast<int>(positions.size()); }
};

// The truth's landmarks at time t (seconds from its first frame), linear between its frames and
// held beyond its ends. At least two frames.
std::array<Eigen::Vector3f, kNumScoredLandmarks> LandmarksAt(const LandmarkTruth& truth, double t);

// A body's size seen through its landmarks: hip to knee to ankle and shoulder to elbow to wrist,
// metres, the mean of both sides (rigid bones: any frame gives it).
struct LandmarkBodySize {
  float leg = 0, arm = 0;
};
LandmarkBodySize BodySizeOf(const std::array<Eigen::Vector3f, kNumScoredLandmarks>& frame);
// The same for the database's body (its skeleton's bone lengths).
LandmarkBodySize BodySizeOf(const ReconstructionDatabase& database);

// Sums over scored frames; Mean() turns them into figures.
struct LandmarkMetrics : ClipPlausibility {
  double frames = 0;
  double landmark_error_m = 0;  // Σ per-frame mean distance over the 14 landmarks
  std::array<double, kNumLandmarkGroups> group_error_m{};
  // The pose alone: Σ per-frame mean distance over the 13 landmarks other than the pelvis, each
  // taken relative to its body's pelvis (where the body is does not count, how it stands does).
  double pose_error_m = 0;
  double seconds = 0;  // engine wall time
  // Issue #25: after each input dropout, the mean jerk (m/s³, the 14 landmarks' mean) of the output
  // from 0.2 s before the input came back to 0.5 s after, and the capture's over the same times.
  double reentries = 0, reentry_jerk = 0, truth_reentry_jerk = 0;

  void Add(const LandmarkMetrics& other);
  double Mean(double sum) const { return frames > 0 ? sum / frames : 0.0; }
  double wrist_error_m() const { return group_error_m[4]; }
};

// Scores `frames` (the database's rig, its rate, on the input's clock starting at time 0) at each
// of the truth's frame times, the output's landmarks interpolated linearly between the two output
// frames around that time. Truth frames outside the output's time span are not scored.
// `maps`: each frame's positions go to the performer's space through its map first (a body
// reconstructed at the database's size, body_sizer.h): one per frame, or one for every frame, or
// none (the output is the performer's).
// `confidence`, when given, receives each scored frame's confidence pairs (the expected errors of
// the output frame nearer in time, scaled as its positions).
LandmarkMetrics MeasureLandmarks(const ReconstructionDatabase& database, const LandmarkTruth& truth,
                                 const std::vector<ReconstructedFrame>& frames, std::span<const SizeMap> maps = {},
                                 std::vector<ConfidenceSample>* confidence = nullptr);

// Adds to `metrics` the re-entry jerk of `frames` after each dropout of the input `samples` (a
// step of more than 2.5 of its typical sample periods), against the truth's at the same times.
void MeasureReentryJerk(const ReconstructionDatabase& database, const LandmarkTruth& truth,
                        const std::vector<ReconstructedFrame>& frames, const std::vector<WristSample>& samples,
                        std::span<const SizeMap> maps, LandmarkMetrics* metrics);

}  // namespace mocap::eval
