#include "client/cli/reconstruction_timeline.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "client/cli/reconstruction_bvh.h"

namespace mocap::cli {
namespace {

void Lerp(const v1::Vec3& a, const v1::Vec3& b, float s, v1::Vec3* out) {
  out->set_x(a.x() + s * (b.x() - a.x()));
  out->set_y(a.y() + s * (b.y() - a.y()));
  out->set_z(a.z() + s * (b.z() - a.z()));
}

void Slerp(const v1::Quaternion& a, const v1::Quaternion& b, float s, v1::Quaternion* out) {
  const Eigen::Quaternionf qa = Eigen::Quaternionf(a.w(), a.x(), a.y(), a.z()).normalized();
  const Eigen::Quaternionf qb = Eigen::Quaternionf(b.w(), b.x(), b.y(), b.z()).normalized();
  const Eigen::Quaternionf q = qa.slerp(s, qb);  // the shorter way round
  out->set_w(q.w());
  out->set_x(q.x());
  out->set_y(q.y());
  out->set_z(q.z());
}

// The frame `s` of the way from `a` to `b` (0 < s < 1), at `time`.
v1::Frame Between(const v1::Frame& a, const v1::Frame& b, float s, double time) {
  v1::Frame out = a;
  out.set_time(time);
  out.set_frame_in_segment(-1);
  out.clear_diagnostics();
  out.clear_expected_error();
  out.set_left_hand_state(v1::TRACKING_STATE_LOST);
  out.set_right_hand_state(v1::TRACKING_STATE_LOST);
  out.set_motion_limited(false);
  Lerp(a.root_position(), b.root_position(), s, out.mutable_root_position());
  Lerp(a.pelvis_position(), b.pelvis_position(), s, out.mutable_pelvis_position());
  Slerp(a.pelvis_rotation(), b.pelvis_rotation(), s, out.mutable_pelvis_rotation());
  Lerp(a.left_ankle(), b.left_ankle(), s, out.mutable_left_ankle());
  Lerp(a.right_ankle(), b.right_ankle(), s, out.mutable_right_ankle());
  Lerp(a.left_wrist(), b.left_wrist(), s, out.mutable_left_wrist());
  Lerp(a.right_wrist(), b.right_wrist(), s, out.mutable_right_wrist());
  // Frames of different skeletons (a target rig's) are not blended: the one before holds.
  if (a.rotations_size() == b.rotations_size()) {
    for (int j = 0; j < a.rotations_size(); ++j) Slerp(a.rotations(j), b.rotations(j), s, out.mutable_rotations(j));
  }
  const float scale = BodyScale(a) + s * (BodyScale(b) - BodyScale(a));
  out.set_body_scale(scale == 1.0f ? 0.0f : scale);
  return out;
}

}  // namespace

std::optional<FilledTimeline> FillDropouts(const std::vector<v1::Frame>& frames, double frame_rate) {
  if (!(frame_rate > 0.0)) return std::nullopt;
  const double frame_time = 1.0 / frame_rate;
  auto gap = [&](size_t f) { return frames[f + 1].time() - frames[f].time(); };
  auto missing = [&](size_t f) { return FrameTimesMissing(gap(f), frame_time); };
  long total = 0;
  int unfilled = 0;
  for (size_t f = 0; f + 1 < frames.size(); ++f) {
    total += missing(f);
    unfilled += GapTooLongToFill(gap(f));
  }
  if (total == 0 && unfilled == 0) return std::nullopt;
  FilledTimeline out;
  out.unfilled_gaps = unfilled;
  out.frames.reserve(frames.size() + static_cast<size_t>(total));
  for (size_t f = 0; f < frames.size(); ++f) {
    out.frames.push_back(frames[f]);
    if (f + 1 == frames.size()) break;
    const long n = missing(f);
    if (n == 0) continue;
    ++out.gaps;
    out.filled_frames += static_cast<int>(n);
    for (long k = 1; k <= n; ++k) {
      const float s = static_cast<float>(k) / static_cast<float>(n + 1);
      out.frames.push_back(
          Between(frames[f], frames[f + 1], s, frames[f].time() + static_cast<double>(k) * frame_time));
    }
  }
  return out;
}

}  // namespace mocap::cli
