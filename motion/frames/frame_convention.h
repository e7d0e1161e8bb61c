// Coordinate conventions of a caller's world (issue #12): length unit, up axis, handedness, and
// the change of basis that takes them to the server's native frame (metres, right-handed, Y up).
#pragma once

#include <optional>
#include <string_view>

#include <Eigen/Core>

#include "motion/core/units.h"

namespace mocap {

enum class UpAxis { kPosX, kNegX, kPosY, kNegY, kPosZ, kNegZ };
enum class Handedness { kRight, kLeft };

std::string_view UpAxisName(UpAxis up);                            // "+X", "-X", "+Y", "-Y", "+Z", "-Z"
std::optional<UpAxis> ParseUpAxis(std::string_view name);          // the names above; "x" = "+x"; any case
std::string_view HandednessName(Handedness handedness);            // "right", "left"
std::optional<Handedness> ParseHandedness(std::string_view name);  // "right"/"rh", "left"/"lh"; any case
// Index (0, 1, 2 for X, Y, Z) and sign (+1, −1) of an up axis.
int UpAxisIndex(UpAxis up);
float UpAxisSign(UpAxis up);

struct FrameConvention {
  LengthUnit unit = LengthUnit::kMetre;
  UpAxis up = UpAxis::kPosY;
  Handedness handedness = Handedness::kRight;
};

// The signed permutation C with native = C · caller (before units and floor); det C = −1 for a
// left-handed caller. The rule, so that the horizontal axes are predictable:
//   1. left-handed: negate the caller's last horizontal axis (Z when X or Y is up, Y when Z is
//      up), which makes the frame right-handed (Unity: z → −z; Unreal: y → −y);
//   2. turn the up axis onto +Y by the shortest rotation: +Z up → (x, z, −y) (Blender), −Z up →
//      (x, −z, y), +X up → (−y, x, z), −X up → (y, −x, z), −Y up → (x, −y, −z) (180° about X).
// The reconstruction does not depend on the heading, so any such rule gives the same motion; this
// one keeps +Y-up right-handed input unchanged.
Eigen::Matrix3f NativeBasis(UpAxis up, Handedness handedness);

}  // namespace mocap
