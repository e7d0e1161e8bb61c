#include "motion/core/units.h"

#include <gtest/gtest.h>

namespace mocap {
namespace {

TEST(UnitsTest, DetectsUnitsFromLegLength) {
  EXPECT_EQ(DetectUnitFromLegLength(80.0), LengthUnit::kCentimetre);  // Bandai-like rig
  EXPECT_EQ(DetectUnitFromLegLength(97.5), LengthUnit::kCentimetre);  // CC rig (tall character)
  EXPECT_EQ(DetectUnitFromLegLength(0.82), LengthUnit::kMetre);
  EXPECT_EQ(DetectUnitFromLegLength(33.0), LengthUnit::kInch);
  EXPECT_EQ(DetectUnitFromLegLength(850.0), LengthUnit::kMillimetre);
}

TEST(UnitsTest, ParsesAndNamesUnits) {
  for (LengthUnit unit : {LengthUnit::kMetre, LengthUnit::kCentimetre, LengthUnit::kMillimetre, LengthUnit::kInch}) {
    EXPECT_EQ(ParseUnit(UnitName(unit)), unit);
  }
  EXPECT_FALSE(ParseUnit("furlong").has_value());
  EXPECT_DOUBLE_EQ(MetresPerUnit(LengthUnit::kInch), 0.0254);
}

}  // namespace
}  // namespace mocap
