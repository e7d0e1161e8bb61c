#include "motion/skeleton/local_motion.h"

#include <algorithm>
#include <cmath>

namespace mocap {

void LocalMotion::Resize(int frames, int joints) {
  for (Eigen::ArrayXXf* array : {&qw, &qx, &qy, &qz, &tx, &ty, &tz}) array->resize(frames, joints);
}

void LocalMotion::SetRotation(int frame, int joint, const Eigen::Quaternionf& q) {
  qw(frame, joint) = q.w();
  qx(frame, joint) = q.x();
  qy(frame, joint) = q.y();
  qz(frame, joint) = q.z();
}

void LocalMotion::SetTranslation(int frame, int joint, const Eigen::Vector3f& t) {
  tx(frame, joint) = t.x();
  ty(frame, joint) = t.y();
  tz(frame, joint) = t.z();
}

LocalMotion MotionFromChannels(const Skeleton& skeleton, const ChannelMatrix& channels, double frame_time) {
  const int frames = static_cast<int>(channels.rows());
  const int joints = skeleton.num_joints();
  LocalMotion motion;
  motion.frame_time = frame_time;
  motion.Resize(frames, joints);
  constexpr float kHalfDegree = static_cast<float>(M_PI / 360.0);
  for (int j = 0; j < joints; ++j) {
    const Joint& joint = skeleton.joint(j);
    const int start = skeleton.channel_start(j);
    const bool is_root = j == 0;
    for (int axis = 0; axis < 3; ++axis) {
      Eigen::ArrayXXf& t = axis == 0 ? motion.tx : axis == 1 ? motion.ty : motion.tz;
      t.col(j).setConstant(joint.offset[axis]);
    }
    motion.qw.col(j).setOnes();
    motion.qx.col(j).setZero();
    motion.qy.col(j).setZero();
    motion.qz.col(j).setZero();
    for (size_t c = 0; c < joint.channels.size(); ++c) {
      const ChannelType type = joint.channels[c];
      const int axis = ChannelAxis(type);
      const int column = start + static_cast<int>(c);
      if (!IsRotation(type)) {
        Eigen::ArrayXXf& t = axis == 0 ? motion.tx : axis == 1 ? motion.ty : motion.tz;
        for (int f = 0; f < frames; ++f) {
          t(f, j) = is_root ? joint.offset[axis] + channels(f, column) : channels(f, column);
        }
        continue;
      }
      // q <- q * (rotation about `axis`): intrinsic composition in channel order.
      for (int f = 0; f < frames; ++f) {
        const float half = channels(f, column) * kHalfDegree;
        const float s = std::sin(half), co = std::cos(half);
        const float w = motion.qw(f, j), x = motion.qx(f, j), y = motion.qy(f, j), z = motion.qz(f, j);
        float rw, rx, ry, rz;
        if (axis == 0) {
          rw = w * co - x * s;
          rx = x * co + w * s;
          ry = y * co + z * s;
          rz = z * co - y * s;
        } else if (axis == 1) {
          rw = w * co - y * s;
          rx = x * co - z * s;
          ry = y * co + w * s;
          rz = z * co + x * s;
        } else {
          rw = w * co - z * s;
          rx = x * co + y * s;
          ry = y * co - x * s;
          rz = z * co + w * s;
        }
        motion.qw(f, j) = rw;
        motion.qx(f, j) = rx;
        motion.qy(f, j) = ry;
        motion.qz(f, j) = rz;
      }
    }
  }
  return motion;
}

namespace {

// Euler angles (radians) of `rotation` for the intrinsic order `axes` (R = R_a0 R_a1 R_a2), with
// the middle angle in [-pi/2, pi/2] — the branch nearest to zero for typical joint rotations.
Eigen::Vector3f EulerAngles(const Eigen::Quaternionf& rotation, int a0, int a1, int a2) {
  // Works for Tait–Bryan orders (three distinct axes). Sign of the permutation decides the formulas.
  // The matrix in double from the quaternion, the middle angle by atan2 of its sine and cosine:
  // in float, a middle angle within ~0.3° of ±90° had to be taken as gimbal lock, which turned the
  // rotation by up to ~0.1° (millimetres at a hand).
  const Eigen::Matrix3d m = rotation.cast<double>().normalized().toRotationMatrix();
  const bool even = (a1 == (a0 + 1) % 3);
  const double sign = even ? 1.0 : -1.0;
  Eigen::Vector3d angles;
  const double s1 = sign * m(a0, a2);
  const double c1 = std::hypot(m(a0, a0), m(a0, a1));
  angles[1] = std::atan2(s1, c1);
  if (c1 > 1e-7) {
    angles[0] = std::atan2(-sign * m(a1, a2), m(a2, a2));
    angles[2] = std::atan2(-sign * m(a0, a1), m(a0, a0));
  } else {  // gimbal lock: put everything in the first angle
    angles[0] = std::atan2(sign * m(a2, a1), m(a1, a1));
    angles[2] = 0.0;
  }
  return angles.cast<float>();
}

}  // namespace

ChannelMatrix ChannelsFromMotion(const Skeleton& skeleton, const LocalMotion& motion) {
  ChannelMatrix channels(motion.num_frames(), skeleton.num_channels());
  constexpr float kDegrees = static_cast<float>(180.0 / M_PI);
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    const Joint& joint = skeleton.joint(j);
    int order[3];
    int n = 0;
    bool used[3] = {false, false, false};
    for (ChannelType type : joint.channels) {
      if (IsRotation(type)) {
        order[n++] = ChannelAxis(type);
        used[ChannelAxis(type)] = true;
      }
    }
    const int rotation_channels = n;
    for (int axis = 0; axis < 3 && n < 3; ++axis) {
      if (!used[axis]) order[n++] = axis;
    }
    for (int f = 0; f < motion.num_frames(); ++f) {
      Eigen::Vector3f angles = Eigen::Vector3f::Zero();
      if (rotation_channels > 0) {
        angles = EulerAngles(motion.rotation(f, j), order[0], order[1], order[2]);
        if (rotation_channels < 3) {
          // The other Euler solution (a+pi, pi-b, c+pi) may be the one whose dropped angles are
          // zero; keep whichever drops less.
          const float pi = static_cast<float>(M_PI);
          auto wrap = [pi](float a) { return a > pi ? a - 2 * pi : (a < -pi ? a + 2 * pi : a); };
          const Eigen::Vector3f other(wrap(angles[0] + pi), wrap(pi - angles[1]), wrap(angles[2] + pi));
          auto dropped = [&](const Eigen::Vector3f& a) { return a.tail(3 - rotation_channels).cwiseAbs().sum(); };
          if (dropped(other) < dropped(angles)) angles = other;
        }
      }
      int r = 0;
      for (size_t c = 0; c < joint.channels.size(); ++c) {
        const ChannelType type = joint.channels[c];
        const int column = skeleton.channel_start(j) + static_cast<int>(c);
        const int axis = ChannelAxis(type);
        if (IsRotation(type)) {
          channels(f, column) = angles[r++] * kDegrees;
        } else {
          const float t = motion.translation(f, j)[axis];
          channels(f, column) = j == 0 ? t - joint.offset[axis] : t;
        }
      }
    }
  }
  return channels;
}

LocalMotion Resample(const LocalMotion& motion, double target_frame_time) {
  const int source_frames = motion.num_frames();
  if (source_frames < 1) {
    LocalMotion empty;
    empty.frame_time = target_frame_time;
    empty.Resize(0, motion.num_joints());
    return empty;
  }
  const double duration = (source_frames - 1) * motion.frame_time;
  const int frames = static_cast<int>(std::floor(duration / target_frame_time + 1e-6)) + 1;
  LocalMotion out;
  out.frame_time = target_frame_time;
  out.Resize(frames, motion.num_joints());
  for (int k = 0; k < frames; ++k) {
    const double position = k * target_frame_time / motion.frame_time;
    const int f0 = std::min(static_cast<int>(std::floor(position + 1e-9)), source_frames - 1);
    const int f1 = std::min(f0 + 1, source_frames - 1);
    const float u = static_cast<float>(std::clamp(position - f0, 0.0, 1.0));
    for (int j = 0; j < motion.num_joints(); ++j) {
      if (u < 1e-6f || f0 == f1) {
        out.SetRotation(k, j, motion.rotation(f0, j));
        out.SetTranslation(k, j, motion.translation(f0, j));
      } else {
        out.SetRotation(k, j, motion.rotation(f0, j).slerp(u, motion.rotation(f1, j)));
        out.SetTranslation(k, j, (1 - u) * motion.translation(f0, j) + u * motion.translation(f1, j));
      }
    }
  }
  return out;
}

void ScaleTranslations(LocalMotion& motion, float factor) {
  motion.tx *= factor;
  motion.ty *= factor;
  motion.tz *= factor;
}

void RotateWorld(LocalMotion& motion, const Eigen::Quaternionf& rotation) {
  for (int f = 0; f < motion.num_frames(); ++f) {
    motion.SetRotation(f, 0, rotation * motion.rotation(f, 0));
    motion.SetTranslation(f, 0, rotation * motion.translation(f, 0));
  }
}

}  // namespace mocap
