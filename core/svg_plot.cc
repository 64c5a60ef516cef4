#include "core/svg_plot.h"

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

}  // namespace

std::string XmlEscape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string RenderSvg(const PlotSpec& spec) {
  const double left = 64, right = 16, top = spec.title.empty() ? 16 : 34, bottom = 52;
  const double pw = spec.width - left - right, ph = spec.height - top - bottom;
  const bool bars = !spec.categories.empty();
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
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
  if (bars) {
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
  const double xs = NiceStep(x1 - x0, 6), ys = NiceStep(y1 - y0, 6);
  if (!bars) {
    x0 = std::floor(x0 / xs) * xs;
    x1 = std::ceil(x1 / xs) * xs;
  }
  y0 = std::floor(y0 / ys) * ys;
  y1 = std::ceil(y1 / ys) * ys;
  if (spec.identity_line) {
    x0 = y0 = std::min(x0, y0);
    x1 = y1 = std::max(x1, y1);
  }
  auto px = [&](double x) { return left + (x - x0) / (x1 - x0) * pw; };
  auto py = [&](double y) { return top + ph - (y - y0) / (y1 - y0) * ph; };

  std::string o;
  o += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(spec.width) +
       "\" height=\"" + std::to_string(spec.height) + "\" viewBox=\"0 0 " +
       std::to_string(spec.width) + " " + std::to_string(spec.height) +
       "\" font-family=\"sans-serif\" font-size=\"11\" role=\"img\">\n";
  o += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  if (!spec.title.empty()) {
    o += "<text x=\"" + Num(spec.width / 2.0) + "\" y=\"20\" text-anchor=\"middle\" "
         "font-size=\"13\" font-weight=\"bold\">" + XmlEscape(spec.title) + "</text>\n";
  }
  // Grid and ticks.
  for (double y = y0; y <= y1 + ys * 1e-9; y += ys) {
    o += "<line x1=\"" + Num(left) + "\" x2=\"" + Num(left + pw) + "\" y1=\"" + Num(py(y)) +
         "\" y2=\"" + Num(py(y)) + "\" stroke=\"#e4e4e4\"/>\n";
    o += "<text x=\"" + Num(left - 6) + "\" y=\"" + Num(py(y) + 4) +
         "\" text-anchor=\"end\">" + TickLabel(y, ys) + "</text>\n";
  }
  if (bars) {
    for (size_t i = 0; i < spec.categories.size(); ++i) {
      o += "<text x=\"" + Num(px(static_cast<double>(i))) + "\" y=\"" + Num(top + ph + 16) +
           "\" text-anchor=\"middle\">" + XmlEscape(spec.categories[i]) + "</text>\n";
    }
  } else {
    for (double x = x0; x <= x1 + xs * 1e-9; x += xs) {
      o += "<line x1=\"" + Num(px(x)) + "\" x2=\"" + Num(px(x)) + "\" y1=\"" + Num(top) +
           "\" y2=\"" + Num(top + ph) + "\" stroke=\"#f0f0f0\"/>\n";
      o += "<text x=\"" + Num(px(x)) + "\" y=\"" + Num(top + ph + 16) +
           "\" text-anchor=\"middle\">" + TickLabel(x, xs) + "</text>\n";
    }
  }
  o += "<rect x=\"" + Num(left) + "\" y=\"" + Num(top) + "\" width=\"" + Num(pw) +
       "\" height=\"" + Num(ph) + "\" fill=\"none\" stroke=\"#555\"/>\n";
  if (spec.identity_line) {
    o += "<line x1=\"" + Num(px(x0)) + "\" y1=\"" + Num(py(y0)) + "\" x2=\"" + Num(px(x1)) +
         "\" y2=\"" + Num(py(y1)) + "\" stroke=\"#333\" stroke-dasharray=\"5,4\"/>\n";
  }
  if (spec.zero_line) {
    o += "<line x1=\"" + Num(left) + "\" x2=\"" + Num(left + pw) + "\" y1=\"" + Num(py(0)) +
         "\" y2=\"" + Num(py(0)) + "\" stroke=\"#333\" stroke-dasharray=\"5,4\"/>\n";
  }
  // Series.
  const size_t n_series = spec.series.size();
  for (size_t si = 0; si < n_series; ++si) {
    const PlotSeries& s = spec.series[si];
    const std::string fill = s.color.empty() ? "#1f77b4" : s.color;
    if (s.style == PlotSeries::Style::kLine) {
      std::string pts;
      for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
        if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
        pts += Num(px(s.x[i])) + "," + Num(py(s.y[i])) + " ";
      }
      o += "<polyline fill=\"none\" stroke=\"" + fill + "\" stroke-width=\"2\" points=\"" +
           pts + "\"/>\n";
    } else if (s.style == PlotSeries::Style::kBars) {
      const double slot = pw / std::max<size_t>(1, spec.categories.size());
      const double bw = 0.8 * slot / static_cast<double>(std::max<size_t>(1, n_series));
      for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
        const double xc = px(s.x[i]) - 0.4 * slot + bw * (static_cast<double>(si) + 0.5);
        const double ya = py(std::max(0.0, s.y[i])), yb = py(std::min(0.0, s.y[i]));
        o += "<rect x=\"" + Num(xc - bw / 2) + "\" y=\"" + Num(ya) + "\" width=\"" + Num(bw) +
             "\" height=\"" + Num(std::max(0.5, yb - ya)) + "\" fill=\"" + fill + "\"/>\n";
      }
    } else {
      o += "<g fill=\"" + fill + "\" fill-opacity=\"" + Num(s.opacity).substr(0, 3) + "\">\n";
      for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
        if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
        o += "<circle cx=\"" + Num(px(s.x[i])) + "\" cy=\"" + Num(py(s.y[i])) + "\" r=\"" +
             Num(s.radius) + "\"/>\n";
      }
      o += "</g>\n";
    }
  }
  // Axis labels and legend.
  o += "<text x=\"" + Num(left + pw / 2) + "\" y=\"" + Num(spec.height - 12.0) +
       "\" text-anchor=\"middle\">" + XmlEscape(spec.x_label) + "</text>\n";
  o += "<text transform=\"translate(14," + Num(top + ph / 2) +
       ") rotate(-90)\" text-anchor=\"middle\">" + XmlEscape(spec.y_label) + "</text>\n";
  double ly = top + 8;
  for (const PlotSeries& s : spec.series) {
    if (s.name.empty()) continue;
    const std::string fill = s.color.empty() ? "#1f77b4" : s.color;
    o += "<rect x=\"" + Num(left + 10) + "\" y=\"" + Num(ly - 8) +
         "\" width=\"10\" height=\"10\" fill=\"" + fill + "\"/>\n";
    o += "<text x=\"" + Num(left + 24) + "\" y=\"" + Num(ly + 1) + "\">" + XmlEscape(s.name) +
         "</text>\n";
    ly += 15;
  }
  if (spec.identity_line) {
    o += "<text x=\"" + Num(left + pw - 6) + "\" y=\"" + Num(top + 14) +
         "\" text-anchor=\"end\" fill=\"#333\">dashed: 1:1</text>\n";
  }
  o += "</svg>\n";
  return o;
}

}  // namespace rollwear
