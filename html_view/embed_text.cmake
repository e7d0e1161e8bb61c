# Writes OUTPUT, a C++ source defining mocap::html_view::ViewerBundleJs() that returns the text of
# INPUT (the viewer's ASCII bundle), as raw string literals of at most 30,000 characters each (no
# compiler limit on string length is approached, and -Wpedantic stays quiet).
#   cmake -DINPUT=mocap-viewer.js -DOUTPUT=viewer_bundle.cc -P embed_text.cmake
file(READ "${INPUT}" text)
set(delimiter "mocap_viewer_js")
string(FIND "${text}" ")${delimiter}\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "${INPUT} contains the raw string delimiter )${delimiter}\"")
endif()
string(LENGTH "${text}" length)
set(chunk 30000)
set(body "")
set(position 0)
while(position LESS length)
  string(SUBSTRING "${text}" ${position} ${chunk} piece)
  string(APPEND body "    R\"${delimiter}(${piece})${delimiter}\",\n")
  math(EXPR position "${position} + ${chunk}")
endwhile()
file(WRITE "${OUTPUT}.tmp" "// Generated from ${INPUT} by html_view/embed_text.cmake: do not edit.
#include \"html_view/viewer_bundle.h\"

#include <string_view>

namespace mocap::html_view {

const std::string& ViewerBundleJs() {
  // const, not constexpr: clang gives up measuring 1.5 MB of literals at compile time.
  static const std::string_view kChunks[] = {
${body}  };
  static const std::string text = [] {
    std::string joined;
    for (std::string_view piece : kChunks) joined.append(piece);
    return joined;
  }();
  return text;
}

}  // namespace mocap::html_view
")
file(RENAME "${OUTPUT}.tmp" "${OUTPUT}")
