// StrCat for std::string_view and numbers. Debian's absl is built with its own absl::string_view,
// so absl::StrCat does not take std::string_view; error paths use this instead.
#pragma once

#include <sstream>
#include <string>

namespace mocap {

template <typename... Args>
std::string StrCat(const Args&... args) {
  std::ostringstream out;
  out.precision(7);
  (out << ... << args);
  return out.str();
}

}  // namespace mocap
