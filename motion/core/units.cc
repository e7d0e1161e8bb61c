#include "motion/core/units.h"

#include <array>
#include <cmath>
#include <limits>

namespace mocap {

double MetresPerUnit(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::kMetre:
      return 1.0;
    case LengthUnit::kCentimetre:
      return 0.01;
    case LengthUnit::kMillimetre:
      return 0.001;
    case LengthUnit::kInch:
      return 0.0254;
    case LengthUnit::kCmuUnit:
      return 0.0254 / 0.45;
  }
  return 1.0;
}

std::string_view UnitName(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::kMetre:
      return "m";
    case LengthUnit::kCentimetre:
      return "cm";
    case LengthUnit::kMillimetre:
      return "mm";
    case LengthUnit::kInch:
      return "in";
    case LengthUnit::kCmuUnit:
      return "cmu";
  }
  return "?";
}

std::optional<LengthUnit> ParseUnit(std::string_view name) {
  if (name == "m") return LengthUnit::kMetre;
  if (name == "cm") return LengthUnit::kCentimetre;
  if (name == "mm") return LengthUnit::kMillimetre;
  if (name == "in" || name == "inch") return LengthUnit::kInch;
  if (name == "cmu") return LengthUnit::kCmuUnit;
  return std::nullopt;
}

LengthUnit DetectUnitFromLegLength(double leg_length) {
  constexpr double kTypicalLegMetres = 0.8;
  constexpr std::array kCandidates = {LengthUnit::kCentimetre, LengthUnit::kMetre, LengthUnit::kInch,
                                      LengthUnit::kMillimetre, LengthUnit::kCmuUnit};
  LengthUnit best = LengthUnit::kCentimetre;
  double best_error = std::numeric_limits<double>::infinity();
  for (LengthUnit unit : kCandidates) {
    const double error = std::abs(std::log(leg_length * MetresPerUnit(unit) / kTypicalLegMetres));
    if (error < best_error) {
      best_error = error;
      best = unit;
    }
  }
  return best;
}

}  // namespace mocap
