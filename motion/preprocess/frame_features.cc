#include "motion/preprocess/frame_features.h"

#include <algorithm>
#include <cmath>

namespace mocap {
namespace {

void Store(const Eigen::Vector3f& v, float out[3]) {
  out[0] = v.x();
  out[1] = v.y();
  out[2] = v.z();
}

}  // namespace

ReferenceFrame WristReferenceFrame(const Eigen::Vector3f& left_wrist, const Eigen::Vector3f& right_wrist,
                                   float fallback_heading, float* heading_out) {
  Eigen::Vector3f x_axis(left_wrist.x() - right_wrist.x(), 0.0f, left_wrist.z() - right_wrist.z());
  float heading;
  if (x_axis.norm() < 1e-3f) {
    heading = fallback_heading;
  } else {
    heading = std::atan2(-x_axis.z(), x_axis.x());
  }
  if (heading_out != nullptr) *heading_out = heading;
  ReferenceFrame frame;
  const Eigen::Vector3f midpoint = 0.5f * (left_wrist + right_wrist);
  frame.origin = Eigen::Vector3f(midpoint.x(), 0.0f, midpoint.z());
  frame.rotation = Eigen::AngleAxisf(heading, Eigen::Vector3f::UnitY()).toRotationMatrix();
  return frame;
}

ReferenceFrame ReferenceFrameOf(const FrameFeatures& features) {
  ReferenceFrame frame;
  frame.origin = Eigen::Vector3f(features.ref_origin_x, 0.0f, features.ref_origin_z);
  frame.rotation = Eigen::AngleAxisf(features.ref_heading, Eigen::Vector3f::UnitY()).toRotationMatrix();
  return frame;
}

std::vector<FrameFeatures> ComputeFrameFeatures(const GlobalPoses& poses, const BodyLandmarks& landmarks,
                                                const Eigen::Vector3f& pelvis_up_local, double frame_time) {
  const int frames = poses.num_frames();
  std::vector<FrameFeatures> features(frames);
  const int wrists[2] = {landmarks.left_wrist, landmarks.right_wrist};
  const int ankles[2] = {landmarks.left_ankle, landmarks.right_ankle};
  const float rate = static_cast<float>(1.0 / frame_time);

  // First usable heading, so leading frames with vertically aligned wrists have one too.
  float heading = 0.0f;
  for (int f = 0; f < frames; ++f) {
    const Eigen::Vector3f d = poses.position(f, wrists[0]) - poses.position(f, wrists[1]);
    if (Eigen::Vector2f(d.x(), d.z()).norm() >= 1e-3f) {
      heading = std::atan2(-d.z(), d.x());
      break;
    }
  }
  // Finite differences of world positions between consecutive frames (A1); the first frame
  // takes the forward difference.
  auto velocity = [&](int f, int joint) -> Eigen::Vector3f {
    if (frames < 2) return Eigen::Vector3f::Zero();
    const int a = f == 0 ? 0 : f - 1;
    const int b = f == 0 ? 1 : f;
    return (poses.position(b, joint) - poses.position(a, joint)) * rate;
  };
  for (int f = 0; f < frames; ++f) {
    FrameFeatures& out = features[f];
    const ReferenceFrame ref =
        WristReferenceFrame(poses.position(f, wrists[0]), poses.position(f, wrists[1]), heading, &heading);
    out.ref_origin_x = ref.origin.x();
    out.ref_origin_z = ref.origin.z();
    out.ref_heading = heading;
    for (int side = 0; side < 2; ++side) {
      Store(ref.ToLocal(poses.position(f, wrists[side])), out.wrist_position[side]);
      Store(ref.DirectionToLocal(velocity(f, wrists[side])), out.wrist_velocity[side]);
      Store(ref.ToLocal(poses.position(f, ankles[side])), out.ankle_position[side]);
      Store(ref.DirectionToLocal(velocity(f, ankles[side])), out.ankle_velocity[side]);
    }
    const Eigen::Vector3f pelvis = poses.position(f, landmarks.pelvis);
    const Eigen::Quaternionf pelvis_rotation = poses.rotation(f, landmarks.pelvis).normalized();
    out.pelvis_height = pelvis.y();
    const Eigen::Vector3f pelvis_up = pelvis_rotation * pelvis_up_local;
    out.pelvis_tilt = std::acos(std::clamp(pelvis_up.normalized().y(), -1.0f, 1.0f));
    Store(ref.ToLocal(pelvis), out.pelvis_position);
    Eigen::Quaternionf local_rotation = Eigen::Quaternionf(ref.rotation.transpose()) * pelvis_rotation;
    if (local_rotation.w() < 0) local_rotation.coeffs() *= -1.0f;
    out.pelvis_rotation[0] = local_rotation.w();
    out.pelvis_rotation[1] = local_rotation.x();
    out.pelvis_rotation[2] = local_rotation.y();
    out.pelvis_rotation[3] = local_rotation.z();
  }
  return features;
}

std::vector<FrameFeatures> PlayedBackwards(std::span<const FrameFeatures> clip) {
  std::vector<FrameFeatures> reversed(clip.rbegin(), clip.rend());
  const int frames = static_cast<int>(clip.size());
  for (int f = 0; f < frames; ++f) {
    FrameFeatures& out = reversed[frames - 1 - f];
    const FrameFeatures& next = clip[std::min(f + 1, frames - 1)];
    // next's velocities are in next's wrist frame: turn them by the heading change into f's.
    const Eigen::Matrix3f turn =
        Eigen::AngleAxisf(next.ref_heading - clip[f].ref_heading, Eigen::Vector3f::UnitY()).toRotationMatrix();
    for (int side = 0; side < 2; ++side) {
      const Eigen::Vector3f wrist = -(turn * Eigen::Map<const Eigen::Vector3f>(next.wrist_velocity[side]));
      const Eigen::Vector3f ankle = -(turn * Eigen::Map<const Eigen::Vector3f>(next.ankle_velocity[side]));
      for (int axis = 0; axis < 3; ++axis) {
        out.wrist_velocity[side][axis] = wrist[axis];
        out.ankle_velocity[side][axis] = ankle[axis];
      }
    }
  }
  return reversed;
}

}  // namespace mocap
