// Numbers in mocap-eval's reports: fixed-point with a given number of decimals.
#pragma once

#include <cstdio>
#include <string>

namespace mocap::eval {

inline std::string Fixed(double v, int digits = 2) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, v);
  return buffer;
}

}  // namespace mocap::eval
