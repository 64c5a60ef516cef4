// A small SVG chart renderer: scatter, line and bar series with axes, ticks,
// units, a legend and an optional 1:1 line. The one plotting module of
// rollwear: the diagnosis and study reports and the daemon's dashboard all
// draw through it, so charts look and read the same everywhere.
//
// Thread-safety: pure function.
#ifndef ROLLWEAR_CORE_SVG_PLOT_H_
#define ROLLWEAR_CORE_SVG_PLOT_H_

#include <string>
#include <utility>
#include <vector>

namespace rollwear {

struct PlotSeries {
  enum class Style { kPoints, kLine, kBars };
  std::string name;   // legend entry ("" = not in the legend)
  std::string color;  // CSS colour
  Style style = Style::kPoints;
  std::vector<double> x, y;
  double radius = 2.5;  // points
  double opacity = 0.7;

  static PlotSeries Make(std::string name, std::string color, Style style) {
    PlotSeries s;
    s.name = std::move(name);
    s.color = std::move(color);
    s.style = style;
    return s;
  }
};

struct PlotSpec {
  std::string title;
  std::string x_label;  // with unit, e.g. "measured wear (µm)"
  std::string y_label;
  std::vector<PlotSeries> series;
  bool identity_line = false;  // 1:1 line for parity plots (equal axes)
  bool zero_line = false;      // horizontal y = 0 (residual plots)
  // Bar charts: category labels on the x axis (x values are indices).
  std::vector<std::string> categories;
  int width = 520;
  int height = 380;
};

std::string RenderSvg(const PlotSpec& spec);

// Escapes &, <, >, " for XML/HTML text and attributes.
std::string XmlEscape(const std::string& text);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_SVG_PLOT_H_
