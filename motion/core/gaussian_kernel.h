// Gaussian filter weights over frames, shared by the ankle (A4) and joint-space (A7) filters.
#pragma once

#include <cmath>
#include <vector>

namespace mocap {

// Weights for offsets −r..r (r = ⌈3σ⌉), normalised to sum 1; {1} when σ ≤ 0.
inline std::vector<float> GaussianKernel(float sigma_frames) {
  if (sigma_frames <= 0.0f) return {1.0f};
  const int radius = static_cast<int>(std::ceil(3.0f * sigma_frames));
  std::vector<float> kernel(2 * radius + 1);
  float sum = 0.0f;
  for (int i = -radius; i <= radius; ++i) {
    kernel[i + radius] = std::exp(-0.5f * static_cast<float>(i * i) / (sigma_frames * sigma_frames));
    sum += kernel[i + radius];
  }
  for (float& w : kernel) w /= sum;
  return kernel;
}

inline int GaussianRadius(float sigma_frames) {
  return sigma_frames <= 0.0f ? 0 : static_cast<int>(std::ceil(3.0f * sigma_frames));
}

}  // namespace mocap
