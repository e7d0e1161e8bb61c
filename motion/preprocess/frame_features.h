// Per-frame features of docs/method.md A1, expressed in each frame's wrist reference frame.
#pragma once

#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "motion/skeleton/body_topology.h"
#include "motion/skeleton/forward_kinematics.h"

namespace mocap {

// Index 0 = left, 1 = right. Lengths in metres, velocities in m/s, angles in radians.
// The wrist reference frame (A1): origin on the ground (y = 0) below the midpoint of the wrists;
// y axis = world up; x axis = ground projection of (left wrist - right wrist); z = x × y (the
// direction the wrists face). It is the world rotated by `ref_heading` about Y: x axis =
// (cos h, 0, -sin h).
struct FrameFeatures {
  float ref_origin_x, ref_origin_z, ref_heading;
  float wrist_position[2][3];
  float wrist_velocity[2][3];
  float ankle_position[2][3];
  float ankle_velocity[2][3];
  float pelvis_height;       // h: pelvis above the ground
  float pelvis_tilt;         // θ: angle between world up and the pelvis' up vector
  float pelvis_position[3];  // in the reference frame
  float pelvis_rotation[4];  // w, x, y, z, in the reference frame
};
inline constexpr int kFrameFeatureFloats = 36;
static_assert(sizeof(FrameFeatures) == kFrameFeatureFloats * sizeof(float), "FrameFeatures must stay packed");

// World transform of a reference frame.
struct ReferenceFrame {
  Eigen::Vector3f origin;
  Eigen::Matrix3f rotation;  // columns: x, y, z axes in world coordinates
  Eigen::Vector3f ToLocal(const Eigen::Vector3f& world_point) const {
    return rotation.transpose() * (world_point - origin);
  }
  Eigen::Vector3f DirectionToLocal(const Eigen::Vector3f& world_vector) const {
    return rotation.transpose() * world_vector;
  }
};

// Reference frame from two world wrist positions (Y up, ground y = 0). When the wrists are
// vertically aligned (ground distance < 1 mm) `fallback_heading` gives the x axis.
ReferenceFrame WristReferenceFrame(const Eigen::Vector3f& left_wrist, const Eigen::Vector3f& right_wrist,
                                   float fallback_heading, float* heading_out);

// The world transform of the reference frame a FrameFeatures was expressed in (its stored origin
// and heading).
ReferenceFrame ReferenceFrameOf(const FrameFeatures& features);

// Features of every frame of `poses` (world, metres, Y up, ground at y = 0). `pelvis_up_local`
// is the pelvis-local direction that is vertical on average (RigModel).
std::vector<FrameFeatures> ComputeFrameFeatures(const GlobalPoses& poses, const BodyLandmarks& landmarks,
                                                const Eigen::Vector3f& pelvis_up_local, double frame_time);

// The clip's features played backwards, last frame first: positions and pose as they are, and
// the velocities ComputeFrameFeatures would measure on the reversed motion. Its velocities are
// backward differences, so a frame's reversed velocity is the next frame's velocity negated
// (turned into this frame's wrist reference frame); the last frame keeps its own, negated.
std::vector<FrameFeatures> PlayedBackwards(std::span<const FrameFeatures> clip);

}  // namespace mocap
