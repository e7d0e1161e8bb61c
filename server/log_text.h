// Client-supplied text (labels, database and file names, error messages that quote them) made
// safe for one log line: control characters, quotes, backslashes and bytes outside printable
// ASCII are escaped (\n, \", \x1b, ...), and the text is cut to `max_bytes` with the length of what
// was left out, so a client can neither forge a log line nor flood the log.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace mocap {

inline constexpr size_t kMaxLoggedTextBytes = 200;

std::string LogText(std::string_view text, size_t max_bytes = kMaxLoggedTextBytes);

}  // namespace mocap
