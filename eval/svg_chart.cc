#include "eval/svg_chart.h"

#include <algorithm>
#include <cstdio>

#include "motion/core/str_cat.h"

namespace mocap::eval {
namespace {

constexpr const char* kColours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b"};
constexpr double kWidth = 760, kHeight = 420, kLeft = 70, kRight = 170, kTop = 40, kBottom = 90;

std::string Escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else
      out += c;
  }
  return out;
}

std::string Number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", v);
  return buffer;
}

double NiceMax(const std::vector<Series>& series) {
  double top = 0;
  for (const Series& s : series) {
    for (double v : s.values) top = std::max(top, v);
  }
  return top > 0 ? top * 1.1 : 1.0;
}

// Frame, title, y axis with 5 ticks, legend.
std::string Frame(const std::string& title, const std::string& y_label, double y_max,
                  const std::vector<Series>& series) {
  std::string svg = StrCat(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"", kWidth, "\" height=\"", kHeight,
      "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
      "<text x=\"", kWidth / 2, "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">", Escape(title), "</text>\n");
  const double plot_h = kHeight - kTop - kBottom;
  for (int i = 0; i <= 5; ++i) {
    const double v = y_max * i / 5, y = kTop + plot_h * (1 - i / 5.0);
    svg += StrCat("<line x1=\"", kLeft, "\" x2=\"", kWidth - kRight, "\" y1=\"", y, "\" y2=\"", y,
                  "\" stroke=\"#ddd\"/>\n", "<text x=\"", kLeft - 6, "\" y=\"", y + 4, "\" text-anchor=\"end\">",
                  Number(v), "</text>\n");
  }
  svg += StrCat("<text transform=\"translate(16,", kTop + plot_h / 2, ") rotate(-90)\" text-anchor=\"middle\">",
                Escape(y_label), "</text>\n");
  for (size_t s = 0; s < series.size(); ++s) {
    const double y = kTop + 10 + 20.0 * static_cast<double>(s);
    svg += StrCat("<rect x=\"", kWidth - kRight + 15, "\" y=\"", y - 9, "\" width=\"12\" height=\"12\" fill=\"",
                  kColours[s % 6], "\"/>", "<text x=\"", kWidth - kRight + 32, "\" y=\"", y + 1, "\">",
                  Escape(series[s].name), "</text>\n");
  }
  return svg;
}

}  // namespace

std::string BarChartSvg(const std::string& title, const std::string& y_label,
                        const std::vector<std::string>& categories, const std::vector<Series>& series) {
  const double y_max = NiceMax(series);
  std::string svg = Frame(title, y_label, y_max, series);
  const double plot_w = kWidth - kLeft - kRight, plot_h = kHeight - kTop - kBottom;
  const double group = plot_w / std::max<size_t>(1, categories.size());
  const double bar = group * 0.8 / std::max<size_t>(1, series.size());
  for (size_t c = 0; c < categories.size(); ++c) {
    const double x0 = kLeft + group * static_cast<double>(c) + group * 0.1;
    for (size_t s = 0; s < series.size(); ++s) {
      const double v = c < series[s].values.size() ? series[s].values[c] : 0.0;
      const double h = plot_h * v / y_max;
      svg += StrCat("<rect x=\"", x0 + bar * static_cast<double>(s), "\" y=\"", kTop + plot_h - h, "\" width=\"",
                    bar * 0.95, "\" height=\"", h, "\" fill=\"", kColours[s % 6], "\"><title>", Escape(series[s].name),
                    ": ", Number(v), "</title></rect>\n");
    }
    svg += StrCat("<text transform=\"translate(", x0 + group * 0.4, ",", kTop + plot_h + 12, ") rotate(30)\">",
                  Escape(categories[c]), "</text>\n");
  }
  return svg + "</svg>\n";
}

std::string LineChartSvg(const std::string& title, const std::string& x_label, const std::string& y_label,
                         const std::vector<double>& x, const std::vector<Series>& series) {
  const double y_max = NiceMax(series);
  std::string svg = Frame(title, y_label, y_max, series);
  const double plot_w = kWidth - kLeft - kRight, plot_h = kHeight - kTop - kBottom;
  const double x_min = x.empty() ? 0 : *std::min_element(x.begin(), x.end());
  const double x_max = x.empty() ? 1 : std::max(x_min + 1e-9, *std::max_element(x.begin(), x.end()));
  auto px = [&](double v) { return kLeft + plot_w * (v - x_min) / (x_max - x_min); };
  auto py = [&](double v) { return kTop + plot_h * (1 - v / y_max); };
  for (double v : x) {
    svg += StrCat("<text x=\"", px(v), "\" y=\"", kTop + plot_h + 16, "\" text-anchor=\"middle\">", Number(v),
                  "</text>\n");
  }
  svg += StrCat("<text x=\"", kLeft + plot_w / 2, "\" y=\"", kTop + plot_h + 36, "\" text-anchor=\"middle\">",
                Escape(x_label), "</text>\n");
  for (size_t s = 0; s < series.size(); ++s) {
    std::string points;
    for (size_t i = 0; i < x.size() && i < series[s].values.size(); ++i) {
      points += StrCat(px(x[i]), ",", py(series[s].values[i]), " ");
      svg += StrCat("<circle cx=\"", px(x[i]), "\" cy=\"", py(series[s].values[i]), "\" r=\"3\" fill=\"",
                    kColours[s % 6], "\"><title>", Number(series[s].values[i]), "</title></circle>\n");
    }
    svg += StrCat("<polyline fill=\"none\" stroke-width=\"2\" stroke=\"", kColours[s % 6], "\" points=\"", points,
                  "\"/>\n");
  }
  return svg + "</svg>\n";
}

}  // namespace mocap::eval
