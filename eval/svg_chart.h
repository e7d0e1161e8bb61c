// Small SVG charts for the evaluation report (grouped bars, lines), readable in any browser.
#pragma once

#include <string>
#include <vector>

namespace mocap::eval {

struct Series {
  std::string name;
  std::vector<double> values;  // one per category / x value
};

// Grouped bar chart: one group per category, one bar per series.
std::string BarChartSvg(const std::string& title, const std::string& y_label,
                        const std::vector<std::string>& categories, const std::vector<Series>& series);

// Line chart over numeric x values (shared by all series).
std::string LineChartSvg(const std::string& title, const std::string& x_label, const std::string& y_label,
                         const std::vector<double>& x, const std::vector<Series>& series);

}  // namespace mocap::eval
