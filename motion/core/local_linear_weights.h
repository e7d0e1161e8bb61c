// A kernel's weights for a line fitted through the taps there are (local linear regression): the
// value at the centre of the weighted least-squares line x(i) ≈ a + b·i over offsets [low, high]
// is Σ cᵢ·xᵢ. Inside the data (every tap there) it is the kernel's own weighted mean; where the
// kernel reaches past the newest (or oldest) sample it has no lag for steady motion, where
// repeating the end sample lags by the kernel's weight beyond it.
#pragma once

#include <algorithm>
#include <span>
#include <vector>

namespace mocap {

// `kernel`: 2r + 1 non-negative weights for offsets −r..r. Writes the 2r + 1 coefficients cᵢ
// (zero outside [low, high], which is clamped to [−r, r]; they sum to 1) into `weights`. With a
// single tap, or taps that do not spread, the fit is the weighted mean of what there is.
inline void LocalLinearWeights(std::span<const float> kernel, int low, int high, std::vector<float>* weights) {
  const int radius = static_cast<int>(kernel.size()) / 2;
  low = std::max(low, -radius);
  high = std::min(high, radius);
  weights->assign(kernel.size(), 0.0f);
  float sum = 0.0f, mean = 0.0f;
  for (int i = low; i <= high; ++i) {
    sum += kernel[i + radius];
    mean += kernel[i + radius] * static_cast<float>(i);
  }
  if (sum <= 0.0f) return;
  mean /= sum;
  float spread = 0.0f;
  for (int i = low; i <= high; ++i)
    spread += kernel[i + radius] * (static_cast<float>(i) - mean) * (static_cast<float>(i) - mean);
  // a = x̄ − ī·b with b = Σ wᵢ (i − ī)(xᵢ − x̄) / spread, so cᵢ = wᵢ (1 / Σw − ī (i − ī) / spread).
  const float tilt = spread > 1e-6f ? mean / spread : 0.0f;
  for (int i = low; i <= high; ++i)
    (*weights)[i + radius] = kernel[i + radius] * (1.0f / sum - tilt * (static_cast<float>(i) - mean));
}

}  // namespace mocap
