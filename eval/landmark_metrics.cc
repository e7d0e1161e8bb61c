#include "eval/landmark_metrics.h"

#include <algorithm>
#include <cmath>

namespace mocap::eval {

LandmarkBodySize BodySizeOf(const std::array<Eigen::Vector3f, kNumScoredLandmarks>& p) {
  auto chain = [&](int a, int b, int c) { return (p[a] - p[b]).norm() + (p[b] - p[c]).norm(); };
  // Scoring order: shoulders 2-3, elbows 4-5, wrists 6-7, hips 8-9, knees 10-11, ankles 12-13.
  return {.leg = 0.5f * (chain(8, 10, 12) + chain(9, 11, 13)), .arm = 0.5f * (chain(2, 4, 6) + chain(3, 5, 7))};
}

LandmarkBodySize BodySizeOf(const ReconstructionDatabase& database) {
  const std::array<int, kNumScoredLandmarks> joints = ScoredLandmarkJoints(database.rig().topology.landmarks);
  BodyPose rest;
  rest.rotations.assign(database.body().skeleton().num_joints(), Eigen::Quaternionf::Identity());
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> positions;
  database.body().WorldTransforms(rest, &rotations, &positions);
  std::array<Eigen::Vector3f, kNumScoredLandmarks> at;
  for (int k = 0; k < kNumScoredLandmarks; ++k) at[k] = positions[joints[k]];
  return BodySizeOf(at);
}

void LandmarkMetrics::Add(const LandmarkMetrics& o) {
  frames += o.frames;
  landmark_error_m += o.landmark_error_m;
  pose_error_m += o.pose_error_m;
  for (int g = 0; g < kNumLandmarkGroups; ++g) group_error_m[g] += o.group_error_m[g];
  seconds += o.seconds;
  reentries += o.reentries;
  reentry_jerk += o.reentry_jerk;
  truth_reentry_jerk += o.truth_reentry_jerk;
  AddPlausibility(o);
}

namespace {

// The capture's fastest `landmark`, measured over the database's frame time (the output's), so a
// 120 fps capture's marker noise is not taken for speed.
double TruthSpeedMax(const LandmarkTruth& truth, int landmark, double database_frame_time) {
  const int step = std::max(1, static_cast<int>(std::lround(database_frame_time / truth.frame_time)));
  double fastest = 0;
  for (int f = step; f < truth.num_frames(); ++f) {
    const double moved = (truth.positions[f][landmark] - truth.positions[f - step][landmark]).norm();
    fastest = std::max(fastest, moved / (step * truth.frame_time));
  }
  return fastest;
}

SizeMap MapOf(std::span<const SizeMap> maps, size_t frame) {
  if (maps.empty()) return {};
  return maps.size() == 1 ? maps.front() : maps[frame];
}

}  // namespace

LandmarkMetrics MeasureLandmarks(const ReconstructionDatabase& database, const LandmarkTruth& truth,
                                 const std::vector<ReconstructedFrame>& frames, std::span<const SizeMap> maps,
                                 std::vector<ConfidenceSample>* confidence) {
  LandmarkMetrics m;
  const std::array<int, kNumScoredLandmarks> joints = ScoredLandmarkJoints(database.rig().topology.landmarks);
  const PlausibilityRig plausibility_rig =
      MakePlausibilityRig(database.body().skeleton(), database.rig().topology.landmarks);
  std::vector<std::array<Eigen::Vector3f, kNumScoredLandmarks>> output(frames.size());
  std::vector<PlausibilityFrame> plausibility_frames;
  plausibility_frames.reserve(frames.size());
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> positions;
  for (size_t i = 0; i < frames.size(); ++i) {
    database.body().WorldTransforms(frames[i].pose, &rotations, &positions);
    const SizeMap map = MapOf(maps, i);
    for (int k = 0; k < kNumScoredLandmarks; ++k) output[i][k] = map.ToPerformer(positions[joints[k]]);
    // Measured where the capture it is compared with moves, the performer's space: a body sized up
    // by 1.2 moves 1.2 times as fast there as in the database body's, and while the size eases in,
    // its growth is motion the user sees. What is true in either space (the input within reach) is
    // read in the database body's, where its arms are.
    PlausibilityFrame plausibility =
        MakePlausibilityFrame(plausibility_rig, positions, frames[i].wrists, frames[i].time, frames[i].segment,
                              frames[i].implausible_input(), frames[i].motion_limited);
    plausibility.pelvis = map.ToPerformer(plausibility.pelvis);
    for (int side = 0; side < 2; ++side) {
      plausibility.hands[side] = map.ToPerformer(plausibility.hands[side]);
      plausibility.input[side] = map.ToPerformer(plausibility.input[side]);
      plausibility.ankles[side] = map.ToPerformer(plausibility.ankles[side]);
    }
    plausibility.lowest_point *= map.scale;
    plausibility.put_down_hands = frames[i].put_down_hands();
    plausibility_frames.push_back(plausibility);
  }
  size_t next = 1;  // the first output frame at or after the truth frame's time
  for (int f = 0; f < truth.num_frames() && frames.size() >= 2; ++f) {
    const double t = f * truth.frame_time;
    if (t < frames.front().time - 1e-9 || t > frames.back().time + 1e-9) continue;
    while (next + 1 < frames.size() && frames[next].time < t) ++next;
    const double t0 = frames[next - 1].time, t1 = frames[next].time;
    const float w = t1 > t0 ? static_cast<float>(std::clamp((t - t0) / (t1 - t0), 0.0, 1.0)) : 0.0f;
    double sum = 0, pose = 0;
    std::array<double, kNumLandmarkGroups> group{};
    std::array<Eigen::Vector3f, kNumScoredLandmarks> at;
    for (int k = 0; k < kNumScoredLandmarks; ++k) {
      at[k] = (1.0f - w) * output[next - 1][k] + w * output[next][k];
      const double e = (at[k] - truth.positions[f][k]).norm();
      sum += e;
      group[kLandmarkGroup[k]] += e;
    }
    for (int k = 0; k < kNumScoredLandmarks; ++k) {
      if (k == kPelvisLandmark) continue;
      pose += ((at[k] - at[kPelvisLandmark]) - (truth.positions[f][k] - truth.positions[f][kPelvisLandmark])).norm();
    }
    // A time between two segments (a dropout too long to bridge) has no answer, so no expected
    // error either: its position is scored as interpolated, its confidence is not.
    const bool answered =
        frames[next - 1].segment == frames[next].segment || std::min(t - t0, t1 - t) <= 0.5 * database.frame_time();
    if (confidence && answered) {
      const size_t nearer = w < 0.5f ? next - 1 : next;
      AddConfidenceSamples(frames[nearer], MapOf(maps, nearer).scale, at, truth.positions[f], confidence);
    }
    m.pose_error_m += pose / (kNumScoredLandmarks - 1);
    m.frames += 1;
    m.landmark_error_m += sum / kNumScoredLandmarks;
    for (int g = 0; g < kNumLandmarkGroups; ++g) m.group_error_m[g] += g < 2 ? group[g] : group[g] / 2;
  }
  // The database's planted ankle and fastest pelvis at the size the body ended at.
  const float size = frames.empty() ? 1.0f : MapOf(maps, frames.size() - 1).scale;
  m.SetClip(MeasurePlausibility(plausibility_frames, size * database.planted_ankle_height(),
                                size * database.motion_limits().pelvis_speed_max),
            TruthSpeedMax(truth, kPelvisLandmark, database.frame_time()),
            std::max(TruthSpeedMax(truth, kLeftAnkleLandmark, database.frame_time()),
                     TruthSpeedMax(truth, kRightAnkleLandmark, database.frame_time())));
  return m;
}

std::array<Eigen::Vector3f, kNumScoredLandmarks> LandmarksAt(const LandmarkTruth& truth, double t) {
  const double at = std::clamp(t / truth.frame_time, 0.0, static_cast<double>(truth.num_frames() - 1));
  const int f = std::min(static_cast<int>(at), truth.num_frames() - 2);
  const float w = static_cast<float>(at - f);
  std::array<Eigen::Vector3f, kNumScoredLandmarks> p;
  for (int k = 0; k < kNumScoredLandmarks; ++k) p[k] = (1 - w) * truth.positions[f][k] + w * truth.positions[f + 1][k];
  return p;
}

namespace {

// Mean over the landmarks of |third difference| / dt³ at frame i of `positions` (i ≥ 3).
double Jerk(const std::vector<std::array<Eigen::Vector3f, kNumScoredLandmarks>>& positions, size_t i, double dt) {
  double sum = 0;
  for (int k = 0; k < kNumScoredLandmarks; ++k) {
    sum += (positions[i][k] - 3 * positions[i - 1][k] + 3 * positions[i - 2][k] - positions[i - 3][k]).norm();
  }
  return sum / kNumScoredLandmarks / (dt * dt * dt);
}

}  // namespace

void MeasureReentryJerk(const ReconstructionDatabase& database, const LandmarkTruth& truth,
                        const std::vector<ReconstructedFrame>& frames, const std::vector<WristSample>& samples,
                        std::span<const SizeMap> maps, LandmarkMetrics* metrics) {
  if (samples.size() < 3 || frames.size() < 4 || truth.num_frames() < 2) return;
  std::vector<double> steps;
  for (size_t i = 1; i < samples.size(); ++i) steps.push_back(samples[i].time - samples[i - 1].time);
  std::nth_element(steps.begin(), steps.begin() + static_cast<long>(steps.size() / 2), steps.end());
  const double period = steps[steps.size() / 2];
  const std::array<int, kNumScoredLandmarks> joints = ScoredLandmarkJoints(database.rig().topology.landmarks);
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> positions;
  std::vector<std::array<Eigen::Vector3f, kNumScoredLandmarks>> output(frames.size()), captured(frames.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    database.body().WorldTransforms(frames[i].pose, &rotations, &positions);
    const SizeMap map = MapOf(maps, i);
    for (int k = 0; k < kNumScoredLandmarks; ++k) output[i][k] = map.ToPerformer(positions[joints[k]]);
    captured[i] = LandmarksAt(truth, frames[i].time);
  }
  const double dt = database.frame_time();
  const double truth_end = (truth.num_frames() - 1) * truth.frame_time;
  for (size_t s = 1; s < samples.size(); ++s) {
    const bool hand_back =
        (samples[s].tracked[0] && !samples[s - 1].tracked[0]) || (samples[s].tracked[1] && !samples[s - 1].tracked[1]);
    if (samples[s].time - samples[s - 1].time <= 2.5 * period && !hand_back) continue;
    const double back = samples[s].time;
    double jerk = 0, truth_jerk = 0;
    int counted = 0;
    for (size_t i = 3; i < frames.size(); ++i) {
      if (frames[i].time < back - 0.2 || frames[i].time > back + 0.5 || frames[i].time > truth_end) continue;
      if (frames[i - 3].segment != frames[i].segment) continue;  // a new segment's first frames
      jerk += Jerk(output, i, dt);
      truth_jerk += Jerk(captured, i, dt);
      ++counted;
    }
    if (counted == 0) continue;
    metrics->reentries += 1;
    metrics->reentry_jerk += jerk / counted;
    metrics->truth_reentry_jerk += truth_jerk / counted;
  }
}

}  // namespace mocap::eval
