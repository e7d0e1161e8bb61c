#include "server/log_text.h"

#include <algorithm>

namespace mocap {

std::string LogText(std::string_view text, size_t max_bytes) {
  std::string out;
  const size_t kept = std::min(text.size(), max_bytes);
  out.reserve(kept + 16);
  static constexpr char kHex[] = "0123456789abcdef";
  for (size_t i = 0; i < kept; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    switch (c) {
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      default:
        if (c >= 0x20 && c < 0x7f) {
          out += static_cast<char>(c);
        } else {
          out += "\\x";
          out += kHex[c >> 4];
          out += kHex[c & 15];
        }
    }
  }
  if (kept < text.size()) out += "...(+" + std::to_string(text.size() - kept) + " bytes)";
  return out;
}

}  // namespace mocap
