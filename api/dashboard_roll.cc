// GET /rolls/{roll_id}: the roll page of the dashboard, linked from the
// mounted-rolls table of GET / (api/dashboard_page.cc). One roll's life
// across campaigns (MillStore::GetRollLife): a table of its mounts (where,
// when, diameter, coils, km, predicted and measured wear) and a bar chart of
// predicted against measured wear per mount (core/report/svg_plot.h). Part
// of Router (api/router.h).
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "api/router.h"
#include "api/router_internal.h"
#include "core/dataset/dataset.h"
#include "core/dataset/timestamp.h"
#include "core/report/svg_plot.h"

namespace rollwear::api {
namespace {

std::string Num(const char* format, double v) {
  char buf[48];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

std::string Cell(const std::string& text, const char* cls = "") {
  return std::string("<td") +
         (*cls != 0 ? std::string(" class=\"") + cls + "\"" : "") + ">" +
         XmlEscape(text) + "</td>";
}

std::string MountRow(const storage::RollMountLife& m) {
  std::string s = "<tr class=\"mount\" data-campaign-id=\"" +
                  XmlEscape(m.campaign_id) + "\">";
  s += Cell(m.campaign_id);
  s += Cell(StandName(m.stand) + "/" + PositionName(m.position));
  s += Cell(FormatTimestamp(m.started_at));
  s += Cell(m.ended_at ? FormatTimestamp(*m.ended_at) : "running");
  s += Cell(Num("%.1f", m.diameter_mm));
  s += Cell(Num("%.0f", m.hardness_hb));
  s += Cell(std::to_string(m.coils), "coils");
  s += Cell(Num("%.1f", m.rolled_length_m / 1000), "km");
  s += Cell(Num("%.1f", m.predicted_wear_um), "predicted");
  if (m.measured_um) {
    s += Cell(Num("%.1f", *m.measured_um) +
                  (m.measured_suspect.empty() ? "" : " (suspect)"),
              m.measured_suspect.empty() ? "measured" : "measured suspect");
  } else {
    s += Cell("–", "measured");
  }
  return s + "</tr>\n";
}

// Predicted and measured wear per mount, side by side.
std::string WearChart(const storage::RollLife& life) {
  PlotSpec spec;
  spec.title = "predicted and measured centre wear per mount";
  spec.x_label = "campaign";
  spec.y_label = "wear (µm)";
  spec.fluid = true;
  spec.legend = PlotSpec::Legend::kTopLeft;
  PlotSeries predicted =
      PlotSeries::Make("predicted", "#1f77b4", PlotSeries::Style::kBars);
  PlotSeries measured =
      PlotSeries::Make("measured", "#d62728", PlotSeries::Style::kPoints);
  measured.radius = 4;
  measured.opacity = 1;
  for (size_t i = 0; i < life.mounts.size(); ++i) {
    const storage::RollMountLife& m = life.mounts[i];
    spec.categories.push_back(m.campaign_id);
    predicted.x.push_back(static_cast<double>(i));
    predicted.y.push_back(m.predicted_wear_um);
    if (m.measured_um) {
      measured.x.push_back(static_cast<double>(i));
      measured.y.push_back(*m.measured_um);
    }
  }
  spec.series.push_back(std::move(predicted));
  if (!measured.x.empty()) spec.series.push_back(std::move(measured));
  return RenderSvg(spec);
}

// The roll's own wear factor under the active model's per-roll family.
std::string WearFactorHtml(const std::optional<RollWearFactor>& f) {
  if (!f.has_value()) return "";
  char text[320];
  if (!f->known) {
    std::snprintf(text, sizeof text,
                  "<p id=\"wear-factor\">Own wear factor: no readings yet, "
                  "at its type's value × 1 (rolls scatter × %.2f to × %.2f, "
                  "95 %%).</p>\n",
                  f->lo, f->hi);
  } else {
    std::snprintf(text, sizeof text,
                  "<p id=\"wear-factor\">Own wear factor × %.2f (95 %% "
                  "× %.2f to × %.2f, from %d readings): it wears %.0f %% %s "
                  "than its roll type under the same strips.</p>\n",
                  f->value, f->lo, f->hi, f->readings,
                  std::abs(f->value - 1) * 100, f->value >= 1 ? "more" : "less");
  }
  return text;
}

std::string RollHtml(const storage::RollLife& life,
                     const std::optional<RollWearFactor>& factor) {
  std::string h =
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
      "<title>roll " +
      XmlEscape(life.roll_id) +
      " · rollwear</title>"
      "<style>body{font-family:sans-serif;margin:1.5em}"
      "table{border-collapse:collapse}td,th{padding:.2em .6em;"
      "border-bottom:1px solid #ddd;text-align:right}"
      ".suspect{color:#b36b00}svg{max-width:760px}</style></head><body>\n";
  h += "<p><a href=\"/\">← dashboard</a></p>\n<h1>Roll " +
       XmlEscape(life.roll_id) + " <small>" + XmlEscape(life.roll_type) +
       "</small></h1>\n";
  h += "<p>" + std::to_string(life.mounts.size()) +
       " mounts; predicted wear under model version " +
       std::to_string(life.model_version) +
       " (at the end of each mount, now "
       "for a running one).</p>\n";
  h += WearFactorHtml(factor);
  h += "<table id=\"mounts\"><tr><th>campaign</th><th>position</th>"
       "<th>mounted</th><th>ended</th><th>diameter mm</th><th>hardness HB</th>"
       "<th>coils</th><th>km</th><th>predicted µm</th><th>measured µm</th>"
       "</tr>\n";
  for (const storage::RollMountLife& m : life.mounts) h += MountRow(m);
  h += "</table>\n<figure>" + WearChart(life) + "</figure>\n</body></html>\n";
  return h;
}

}  // namespace

HttpResponse Router::GetRollPage(const std::string& roll_id) {
  StatusOr<storage::RollLife> life = store_->GetRollLife(roll_id);
  if (!life.ok()) return router_internal::FromStatus(life.status());
  HttpResponse r;
  r.status = 200;
  r.content_type = "text/html; charset=utf-8";
  r.body = RollHtml(*life, life->wear_factor);
  r.headers.emplace_back("Cache-Control", "no-store");
  return r;
}

}  // namespace rollwear::api
