// The viewer's JavaScript (viewer/, three.js and the player, one minified script), compiled in at
// build time by html_view/CMakeLists.txt.
#pragma once

#include <string>

namespace mocap::html_view {

const std::string& ViewerBundleJs();

}  // namespace mocap::html_view
