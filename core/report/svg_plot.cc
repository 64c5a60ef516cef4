#include "core/report/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace rollwear {
namespace {

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.1f", v);
  return buf;
}

// "Nice" tick step for a range (Heckbert, Graphics Gems 1990).
double NiceStep(double range, int target) {
  const double raw = range / std::max(1, target);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / mag;
  const double nice = f < 1.5 ? 1 : (f < 3 ? 2 : (f < 7 ? 5 : 10));
  return nice * mag;
}

std::string TickLabel(double v, double step) {
  char buf[32];
  if (std::abs(v) < step * 1e-9) v = 0;
  if (step >= 1 && std::abs(v) < 1e6) {
    std::snprintf(buf, sizeof(buf), "%.0f", v);
  } else {
    std::snprintf(buf, sizeof(buf), "%.3g", v);
  }
  return buf;
}

// Rough width of `text` in pixels at `font_size` (sans-serif averages about
// 0.58 em per character; µ and other multi-byte characters count once).
double TextWidth(const std::string& text, int font_size) {
  int chars = 0;
  for (unsigned char c : text) {
    if ((c & 0xC0) != 0x80) ++chars;
  }
  return 0.58 * font_size * chars;
}

std::string ColorOf(const PlotSeries& s, size_t i) {
  return s.color.empty() ? PaletteColor(static_cast<int>(i)) : s.color;
}

// The plot area of one panel: font size, margins, data ranges and tick
// steps, and the data-to-pixel maps.
struct PlotFrame {
  int fs = 0;
  double left = 0, top = 0, pw = 0, ph = 0;
  bool bars = false;
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;  // data range of the frame
  double xs = 0, ys = 0;                  // tick steps
  double Px(double x) const { return left + (x - x0) / (x1 - x0) * pw; }
  double Py(double y) const { return top + ph - (y - y0) / (y1 - y0) * ph; }
};

// Margins, the data range of the finite points (widened for bars, the 1:1
// line and the zero line) and the "nice" ticks, rounded out to whole steps.
PlotFrame LayOut(const PlotSpec& spec) {
  PlotFrame f;
  const int fs = f.fs = std::max(8, spec.font_size);
  f.left = 2.2 * fs + 4.2 * fs * 0.58 + 8;
  const double right = 14;
  // Room above the frame for the title, or for the 1:1 label.
  f.top = !spec.title.empty()  ? 2.4 * fs + 6
          : spec.identity_line ? 1.4 * fs + 4
                               : 12;
  const double bottom = 2.9 * fs + 10;
  f.pw = spec.width - f.left - right;
  f.ph = spec.height - f.top - bottom;
  f.bars = !spec.categories.empty();
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0,
         y1 = -x0;
  for (const PlotSeries& s : spec.series) {
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x0 = std::min(x0, s.x[i]);
      x1 = std::max(x1, s.x[i]);
      y0 = std::min(y0, s.y[i]);
      y1 = std::max(y1, s.y[i]);
    }
  }
  if (!std::isfinite(x0)) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  if (f.bars) {
    x0 = -0.5;
    x1 = static_cast<double>(spec.categories.size()) - 0.5;
    y0 = std::min(0.0, y0);
    y1 = std::max(0.0, y1);
  }
  if (spec.identity_line) {
    x0 = y0 = std::min(x0, y0);
    x1 = y1 = std::max(x1, y1);
  }
  if (spec.zero_line) {
    y0 = std::min(y0, 0.0);
    y1 = std::max(y1, 0.0);
  }
  if (x1 <= x0) x1 = x0 + 1;
  if (y1 <= y0) y1 = y0 + 1;
  const int x_ticks = std::max(2, static_cast<int>(f.pw / (6.5 * fs)));
  const int y_ticks = std::max(2, static_cast<int>(f.ph / (3.2 * fs)));
  double xs = NiceStep(x1 - x0, std::min(6, x_ticks));
  double ys = NiceStep(y1 - y0, std::min(6, y_ticks));
  if (!f.bars) {
    x0 = std::floor(x0 / xs) * xs;
    x1 = std::ceil(x1 / xs) * xs;
  }
  y0 = std::floor(y0 / ys) * ys;
  y1 = std::ceil(y1 / ys) * ys;
  if (spec.identity_line) {
    x0 = y0 = std::min(x0, y0);
    x1 = y1 = std::max(x1, y1);
    xs = ys = std::max(xs, ys);
  }
  f.x0 = x0, f.x1 = x1, f.y0 = y0, f.y1 = y1, f.xs = xs, f.ys = ys;
  return f;
}

// The <svg> element, white background and title.
void AppendOpening(const PlotSpec& spec, const PlotFrame& f, std::string* out) {
  std::string& o = *out;
  const int fs = f.fs;
  const std::string w = std::to_string(spec.width),
                    h = std::to_string(spec.height);
  o += "<svg xmlns=\"http://www.w3.org/2000/svg\" ";
  o += spec.fluid ? std::string("width=\"100%\" ")
                  : "width=\"" + w + "\" height=\"" + h + "\" ";
  o += "viewBox=\"0 0 " + w + " " + h +
       "\" font-family=\"DejaVu Sans, Verdana, sans-serif\" font-size=\"" +
       std::to_string(fs) + "\" role=\"img\"";
  if (!spec.title.empty()) {
    o += " aria-label=\"" + XmlEscape(spec.title) + "\"";
  }
  o += ">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  if (!spec.title.empty()) {
    o += "<text x=\"" + Num(f.left + f.pw / 2) + "\" y=\"" + Num(1.5 * fs + 2) +
         "\" text-anchor=\"middle\" font-size=\"" + std::to_string(fs + 2) +
         "\" font-weight=\"bold\">" + XmlEscape(spec.title) + "</text>\n";
  }
}

// Grid, ticks (category labels for bars), the frame, the 1:1 line and the
// zero line.
void AppendAxes(const PlotSpec& spec, const PlotFrame& f, std::string* out) {
  std::string& o = *out;
  const int fs = f.fs;
  const double left = f.left, top = f.top, pw = f.pw, ph = f.ph;
  for (double y = f.y0; y <= f.y1 + f.ys * 1e-9; y += f.ys) {
    o += "<line x1=\"" + Num(left) + "\" x2=\"" + Num(left + pw) + "\" y1=\"" +
         Num(f.Py(y)) + "\" y2=\"" + Num(f.Py(y)) + "\" stroke=\"#e4e4e4\"/>\n";
    o += "<text x=\"" + Num(left - 6) + "\" y=\"" + Num(f.Py(y) + 0.35 * fs) +
         "\" text-anchor=\"end\">" + TickLabel(y, f.ys) + "</text>\n";
  }
  if (f.bars) {
    for (size_t i = 0; i < spec.categories.size(); ++i) {
      o += "<text x=\"" + Num(f.Px(static_cast<double>(i))) + "\" y=\"" +
           Num(top + ph + 1.4 * fs) + "\" text-anchor=\"middle\">" +
           XmlEscape(spec.categories[i]) + "</text>\n";
    }
  } else {
    for (double x = f.x0; x <= f.x1 + f.xs * 1e-9; x += f.xs) {
      o += "<line x1=\"" + Num(f.Px(x)) + "\" x2=\"" + Num(f.Px(x)) +
           "\" y1=\"" + Num(top) + "\" y2=\"" + Num(top + ph) +
           "\" stroke=\"#eeeeee\"/>\n";
      o += "<text x=\"" + Num(f.Px(x)) + "\" y=\"" + Num(top + ph + 1.4 * fs) +
           "\" text-anchor=\"middle\">" + TickLabel(x, f.xs) + "</text>\n";
    }
  }
  o += "<rect x=\"" + Num(left) + "\" y=\"" + Num(top) + "\" width=\"" +
       Num(pw) + "\" height=\"" + Num(ph) +
       "\" fill=\"none\" stroke=\"#555\"/>\n";
  if (spec.identity_line) {
    o += "<line class=\"identity\" x1=\"" + Num(f.Px(f.x0)) + "\" y1=\"" +
         Num(f.Py(f.y0)) + "\" x2=\"" + Num(f.Px(f.x1)) + "\" y2=\"" +
         Num(f.Py(f.y1)) +
         "\" stroke=\"#333\" stroke-width=\"1.2\" stroke-dasharray=\"6,4\"/>\n";
    // Label where the line leaves the frame (top right corner), outside the
    // plot area so that it never hides a point.
    o += "<text x=\"" + Num(f.Px(f.x1)) + "\" y=\"" + Num(top - 0.35 * fs) +
         "\" text-anchor=\"end\" fill=\"#333\">1:1 ↗</text>\n";
  }
  if (spec.zero_line) {
    o += "<line x1=\"" + Num(left) + "\" x2=\"" + Num(left + pw) + "\" y1=\"" +
         Num(f.Py(0)) + "\" y2=\"" + Num(f.Py(0)) +
         "\" stroke=\"#333\" stroke-dasharray=\"5,4\"/>\n";
  }
}

// Every series: a polyline, grouped bars or a group of circles.
void AppendSeries(const PlotSpec& spec, const PlotFrame& f, std::string* out) {
  std::string& o = *out;
  const size_t n_series = spec.series.size();
  for (size_t si = 0; si < n_series; ++si) {
    const PlotSeries& s = spec.series[si];
    const std::string fill = ColorOf(s, si);
    if (s.style == PlotSeries::Style::kLine) {
      std::string pts;
      for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
        if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
        pts += Num(f.Px(s.x[i])) + "," + Num(f.Py(s.y[i])) + " ";
      }
      o += "<polyline fill=\"none\" stroke=\"" + fill +
           "\" stroke-width=\"2.2\" stroke-linejoin=\"round\" points=\"" + pts +
           "\"/>\n";
    } else if (s.style == PlotSeries::Style::kBars) {
      const double slot = f.pw / std::max<size_t>(1, spec.categories.size());
      const double bw =
          0.8 * slot / static_cast<double>(std::max<size_t>(1, n_series));
      for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
        const double xc =
            f.Px(s.x[i]) - 0.4 * slot + bw * (static_cast<double>(si) + 0.5);
        const double ya = f.Py(std::max(0.0, s.y[i])),
                     yb = f.Py(std::min(0.0, s.y[i]));
        o += "<rect x=\"" + Num(xc - bw / 2) + "\" y=\"" + Num(ya) +
             "\" width=\"" + Num(bw) + "\" height=\"" +
             Num(std::max(0.5, yb - ya)) + "\" fill=\"" + fill + "\"/>\n";
      }
    } else {
      char opacity[16];
      std::snprintf(opacity, sizeof(opacity), "%.2f", s.opacity);
      o += "<g fill=\"" + fill + "\" fill-opacity=\"" + opacity + "\">\n";
      for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
        if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
        o += "<circle cx=\"" + Num(f.Px(s.x[i])) + "\" cy=\"" +
             Num(f.Py(s.y[i])) + "\" r=\"" + Num(s.radius) + "\"/>\n";
      }
      o += "</g>\n";
    }
  }
}

void AppendAxisLabels(const PlotSpec& spec, const PlotFrame& f,
                      std::string* out) {
  *out += "<text x=\"" + Num(f.left + f.pw / 2) + "\" y=\"" +
          Num(spec.height - 0.6 * f.fs) + "\" text-anchor=\"middle\">" +
          XmlEscape(spec.x_label) + "</text>\n";
  *out += "<text transform=\"translate(" + Num(1.1 * f.fs) + "," +
          Num(f.top + f.ph / 2) + ") rotate(-90)\" text-anchor=\"middle\">" +
          XmlEscape(spec.y_label) + "</text>\n";
}

// The legend of the named series, on a white panel inside the plot area.
void AppendLegend(const PlotSpec& spec, const PlotFrame& f, std::string* out) {
  std::string& o = *out;
  const int fs = f.fs;
  std::vector<size_t> entries;
  double text_w = 0;
  for (size_t si = 0; si < spec.series.size(); ++si) {
    if (spec.series[si].name.empty()) continue;
    entries.push_back(si);
    text_w = std::max(text_w, TextWidth(spec.series[si].name, fs));
  }
  if (spec.legend == PlotSpec::Legend::kNone || entries.empty()) return;
  const double line_h = 1.35 * fs, pad = 0.5 * fs;
  const double box_w = text_w + 1.6 * fs + 2 * pad;
  const double box_h =
      line_h * static_cast<double>(entries.size()) + 2 * pad - 0.3 * fs;
  double bx = f.left + 8, by = f.top + 8;
  if (spec.legend == PlotSpec::Legend::kTopRight) {
    bx = f.left + f.pw - 8 - box_w;
  }
  if (spec.legend == PlotSpec::Legend::kBottomRight) {
    bx = f.left + f.pw - 8 - box_w;
    by = f.top + f.ph - 8 - box_h;
  }
  o += "<rect x=\"" + Num(bx) + "\" y=\"" + Num(by) + "\" width=\"" +
       Num(box_w) + "\" height=\"" + Num(box_h) +
       "\" fill=\"white\" fill-opacity=\"0.88\" stroke=\"#bbbbbb\"/>\n";
  double ly = by + pad;
  for (size_t si : entries) {
    const PlotSeries& s = spec.series[si];
    const std::string fill = ColorOf(s, si);
    if (s.style == PlotSeries::Style::kLine) {
      o += "<line x1=\"" + Num(bx + pad) + "\" x2=\"" + Num(bx + pad + fs) +
           "\" y1=\"" + Num(ly + 0.45 * fs) + "\" y2=\"" + Num(ly + 0.45 * fs) +
           "\" stroke=\"" + fill + "\" stroke-width=\"3\"/>\n";
    } else if (s.style == PlotSeries::Style::kPoints) {
      o += "<circle cx=\"" + Num(bx + pad + 0.5 * fs) + "\" cy=\"" +
           Num(ly + 0.45 * fs) + "\" r=\"" + Num(0.35 * fs) + "\" fill=\"" +
           fill + "\"/>\n";
    } else {
      o += "<rect x=\"" + Num(bx + pad) + "\" y=\"" + Num(ly) + "\" width=\"" +
           Num(0.9 * fs) + "\" height=\"" + Num(0.9 * fs) + "\" fill=\"" +
           fill + "\"/>\n";
    }
    o += "<text x=\"" + Num(bx + pad + 1.5 * fs) + "\" y=\"" +
         Num(ly + 0.85 * fs) + "\">" + XmlEscape(s.name) + "</text>\n";
    ly += line_h;
  }
}

}  // namespace

const char* PaletteColor(int i) {
  static const char* const kPalette[] = {"#0072B2", "#D55E00", "#009E73",
                                         "#CC79A7", "#E69F00", "#56B4E9",
                                         "#000000", "#F0E442"};
  constexpr int kSize = sizeof(kPalette) / sizeof(kPalette[0]);
  return kPalette[((i % kSize) + kSize) % kSize];
}

std::string XmlEscape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string RenderSvg(const PlotSpec& spec) {
  const PlotFrame f = LayOut(spec);
  std::string o;
  AppendOpening(spec, f, &o);
  AppendAxes(spec, f, &o);
  AppendSeries(spec, f, &o);
  AppendAxisLabels(spec, f, &o);
  AppendLegend(spec, f, &o);
  o += "</svg>\n";
  return o;
}

std::string RenderSvgGrid(const std::string& title,
                          const std::vector<PlotSpec>& panels, int columns) {
  columns = std::max(1, columns);
  const int n = static_cast<int>(panels.size());
  const int rows = (n + columns - 1) / columns;
  int cell_w = 0, cell_h = 0;
  for (const PlotSpec& p : panels) {
    cell_w = std::max(cell_w, p.width);
    cell_h = std::max(cell_h, p.height);
  }
  const int title_h = title.empty() ? 0 : 30;
  const int width = cell_w * std::min(columns, std::max(1, n));
  const int height = title_h + cell_h * rows;
  std::string o = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" +
                  std::to_string(width) + "\" height=\"" +
                  std::to_string(height) + "\" viewBox=\"0 0 " +
                  std::to_string(width) + " " + std::to_string(height) +
                  "\" font-family=\"DejaVu Sans, Verdana, sans-serif\">\n"
                  "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  if (!title.empty()) {
    o += "<text x=\"" + Num(width / 2.0) +
         "\" y=\"21\" text-anchor=\"middle\" font-size=\"16\" "
         "font-weight=\"bold\">" +
         XmlEscape(title) + "</text>\n";
  }
  for (int i = 0; i < n; ++i) {
    PlotSpec p = panels[i];
    p.fluid = false;
    std::string panel = RenderSvg(p);
    // Place the panel: a nested <svg> with x/y.
    const std::string pos =
        "<svg x=\"" + std::to_string((i % columns) * cell_w) + "\" y=\"" +
        std::to_string(title_h + (i / columns) * cell_h) + "\" ";
    panel.replace(0, std::string("<svg ").size(), pos);
    o += panel;
  }
  o += "</svg>\n";
  return o;
}

}  // namespace rollwear
