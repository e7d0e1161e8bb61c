// Length units of motion files and their detection from body size.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace mocap {

// kCmuUnit: the CMU motion capture database's ASF-converted BVH files, 1 unit = 1/0.45 inch
// (their AMC/ASF "length 0.45" scaling); read as inches they make a 0.9 m person.
enum class LengthUnit { kMetre, kCentimetre, kMillimetre, kInch, kCmuUnit };

// Metres per one `unit`.
double MetresPerUnit(LengthUnit unit);
std::string_view UnitName(LengthUnit unit);  // "m", "cm", "mm", "in", "cmu"
std::optional<LengthUnit> ParseUnit(std::string_view name);

// A standing person's leg, hip joint centre to ankle joint centre along the bones, over their
// height (floor to the top of the head): ~0.47 (anthropometric tables give 0.49 for thigh + shank
// measured from the trochanter; a rig's hip joint sits lower and its ankle higher). The one place
// where a body's height is told from its skeleton: end sites are often zero, and zero-rotation
// poses are often not standing ones.
inline constexpr double kLegShareOfStature = 0.47;

// Picks the unit under which `leg_length` (hip joint to ankle, summed bone lengths, in file units)
// is closest, on a log scale, to an adult's ~0.8 m. Ambiguous for children measured in cm (read as
// inches): callers offer an override.
LengthUnit DetectUnitFromLegLength(double leg_length);

}  // namespace mocap
