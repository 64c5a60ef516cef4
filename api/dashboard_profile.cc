// The dashboard's profile section (api/dashboard_page.h): each mounted
// roll's predicted wear across the barrel with its 95 % interval, and the
// measured against predicted profiles of the last ended campaigns with
// grinder profiles. A roll or a model without a calibrated profile shape
// gets no predicted curve: the page says there is no profile model yet
// (the default g = 1 is a placeholder, not a prediction to steer by).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "api/dashboard_page.h"
#include "core/dataset/dataset.h"
#include "core/report/svg_plot.h"

namespace rollwear {
namespace {

// Columns of the profile panels' grids.
constexpr int kProfileColumns = 4;

// `values` space-separated with 9 significant digits (the markers the
// end-to-end test reads back).
std::string Numbers(const std::vector<double>& values) {
  std::string out;
  char buf[32];
  for (size_t i = 0; i < values.size(); ++i) {
    std::snprintf(buf, sizeof(buf), "%.9g", values[i]);
    if (i > 0) out += ' ';
    out += buf;
  }
  return out;
}

std::string Data(const char* name, const std::string& value) {
  return std::string(" data-") + name + "=\"" + XmlEscape(value) + "\"";
}

std::string RollName(int stand, const std::string& position) {
  return StandName(stand) + " " + position;
}

PlotSpec ProfilePanel(const std::string& title, int columns) {
  PlotSpec spec;
  spec.title = title;
  spec.x_label = "x (mm), + drive side";
  spec.y_label = "wear (µm)";
  spec.width = 830 / columns;
  spec.height = 250;
  spec.font_size = 12;
  spec.fluid = true;
  spec.legend = PlotSpec::Legend::kNone;
  return spec;
}

PlotSeries Line(const char* color, const std::vector<double>& x,
                const std::vector<double>& y, double opacity) {
  PlotSeries s = PlotSeries::Make("", color, PlotSeries::Style::kLine);
  s.x = x;
  s.y = y;
  s.opacity = opacity;
  return s;
}

// One mounted roll's panel: the predicted profile and its interval, or the
// note that it has no profile model yet.
std::string MountedPanel(const DashboardRoll& r, int index, int columns,
                         std::string* uncalibrated) {
  std::string div =
      "<div class=\"roll-profile\"" + Data("stand", std::to_string(r.stand)) +
      Data("position", r.position) + Data("shape", r.profile_shape);
  if (r.profile_shape != "calibrated") {
    if (!uncalibrated->empty()) *uncalibrated += ", ";
    *uncalibrated += RollName(r.stand, r.position);
    return div + "></div>\n";
  }
  div += Data("x-mm", Numbers(r.profile_x_mm)) +
         Data("wear-um", Numbers(r.profile_wear_um)) +
         Data("lo-um", Numbers(r.profile_lo_um)) +
         Data("hi-um", Numbers(r.profile_hi_um)) + ">";
  PlotSpec spec =
      ProfilePanel(RollName(r.stand, r.position) + " " + r.roll_id, columns);
  const char* color = PaletteColor(index);
  spec.series.push_back(Line(color, r.profile_x_mm, r.profile_lo_um, 0.35));
  spec.series.push_back(Line(color, r.profile_x_mm, r.profile_hi_um, 0.35));
  spec.series.push_back(Line(color, r.profile_x_mm, r.profile_wear_um, 1));
  return div + RenderSvg(spec) + "</div>\n";
}

std::string MountedProfiles(const DashboardData& d) {
  std::string panels, uncalibrated;
  const int columns =
      std::clamp(static_cast<int>(d.rolls.size()), 1, kProfileColumns);
  for (size_t i = 0; i < d.rolls.size(); ++i) {
    panels +=
        MountedPanel(d.rolls[i], static_cast<int>(i), columns, &uncalibrated);
  }
  std::string s =
      "<h3>Predicted profile of each mounted roll <small>active "
      "model; thin lines: 95 % interval</small></h3>\n";
  if (d.rolls.empty()) {
    return s + "<p class=\"empty\">No roll mounted.</p>\n";
  }
  if (!uncalibrated.empty()) {
    s += "<p class=\"empty\" id=\"profile-uncalibrated\">No profile model "
         "yet for " +
         XmlEscape(uncalibrated) +
         ": the active model has no calibrated profile shape, so no "
         "predicted profile is drawn (post grinder profiles and "
         "calibrate).</p>\n";
  }
  return s + "<div class=\"grid\" style=\"grid-template-columns:repeat(" +
         std::to_string(columns) + ",minmax(0,1fr))\">\n" + panels + "</div>\n";
}

std::string MeasuredPanel(const DashboardMeasuredProfile& p, int columns) {
  std::string div =
      "<div class=\"measured-profile\"" + Data("campaign-id", p.campaign_id) +
      Data("stand", std::to_string(p.stand)) + Data("position", p.position) +
      Data("x-mm", Numbers(p.x_mm)) +
      Data("measured-um", Numbers(p.measured_um)) +
      Data("predicted-um", p.calibrated ? Numbers(p.predicted_um) : "") + ">";
  PlotSpec spec = ProfilePanel(
      p.campaign_id + " " + RollName(p.stand, p.position), columns);
  PlotSeries measured =
      PlotSeries::Make("measured", "#d62728", PlotSeries::Style::kPoints);
  measured.x = p.x_mm;
  measured.y = p.measured_um;
  measured.radius = 2.5;
  spec.series.push_back(std::move(measured));
  if (p.calibrated) {
    // The points in barrel order, so that the line does not zigzag.
    std::vector<size_t> order(p.x_mm.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return p.x_mm[a] < p.x_mm[b]; });
    PlotSeries predicted =
        PlotSeries::Make("predicted", "#1f77b4", PlotSeries::Style::kLine);
    for (size_t i : order) {
      predicted.x.push_back(p.x_mm[i]);
      predicted.y.push_back(p.predicted_um[i]);
    }
    spec.series.push_back(std::move(predicted));
  }
  return div + RenderSvg(spec) + "</div>\n";
}

std::string MeasuredProfiles(const DashboardData& d) {
  std::string s =
      "<h3>Measured against predicted profiles, last ended "
      "campaigns <small>red points: the grinder's; blue line: "
      "the active model's prediction</small>"
      "</h3>\n";
  if (d.measured_profiles.empty()) {
    return s +
           "<p class=\"empty\">No grinder profile of an ended campaign "
           "yet.</p>\n";
  }
  const bool calibrated = d.measured_profiles.front().calibrated;
  if (!calibrated) {
    s += "<p class=\"empty\" id=\"measured-uncalibrated\">No profile model "
         "yet: the measured profiles are drawn without a prediction.</p>\n";
  }
  const int columns = std::clamp(static_cast<int>(d.measured_profiles.size()),
                                 1, kProfileColumns);
  s += "<div class=\"grid\" style=\"grid-template-columns:repeat(" +
       std::to_string(columns) + ",minmax(0,1fr))\">\n";
  for (const DashboardMeasuredProfile& p : d.measured_profiles) {
    s += MeasuredPanel(p, columns);
  }
  return s + "</div>\n";
}

}  // namespace

std::string DashboardProfileSection(const DashboardData& d) {
  return "<section id=\"profiles\"><h2>Wear profile across the barrel "
         "<small>x: mm from the barrel centre</small></h2>\n" +
         MountedProfiles(d) + MeasuredProfiles(d) + "</section>\n";
}

}  // namespace rollwear
