#include "motion/skeleton/limb_segments.h"

#include <cmath>
#include <limits>

namespace mocap {
namespace {

// |log(a / b)|, infinite when either length is zero.
float LengthMismatch(float a, float b) {
  if (!(a > 1e-6f) || !(b > 1e-6f)) return std::numeric_limits<float>::infinity();
  return std::abs(std::log(a / b));
}

}  // namespace

int UpperSegmentStart(std::span<const float> cumulative, int middle) {
  const int last = static_cast<int>(cumulative.size()) - 1;
  if (middle <= 0 || middle > last) return 0;
  const float lower = cumulative[last] - cumulative[middle];
  int best = 0;
  float best_error = std::numeric_limits<float>::infinity();
  for (int i = 0; i < middle; ++i) {
    const float error = LengthMismatch(cumulative[middle] - cumulative[i], lower);
    if (error < best_error) {
      best_error = error;
      best = i;
    }
  }
  return best;
}

int LimbBendByLength(std::span<const float> cumulative) {
  const int last = static_cast<int>(cumulative.size()) - 1;
  if (last < 2) return last < 0 ? 0 : last;
  int best = 1;
  float best_error = std::numeric_limits<float>::infinity();
  for (int i = 1; i < last; ++i) {
    const float error = LengthMismatch(cumulative[i], cumulative[last] - cumulative[i]);
    if (error < best_error) {
      best_error = error;
      best = i;
    }
  }
  return best;
}

}  // namespace mocap
