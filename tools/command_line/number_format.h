// Numbers as the tools print them for people.
#pragma once

#include <string>

namespace mocap {

// 1234567.4 -> "1,234,567" (rounded to a whole number).
inline std::string Thousands(double value) {
  std::string digits = std::to_string(static_cast<long long>(value + 0.5));
  for (int i = static_cast<int>(digits.size()) - 3; i > 0; i -= 3) digits.insert(static_cast<size_t>(i), ",");
  return digits;
}

}  // namespace mocap
