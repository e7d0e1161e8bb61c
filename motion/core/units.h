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

// Picks the unit under which `leg_length` (hip joint to ankle, summed bone lengths, in file units)
// is closest, on a log scale, to an adult's ~0.8 m. Ambiguous for children measured in cm (read as
// inches): callers offer an override.
LengthUnit DetectUnitFromLegLength(double leg_length);

}  // namespace mocap
