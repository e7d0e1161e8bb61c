#include "motion/frames/frame_convention.h"

#include <algorithm>
#include <cctype>
#include <string>

namespace mocap {
namespace {

std::string Lower(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

constexpr UpAxis kUpAxes[] = {UpAxis::kPosX, UpAxis::kNegX, UpAxis::kPosY, UpAxis::kNegY, UpAxis::kPosZ, UpAxis::kNegZ};

}  // namespace

std::string_view UpAxisName(UpAxis up) {
  switch (up) {
    case UpAxis::kPosX:
      return "+X";
    case UpAxis::kNegX:
      return "-X";
    case UpAxis::kPosY:
      return "+Y";
    case UpAxis::kNegY:
      return "-Y";
    case UpAxis::kPosZ:
      return "+Z";
    case UpAxis::kNegZ:
      return "-Z";
  }
  return "?";
}

std::optional<UpAxis> ParseUpAxis(std::string_view name) {
  std::string text = Lower(name);
  if (text.size() == 1) text = "+" + text;
  for (UpAxis up : kUpAxes) {
    if (Lower(UpAxisName(up)) == text) return up;
  }
  return std::nullopt;
}

std::string_view HandednessName(Handedness handedness) { return handedness == Handedness::kRight ? "right" : "left"; }

std::optional<Handedness> ParseHandedness(std::string_view name) {
  const std::string text = Lower(name);
  if (text == "right" || text == "rh" || text == "right-handed") return Handedness::kRight;
  if (text == "left" || text == "lh" || text == "left-handed") return Handedness::kLeft;
  return std::nullopt;
}

int UpAxisIndex(UpAxis up) { return static_cast<int>(up) / 2; }
float UpAxisSign(UpAxis up) { return static_cast<int>(up) % 2 == 0 ? 1.0f : -1.0f; }

Eigen::Matrix3f NativeBasis(UpAxis up, Handedness handedness) {
  Eigen::Matrix3f mirror = Eigen::Matrix3f::Identity();
  if (handedness == Handedness::kLeft) mirror(UpAxisIndex(up) == 2 ? 1 : 2, UpAxisIndex(up) == 2 ? 1 : 2) = -1.0f;
  Eigen::Matrix3f turn =
      Eigen::Matrix3f::Identity();  // rows: native x, y, z as combinations of the (right-handed) caller axes
  switch (up) {
    case UpAxis::kPosY:
      turn << 1, 0, 0, 0, 1, 0, 0, 0, 1;
      break;
    case UpAxis::kNegY:
      turn << 1, 0, 0, 0, -1, 0, 0, 0, -1;
      break;
    case UpAxis::kPosZ:
      turn << 1, 0, 0, 0, 0, 1, 0, -1, 0;
      break;
    case UpAxis::kNegZ:
      turn << 1, 0, 0, 0, 0, -1, 0, 1, 0;
      break;
    case UpAxis::kPosX:
      turn << 0, -1, 0, 1, 0, 0, 0, 0, 1;
      break;
    case UpAxis::kNegX:
      turn << 0, 1, 0, -1, 0, 0, 0, 0, 1;
      break;
  }
  return turn * mirror;
}

}  // namespace mocap
