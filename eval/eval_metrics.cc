#include "eval/eval_metrics.h"

#include <algorithm>
#include <cmath>

namespace mocap::eval {

void Metrics::Add(const Metrics& o) {
  frames += o.frames;
  joint_error_m += o.joint_error_m;
  lower_body_error_m += o.lower_body_error_m;
  upper_body_error_m += o.upper_body_error_m;
  pelvis_error_m += o.pelvis_error_m;
  ankle_error_m += o.ankle_error_m;
  wrist_error_m += o.wrist_error_m;
  angle_error_deg += o.angle_error_deg;
  angle_error_sq_deg += o.angle_error_sq_deg;
  planted_frames += o.planted_frames;
  skate_m += o.skate_m;
  truth_skate_m += o.truth_skate_m;
  jitter_frames += o.jitter_frames;
  jitter += o.jitter;
  truth_jitter += o.truth_jitter;
  seconds += o.seconds;
  AddPlausibility(o);
}

Metrics Measure(const ReconstructionDatabase& database, const PreparedClip& clip, const GlobalPoses& truth,
                const std::vector<ReconstructedFrame>& frames) {
  Metrics m;
  const RigModel& rig = database.rig();
  const BodyLandmarks& l = rig.topology.landmarks;
  const int joints = truth.num_joints();
  // Joints above the pelvis (Bandai's static joint_Root at the world origin) are bookkeeping, not
  // body: leave them out of every figure.
  std::vector<bool> measured(joints, true);
  for (int j = rig.skeleton.parent(l.pelvis); j >= 0; j = rig.skeleton.parent(j)) measured[j] = false;
  int measured_count = 0;
  for (int j = 0; j < joints; ++j) measured_count += measured[j];
  std::vector<bool> lower(joints, false);
  for (int j = 0; j < joints; ++j) {
    const BodyGroup g = rig.topology.group_of_joint[j];
    lower[j] = g == BodyGroup::kLeftLeg || g == BodyGroup::kRightLeg || j == l.pelvis;
  }
  const double dt = database.frame_time();
  const double rate = 1.0 / dt;
  const int ankles[2] = {l.left_ankle, l.right_ankle};
  const int wrists[2] = {l.left_wrist, l.right_wrist};
  std::vector<std::vector<Eigen::Vector3f>> positions(frames.size());
  std::vector<Eigen::Quaternionf> rotations;
  const PlausibilityRig plausibility_rig = MakePlausibilityRig(database.body().skeleton(), l);
  std::vector<PlausibilityFrame> plausibility_frames;
  for (size_t i = 0; i < frames.size(); ++i) {
    const int f = frames[i].frame_in_segment;
    database.body().WorldTransforms(frames[i].pose, &rotations, &positions[i]);
    plausibility_frames.push_back(MakePlausibilityFrame(plausibility_rig, positions[i], frames[i].wrists,
                                                        frames[i].time, frames[i].segment,
                                                        frames[i].implausible_input(), frames[i].motion_limited));
    plausibility_frames.back().put_down_hands = frames[i].put_down_hands();
    const std::vector<Eigen::Vector3f>& p = positions[i];
    double all = 0, legs = 0, upper = 0, angle = 0, angle_sq = 0;
    int leg_count = 0, upper_count = 0;
    for (int j = 0; j < joints; ++j) {
      if (!measured[j]) continue;
      const double e = (p[j] - truth.position(f, j)).norm();
      all += e;
      if (lower[j]) {
        legs += e;
        ++leg_count;
      } else {
        upper += e;
        ++upper_count;
      }
      if (j != l.pelvis) {  // the pelvis' local rotation is relative to the static root
        const double degrees = frames[i].pose.rotations[j].angularDistance(clip.motion.rotation(f, j)) * 180.0 / M_PI;
        angle += degrees;
        angle_sq += degrees * degrees;
      }
    }
    m.frames += 1;
    m.joint_error_m += all / measured_count;
    m.lower_body_error_m += leg_count ? legs / leg_count : 0.0;
    m.upper_body_error_m += upper_count ? upper / upper_count : 0.0;
    m.wrist_error_m += 0.5 * ((p[wrists[0]] - truth.position(f, wrists[0])).norm() +
                              (p[wrists[1]] - truth.position(f, wrists[1])).norm());
    m.pelvis_error_m += (p[l.pelvis] - truth.position(f, l.pelvis)).norm();
    m.ankle_error_m += 0.5 * ((p[ankles[0]] - truth.position(f, ankles[0])).norm() +
                              (p[ankles[1]] - truth.position(f, ankles[1])).norm());
    m.angle_error_deg += angle / (measured_count - 1);
    m.angle_error_sq_deg += angle_sq / (measured_count - 1);
    if (i >= 1 && frames[i - 1].frame_in_segment == f - 1) {
      for (int a : ankles) {
        const Eigen::Vector3f step = truth.position(f, a) - truth.position(f - 1, a);
        const double ground_speed = std::hypot(step.x(), step.z()) * rate;
        if (ground_speed < kTruthContactSpeed &&
            truth.position(f, a).y() < database.planted_ankle_height() + kTruthContactHeight) {
          const Eigen::Vector3f moved = p[a] - positions[i - 1][a];
          m.planted_frames += 1;
          m.skate_m += std::hypot(moved.x(), moved.z());
          m.truth_skate_m += std::hypot(step.x(), step.z());
        }
      }
    }
    if (i >= 3) {
      double jitter = 0, truth_jitter = 0;
      for (int j = 0; j < joints; ++j) {
        if (!measured[j]) continue;
        jitter += (p[j] - 3 * positions[i - 1][j] + 3 * positions[i - 2][j] - positions[i - 3][j]).norm();
        truth_jitter += (truth.position(f, j) - 3 * truth.position(f - 1, j) + 3 * truth.position(f - 2, j) -
                         truth.position(f - 3, j))
                            .norm();
      }
      m.jitter_frames += 1;
      m.jitter += jitter / measured_count * rate * rate * rate;
      m.truth_jitter += truth_jitter / measured_count * rate * rate * rate;
    }
  }
  auto truth_max = [&](int joint) {
    double fastest = 0;
    for (int f = 1; f < truth.num_frames(); ++f) {
      fastest = std::max(fastest,
                         static_cast<double>((truth.position(f, joint) - truth.position(f - 1, joint)).norm()) * rate);
    }
    return fastest;
  };
  m.SetClip(MeasurePlausibility(plausibility_frames, database.planted_ankle_height(),
                                database.motion_limits().pelvis_speed_max),
            truth_max(l.pelvis), std::max(truth_max(ankles[0]), truth_max(ankles[1])));
  return m;
}

}  // namespace mocap::eval
