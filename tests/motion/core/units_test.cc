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

// Issue #23: CMU's ASF-converted files (1 unit = 1/0.45 inch) were read as inches, a 0.9 m person.
TEST(UnitsTest, DetectsCmuUnits) {
  EXPECT_NEAR(MetresPerUnit(LengthUnit::kCmuUnit), 0.0254 / 0.45, 1e-12);
  // A CMU subject's leg (hip joint to ankle) is ~14.5 units: 0.82 m, where inches would make it 0.37 m.
  for (double leg : {12.5, 13.5, 14.5, 15.5, 17.0}) {
    SCOPED_TRACE(leg);
    EXPECT_EQ(DetectUnitFromLegLength(leg), LengthUnit::kCmuUnit);
  }
}

TEST(UnitsTest, DetectsTypicalLegLengthsInEveryUnit) {
  struct Case {
    double leg;  // hip joint to ankle, in the file's unit
    LengthUnit unit;
  };
  for (const Case& c : {// Centimetres: a short adult to a tall character.
                        Case{65.0, LengthUnit::kCentimetre}, Case{75.0, LengthUnit::kCentimetre},
                        Case{85.0, LengthUnit::kCentimetre}, Case{105.0, LengthUnit::kCentimetre},
                        // Inches: 0.7 m to 1 m.
                        Case{27.5, LengthUnit::kInch}, Case{31.5, LengthUnit::kInch}, Case{35.0, LengthUnit::kInch},
                        Case{39.0, LengthUnit::kInch},
                        // Metres.
                        Case{0.65, LengthUnit::kMetre}, Case{0.75, LengthUnit::kMetre}, Case{0.85, LengthUnit::kMetre},
                        Case{1.05, LengthUnit::kMetre},
                        // Millimetres.
                        Case{700.0, LengthUnit::kMillimetre}, Case{950.0, LengthUnit::kMillimetre}}) {
    SCOPED_TRACE(c.leg);
    EXPECT_EQ(DetectUnitFromLegLength(c.leg), c.unit);
    // The detected unit reads the leg as an adult's.
    const double metres = c.leg * MetresPerUnit(DetectUnitFromLegLength(c.leg));
    EXPECT_GT(metres, 0.6);
    EXPECT_LT(metres, 1.1);
  }
}

TEST(UnitsTest, ParsesAndNamesUnits) {
  for (LengthUnit unit : {LengthUnit::kMetre, LengthUnit::kCentimetre, LengthUnit::kMillimetre, LengthUnit::kInch,
                          LengthUnit::kCmuUnit}) {
    EXPECT_EQ(ParseUnit(UnitName(unit)), unit);
  }
  EXPECT_FALSE(ParseUnit("furlong").has_value());
  EXPECT_DOUBLE_EQ(MetresPerUnit(LengthUnit::kInch), 0.0254);
}

}  // namespace
}  // namespace mocap
