// A small SVG chart renderer: scatter, line and bar series with axes, ticks,
// units, a legend and an optional 1:1 line. The one plotting module of
// rollwear: the diagnosis and study reports and the daemon's dashboard all
// draw through it, so charts look and read the same everywhere.
//
// Thread-safety: pure function.
#ifndef ROLLWEAR_CORE_REPORT_SVG_PLOT_H_
#define ROLLWEAR_CORE_REPORT_SVG_PLOT_H_

#include <string>
#include <utility>
#include <vector>

namespace rollwear {

// A figure to be written to a file (WriteFigures, study_figures.h).
struct SvgFigure {
  std::string file_name;  // "measured_vs_calculated_laws.svg"
  std::string svg;
};

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
  // Where the legend box goes (inside the plot area, on a white panel).
  enum class Legend { kTopLeft, kTopRight, kBottomRight, kNone };
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
  int font_size = 12;  // ticks and legend; titles are 2 px larger
  Legend legend = Legend::kTopLeft;
  // true: the <svg> fills its container's width (width="100%", aspect kept
  // by the viewBox), for HTML pages; false: width x height pixels.
  bool fluid = false;
};

std::string RenderSvg(const PlotSpec& spec);

// Several plots side by side in one SVG document (small multiples, e.g.
// one parity plot per stand), `columns` per row, under a common title.
std::string RenderSvgGrid(const std::string& title,
                          const std::vector<PlotSpec>& panels, int columns);

// Colour of the i-th series in the house palette (colour-blind safe,
// Okabe-Ito order), for callers that draw a series per roll position etc.
const char* PaletteColor(int i);

// Escapes &, <, >, " for XML/HTML text and attributes.
std::string XmlEscape(const std::string& text);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_REPORT_SVG_PLOT_H_
