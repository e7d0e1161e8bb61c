// A self-contained HTML page around the viewer: the page's own HTML (a title, optionally a report
// before the player), the clips as JSON data and the viewer's script, all inline — it opens from
// a file, offline, in any modern browser.
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace mocap::html_view {

struct Page {
  std::string title;
  // {"layout": "overlay" | "side-by-side", "follow": bool, "scenes": [{"label", "clips": [ClipJson(...), ...]}, ...]};
  // null: a page without the player.
  nlohmann::json data;
  // HTML placed before and after the player (escaped by the caller); empty: the player fills the window.
  std::string html_before, html_after;
  std::string extra_css;
};

std::string PageHtml(const Page& page);

// Text for HTML element content and attribute values (& < > " ').
std::string HtmlEscape(std::string_view text);

// JSON that cannot end the <script> element carrying it: '<', '>' and '&' as \u escapes (they
// occur only inside JSON strings, where the escapes mean the same); invalid UTF-8 replaced.
std::string ScriptSafeJson(const nlohmann::json& value);

}  // namespace mocap::html_view
