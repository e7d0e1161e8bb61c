// The plausibility measures' histogram (motion/reconstruct/plausibility.h): quantiles and shares.
#include <gtest/gtest.h>

#include "motion/reconstruct/plausibility.h"

namespace mocap {
namespace {

TEST(HistogramTest, QuantilesAndSharesBelowAValue) {
  Histogram h(0.01f);
  EXPECT_EQ(h.FractionBelow(1.0f), 1.0);                                // nothing measured: nothing is over
  for (int i = 0; i < 100; ++i) h.Add(0.001f * static_cast<float>(i));  // 0 .. 0.099
  EXPECT_EQ(h.count(), 100);
  EXPECT_NEAR(h.Quantile(0.5), 0.05f, 1e-6);
  EXPECT_FLOAT_EQ(h.max(), 0.099f);
  EXPECT_NEAR(h.FractionBelow(0.0495f), 0.5, 1e-9);  // to the bin: 0 .. 0.049
  EXPECT_EQ(h.FractionBelow(0.2f), 1.0);
  h.Add(-1.0f);  // negatives count as 0
  EXPECT_NEAR(h.FractionBelow(0.0f), 11.0 / 101.0, 1e-9);
}

}  // namespace
}  // namespace mocap
