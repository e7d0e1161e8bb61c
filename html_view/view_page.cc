#include "html_view/view_page.h"

#include <algorithm>
#include <cctype>

#include "html_view/viewer_bundle.h"

namespace mocap::html_view {
namespace {

constexpr std::string_view kFullWindowCss =
    "html,body{margin:0;height:100%;background:#1d2127}#mocap-viewer{height:100vh}";
constexpr std::string_view kDocumentCss =
    "body{margin:0 auto;max-width:1200px;padding:16px 24px;background:#f7f8fa;color:#1b1f24;"
    "font:15px/1.5 system-ui,sans-serif}#mocap-viewer{height:75vh;margin:12px 0 "
    "24px;border-radius:8px;overflow:hidden}";

// A script's text with every "</script" and "<!--" made harmless ("<\/script" means the same
// inside a JavaScript string, the only place the bundle could hold one).
std::string InlineScript(const std::string& script) {
  std::string out;
  out.reserve(script.size());
  for (size_t i = 0; i < script.size(); ++i) {
    if (script[i] == '<' && i + 1 < script.size() && (script[i + 1] == '/' || script[i + 1] == '!')) {
      std::string next = script.substr(i + 1, 7);
      std::transform(next.begin(), next.end(), next.begin(), [](unsigned char c) { return std::tolower(c); });
      if (next == "/script" || next.rfind("!--", 0) == 0) {
        out += "<\\";
        continue;
      }
    }
    out += script[i];
  }
  return out;
}

// `text` with each character that `replacement` maps to a string (not null) replaced by that string.
template <typename Replacement>
std::string Escaped(std::string_view text, Replacement replacement) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    if (const char* r = replacement(c))
      out += r;
    else
      out += c;
  }
  return out;
}

}  // namespace

std::string HtmlEscape(std::string_view text) {
  return Escaped(text, [](char c) -> const char* {
    switch (c) {
      case '&':
        return "&amp;";
      case '<':
        return "&lt;";
      case '>':
        return "&gt;";
      case '"':
        return "&quot;";
      case '\'':
        return "&#39;";
      default:
        return nullptr;
    }
  });
}

std::string ScriptSafeJson(const nlohmann::json& value) {
  return Escaped(value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), [](char c) -> const char* {
    switch (c) {
      case '<':
        return "\\u003c";
      case '>':
        return "\\u003e";
      case '&':
        return "\\u0026";
      default:
        return nullptr;
    }
  });
}

std::string PageHtml(const Page& page) {
  const bool full_window = page.html_before.empty() && page.html_after.empty();
  std::string html =
      "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>";
  html += HtmlEscape(page.title);
  html += "</title>\n<style>";
  html += full_window ? kFullWindowCss : kDocumentCss;
  html += page.extra_css;
  html += "</style>\n</head>\n<body>\n";
  html += page.html_before;
  if (!page.data.is_null()) html += "\n<div id=\"mocap-viewer\"></div>\n";
  html += page.html_after;
  if (!page.data.is_null()) {
    html += "\n<script type=\"application/json\" id=\"mocap-viewer-data\">";
    html += ScriptSafeJson(page.data);
    html += "</script>\n<script>";
    html += InlineScript(ViewerBundleJs());
    html += "</script>";
  }
  html += "\n</body>\n</html>\n";
  return html;
}

}  // namespace mocap::html_view
