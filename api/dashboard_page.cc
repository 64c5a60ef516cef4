#include "api/dashboard_page.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <utility>

#include "core/dataset/dataset.h"
#include "core/report/svg_plot.h"

namespace rollwear {
namespace {

// Most points drawn per growth curve; longer tracks are thinned evenly
// (the last point, the current wear, is always kept).
constexpr size_t kMaxTrackPoints = 400;

std::string Fmt(const char* format, double v) {
  if (!std::isfinite(v)) return "–";
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

std::string Attr(const char* name, const std::string& value) {
  return std::string(" ") + name + "=\"" + XmlEscape(value) + "\"";
}

// `text` as one URL path segment (RFC 3986 unreserved bytes kept, every
// other byte %XX): the roll page's link.
std::string PathSegment(const std::string& text) {
  std::string out;
  for (const unsigned char c : text) {
    if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~') {
      out += static_cast<char>(c);
    } else {
      char buf[4];
      std::snprintf(buf, sizeof(buf), "%%%02X", c);
      out += buf;
    }
  }
  return out;
}

std::string Label(int stand, const std::string& position) {
  return StandName(stand) + " " + position;
}

int Slot(int stand, const std::string& position) {
  return (stand - 1) * 2 + (position == "bottom" ? 1 : 0);
}

// Colour of each roll position: the order of the mounted rolls, so the
// table's swatches, the growth curves and the parity points agree.
std::string ColorFor(const DashboardData& d, int stand,
                     const std::string& position) {
  for (size_t i = 0; i < d.rolls.size(); ++i) {
    if (d.rolls[i].stand == stand && d.rolls[i].position == position) {
      return PaletteColor(static_cast<int>(i));
    }
  }
  return PaletteColor(Slot(stand, position));
}

// Suspect measurements' points: drawn apart from the roll positions'.
constexpr const char* kSuspectColor = "#7f7f7f";

constexpr const char* kStyle = R"css(
*{box-sizing:border-box}
html,body{margin:0;background:#e9edf1;color:#1b1f24;
 font:14px/1.35 "DejaVu Sans",Verdana,Arial,sans-serif}
header{display:flex;align-items:baseline;gap:22px;padding:7px 14px;
 background:#1f2d3d;color:#fff;white-space:nowrap;overflow:hidden}
header h1{font-size:18px;margin:0;font-weight:bold}
header .meta{font-size:14px;color:#d6dee8}
header .meta b{color:#fff}
#stale{background:#b00020;color:#fff;padding:2px 8px;border-radius:3px}
main{display:grid;grid-template-columns:560px minmax(0,1fr);gap:8px;padding:8px}
.col{display:flex;flex-direction:column;gap:8px;min-width:0}
section{background:#fff;border:1px solid #cfd6dd;border-radius:4px;
 padding:6px 10px 8px}
h2{font-size:14px;margin:0 0 4px;color:#2b3a4a}
h2 small{font-weight:normal;color:#5a6672}
h3{font-size:13px;margin:6px 0 3px;color:#2b3a4a}
h3 small{font-weight:normal;color:#5a6672}
table{border-collapse:collapse;width:100%}
th{font-size:12px;font-weight:bold;color:#4a5561;text-align:right;
 border-bottom:1px solid #bfc7cf;padding:2px 5px}
td{text-align:right;padding:3px 5px;border-bottom:1px solid #edf0f2;
 font-variant-numeric:tabular-nums}
th:first-child,td:first-child{text-align:left}
td.pos{font-weight:bold;white-space:nowrap}
td.wear{font-size:21px;font-weight:bold;color:#0b2540}
td.iv{color:#4a5561;white-space:nowrap}
td.remaining{white-space:nowrap;line-height:1.2}
.sw{display:inline-block;width:11px;height:11px;border-radius:50%;
 margin-right:6px;vertical-align:-1px}
.muted{color:#5a6672}
.empty{color:#5a6672;padding:12px 0}
.ok{color:#16703a;font-weight:bold}
.bad{color:#b00020;font-weight:bold}
.grid{display:grid;gap:6px}
.finding p{margin:3px 0}
.finding .cov{font-size:16px;font-weight:bold}
.clamp{display:-webkit-box;-webkit-line-clamp:3;-webkit-box-orient:vertical;
 overflow:hidden}
svg{display:block}
)css";

std::string RefreshScript(int seconds) {
  return "<script>(function(){var s=" + std::to_string(seconds) +
         ";function tick(){fetch(location.pathname,{cache:'no-store'})"
         ".then(function(r){if(!r.ok)throw new Error(r.status);return "
         "r.text()})"
         ".then(function(t){var d=new "
         "DOMParser().parseFromString(t,'text/html');"
         "var n=d.getElementById('dash');if(!n)throw new Error('page');"
         "document.getElementById('dash').replaceWith(n);"
         "document.getElementById('stale').hidden=true})"
         ".catch(function(){document.getElementById('stale').hidden=false})"
         ".finally(function(){setTimeout(tick,s*1000)})}"
         "setTimeout(tick,s*1000)})();</script>\n";
}

std::string Header(const DashboardData& d) {
  std::string h =
      "<header><h1>" + XmlEscape(d.title) + " · work-roll wear</h1>";
  h += "<span class=\"meta\">campaign <b>" +
       XmlEscape(d.campaign_id.empty() ? std::string("none open")
                                       : d.campaign_id) +
       "</b></span>";
  h += "<span class=\"meta\">model <b>v" + std::to_string(d.model_version) +
       "</b> " + XmlEscape(d.model_label);
  if (d.model_gap_val_um > 0 && std::isfinite(d.model_gap_val_um)) {
    h += ", validation gap " + Fmt("%.1f", d.model_gap_val_um) + " µm";
  }
  h += "</span><span class=\"meta\">updated <b>" + XmlEscape(d.generated_at) +
       "</b></span></header>\n";
  return h;
}

// "%.3f" of a value, "" when there is none.
std::string OptFmt(const std::optional<double>& v) {
  return v ? Fmt("%.3f", *v) : std::string();
}

// The limit and remaining-life markers and cells of a roll's row.
std::string RemainingAttrs(const DashboardRoll& r) {
  return Attr("data-limit-um", OptFmt(r.wear_limit_um)) +
         Attr("data-remaining-m", OptFmt(r.remaining_length_m)) +
         Attr("data-remaining-lo-m", OptFmt(r.remaining_lo_m)) +
         Attr("data-remaining-hi-m", r.remaining_length_m && !r.remaining_hi_m
                                         ? std::string("inf")
                                         : OptFmt(r.remaining_hi_m)) +
         Attr("data-remaining-coils", OptFmt(r.remaining_coils));
}
std::string RemainingCells(const DashboardRoll& r) {
  std::string s = "<td class=\"limit\">" +
                  (r.wear_limit_um ? Fmt("%.0f", *r.wear_limit_um) : "–") +
                  "</td><td class=\"remaining\">";
  if (r.remaining_length_m) {
    s += Fmt("%.1f", *r.remaining_length_m / 1000) + " km<br><small>" +
         Fmt("%.1f", *r.remaining_lo_m / 1000) + " – " +
         (r.remaining_hi_m ? Fmt("%.1f", *r.remaining_hi_m / 1000) : "∞") +
         " km<br>" + Fmt("%.0f", *r.remaining_coils) + " coils</small>";
  } else {
    s += "–";
  }
  return s + "</td>";
}

std::string RollsSection(const DashboardData& d) {
  std::string s =
      "<section id=\"rolls\"><h2>Mounted work rolls <small>predicted "
      "centre wear, 95 % interval</small></h2>\n";
  if (d.rolls.empty()) {
    return s +
           "<p class=\"empty\">No campaign is open: no rolls are mounted.</p>"
           "</section>\n";
  }
  // Eight columns in the 560-px panel at 1366x768 (the Chromium test
  // measures it): the interval and the remaining life's bounds sit under
  // their figures.
  s += "<table><tr><th>position</th><th>roll</th><th>coils</th>"
       "<th>rolled km</th><th>wear µm</th><th>interval µm</th>"
       "<th>limit µm</th><th>to limit<br>(95 %)</th></tr>\n";
  for (size_t i = 0; i < d.rolls.size(); ++i) {
    const DashboardRoll& r = d.rolls[i];
    s += "<tr class=\"roll\"" + Attr("data-stand", std::to_string(r.stand)) +
         Attr("data-position", r.position) + Attr("data-roll-id", r.roll_id) +
         Attr("data-coils", std::to_string(r.coils)) +
         Attr("data-length-m", Fmt("%.3f", r.rolled_length_m)) +
         Attr("data-wear-um", Fmt("%.3f", r.predicted_wear_um)) +
         Attr("data-lo-um", Fmt("%.3f", r.interval_lo_um)) +
         Attr("data-hi-um", Fmt("%.3f", r.interval_hi_um)) + RemainingAttrs(r) +
         ">";
    s += "<td class=\"pos\"><span class=\"sw\" style=\"background:" +
         std::string(PaletteColor(static_cast<int>(i))) + "\"></span>" +
         XmlEscape(Label(r.stand, r.position)) + "</td>";
    s += "<td title=\"" + XmlEscape(r.roll_type) + "\"><a href=\"/rolls/" +
         XmlEscape(PathSegment(r.roll_id)) + "\">" + XmlEscape(r.roll_id) +
         "</a></td>";
    s += "<td class=\"coils\">" + std::to_string(r.coils) + "</td>";
    s += "<td class=\"length\">" + Fmt("%.1f", r.rolled_length_m / 1000) +
         "</td>";
    s += "<td class=\"wear\">" + Fmt("%.1f", r.predicted_wear_um) + "</td>";
    s += "<td class=\"iv\">" + Fmt("%.1f", r.interval_lo_um) + " –<br>" +
         Fmt("%.1f", r.interval_hi_um) + "</td>" + RemainingCells(r) +
         "</tr>\n";
  }
  return s + "</table></section>\n";
}

std::string CalibrationsSection(const DashboardData& d) {
  std::string s =
      "<section id=\"calibrations\"><h2>Last calibrations <small>mean "
      "|measured − predicted|, µm</small></h2>\n";
  if (d.calibrations.empty()) {
    return s +
           "<p class=\"empty\">No calibration yet: predictions use the prior "
           "model.</p></section>\n";
  }
  s += "<table><tr><th>#</th><th>finished</th><th>model</th><th>train</th>"
       "<th>validation</th><th title=\"the model active then, on the same "
       "validation campaigns\">before</th><th>result</th></tr>\n";
  for (const DashboardCalibration& c : d.calibrations) {
    const bool done = c.status == "done";
    s += "<tr class=\"calibration\"" + Attr("data-id", std::to_string(c.id)) +
         Attr("data-gap-train-um", Fmt("%.3f", c.gap_train_um)) +
         Attr("data-gap-val-um", Fmt("%.3f", c.gap_val_um)) + ">";
    s += "<td>" + std::to_string(c.id) + "</td>";
    s += "<td class=\"muted\">" +
         XmlEscape(c.finished.empty() ? c.status : c.finished) + "</td>";
    s += "<td>" + XmlEscape(c.model) + " " + std::to_string(c.option) + "</td>";
    s += "<td>" + (done ? Fmt("%.1f", c.gap_train_um) : "–") + "</td>";
    s += "<td><b>" + (done ? Fmt("%.1f", c.gap_val_um) : "–") + "</b></td>";
    s += "<td>" +
         (done && c.active_gap_val_um > 0 ? Fmt("%.1f", c.active_gap_val_um)
                                          : "–") +
         "</td>";
    if (c.status == "failed") {
      s += "<td class=\"bad\" title=\"" + XmlEscape(c.message) +
           "\">failed</td>";
    } else if (!done) {
      s += "<td class=\"muted\">" + XmlEscape(c.status) + "</td>";
    } else if (c.promoted) {
      s += "<td class=\"ok\">→ v" + std::to_string(c.model_version) + "</td>";
    } else {
      s += "<td class=\"muted\" title=\"" + XmlEscape(c.message) +
           "\">kept</td>";
    }
    s += "</tr>\n";
  }
  return s + "</table></section>\n";
}

std::string DiagnosisSection(const DashboardData& d) {
  std::string s =
      "<section id=\"diagnosis\" class=\"finding\"><h2>Latest "
      "diagnosis</h2>\n";
  if (!d.diagnosis) {
    return s +
           "<p class=\"empty\">No diagnosis has run since the daemon started "
           "(POST /v1/diagnoses).</p></section>\n";
  }
  const DashboardFinding& f = *d.diagnosis;
  s += "<p class=\"muted\">diagnosis #" + std::to_string(f.diagnosis_id) +
       ", baseline validation gap " + Fmt("%.1f", f.baseline_gap_val_um) +
       " µm</p>\n";
  if (f.covariate.empty()) {
    return s +
           "<p class=\"cov\">No significant mismatch found.</p></section>\n";
  }
  s += "<p class=\"cov\"" + Attr("data-covariate", f.covariate) + ">" +
       XmlEscape(f.covariate) + " <span class=\"muted\">(" +
       XmlEscape(f.mechanism) + ")</span></p>\n";
  s += "<p>validation gap <b>" + Fmt("%.1f", f.gap_val_before_um) + " → " +
       Fmt("%.1f", f.gap_val_after_um) +
       " µm</b>, p = " + Fmt("%.2g", f.p_value) + "</p>\n";
  s += "<p class=\"clamp muted\">" + XmlEscape(f.explanation) + "</p>\n";
  return s + "</section>\n";
}

std::string GrowthSection(const DashboardData& d) {
  std::string s =
      "<section id=\"growth\"><h2>Wear growth along campaign " +
      XmlEscape(d.campaign_id.empty() ? std::string("–") : d.campaign_id) +
      " <small>predicted, active model; straight lines: forecast to each "
      "roll's wear limit at the campaign's mix so far</small></h2>\n";
  PlotSpec spec;
  spec.x_label = "rolled length in this campaign (km)";
  spec.y_label = "predicted centre wear (µm)";
  spec.width = 830;
  spec.height = 305;
  spec.font_size = 13;
  spec.fluid = true;
  bool any = false;
  for (size_t i = 0; i < d.rolls.size(); ++i) {
    const DashboardRoll& r = d.rolls[i];
    PlotSeries line = PlotSeries::Make(Label(r.stand, r.position),
                                       PaletteColor(static_cast<int>(i)),
                                       PlotSeries::Style::kLine);
    const size_t n = std::min(r.track_length_m.size(), r.track_wear_um.size());
    const size_t step =
        n > kMaxTrackPoints ? (n + kMaxTrackPoints - 1) / kMaxTrackPoints : 1;
    line.x.push_back(0);
    line.y.push_back(0);
    for (size_t k = 0; k < n; k += step) {
      line.x.push_back(r.track_length_m[k] / 1000);
      line.y.push_back(r.track_wear_um[k]);
    }
    if (n > 0 && (n - 1) % step != 0) {
      line.x.push_back(r.track_length_m[n - 1] / 1000);
      line.y.push_back(r.track_wear_um[n - 1]);
    }
    any = any || n > 0;
    spec.series.push_back(std::move(line));
    if (r.wear_limit_um && r.remaining_length_m) {
      // The forecast at the campaign's mix so far: a straight line from
      // the current wear to the limit.
      PlotSeries forecast = PlotSeries::Make(
          Label(r.stand, r.position) + " to limit",
          PaletteColor(static_cast<int>(i)), PlotSeries::Style::kLine);
      forecast.x = {r.rolled_length_m / 1000,
                    (r.rolled_length_m + *r.remaining_length_m) / 1000};
      forecast.y = {r.predicted_wear_um,
                    std::max(r.predicted_wear_um, *r.wear_limit_um)};
      spec.series.push_back(std::move(forecast));
    }
  }
  if (!any) {
    return s +
           "<p class=\"empty\">No coil rolled in an open campaign yet.</p>"
           "</section>\n";
  }
  return s + RenderSvg(spec) + "</section>\n";
}

// The suspect measurements among the parity points, with their reasons
// ("" when there is none).
std::string SuspectList(const DashboardData& d) {
  std::string items;
  for (const DashboardParityPoint& p : d.parity) {
    if (p.suspect.empty()) continue;
    items += "<li>" +
             XmlEscape(StandName(p.stand) + "/" + p.position + " of campaign " +
                       p.campaign_id + ": " + Fmt("%.1f", p.measured_um) +
                       " µm — " + p.suspect) +
             "</li>\n";
  }
  if (items.empty()) return "";
  return "<div id=\"suspect\"><h3>Suspect measurements <small>stored "
         "flagged, not fitted</small></h3>\n<ul>\n" +
         items + "</ul></div>";
}

std::string ParitySection(const DashboardData& d) {
  std::string s =
      "<section id=\"parity\"><h2>Measured against predicted, last " +
      std::to_string(d.parity_campaigns) +
      " measured campaigns <small>per stand, active model" +
      std::string(d.parity_reading_terms
                      ? "; predicted wear plus the model's measurement terms"
                      : "") +
      "</small></h2>\n";
  std::map<int, std::vector<const DashboardParityPoint*>> by_stand;
  for (const DashboardParityPoint& p : d.parity)
    by_stand[p.stand].push_back(&p);
  if (by_stand.empty()) {
    return s + "<p class=\"empty\">No measured campaign yet.</p></section>\n";
  }
  const int n = static_cast<int>(by_stand.size());
  const int columns = std::min(n, 4);
  s += "<div class=\"grid\" style=\"grid-template-columns:repeat(" +
       std::to_string(columns) + ",minmax(0,1fr))\">\n";
  for (const auto& [stand, points] : by_stand) {
    PlotSpec spec;
    spec.title = StandName(stand);
    spec.x_label = "measured wear (µm)";
    spec.y_label = d.parity_reading_terms ? "predicted reading (µm)"
                                          : "predicted wear (µm)";
    spec.identity_line = true;
    spec.width = 830 / columns;
    spec.height = n <= 2 ? 315 : 250;
    spec.font_size = columns <= 2 ? 13 : 12;
    spec.fluid = true;
    for (const char* position : {"top", "bottom"}) {
      PlotSeries pts = PlotSeries::Make(position, ColorFor(d, stand, position),
                                        PlotSeries::Style::kPoints);
      pts.radius = 4.5;
      pts.opacity = 0.8;
      for (const DashboardParityPoint* p : points) {
        if (p->position != position || !p->suspect.empty()) continue;
        pts.x.push_back(p->measured_um);
        pts.y.push_back(p->predicted_um);
      }
      if (!pts.x.empty()) spec.series.push_back(std::move(pts));
    }
    PlotSeries suspect =
        PlotSeries::Make("suspect", kSuspectColor, PlotSeries::Style::kPoints);
    suspect.radius = 5.5;
    for (const DashboardParityPoint* p : points) {
      if (p->suspect.empty()) continue;
      suspect.x.push_back(p->measured_um);
      suspect.y.push_back(p->predicted_um);
    }
    if (!suspect.x.empty()) spec.series.push_back(std::move(suspect));
    s += "<div class=\"stand\"" + Attr("data-stand", std::to_string(stand)) +
         ">" + RenderSvg(spec) + "</div>\n";
  }
  return s + "</div>" + SuspectList(d) + "</section>\n";
}

}  // namespace

std::string DashboardHtml(const DashboardData& d) {
  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n";
  h += "<meta name=\"viewport\" content=\"width=device-width, "
       "initial-scale=1\">\n";
  h +=
      "<title>" + XmlEscape(d.title) + " · wear of the mounted rolls</title>\n";
  h += "<noscript><meta http-equiv=\"refresh\" content=\"" +
       std::to_string(d.refresh_seconds) + "\"></noscript>\n";
  h += "<style>" + std::string(kStyle) + "</style></head>\n<body>\n";
  h += "<div id=\"dash\">\n" + Header(d);
  h += "<main><div class=\"col\">\n" + RollsSection(d) +
       CalibrationsSection(d) + DiagnosisSection(d) +
       "</div>\n<div class=\"col\">\n" + GrowthSection(d) + ParitySection(d) +
       DashboardProfileSection(d) + "</div></main>\n</div>\n";
  h += "<div style=\"position:fixed;right:12px;top:8px\"><span id=\"stale\" "
       "hidden>"
       "connection to the daemon lost – showing the last page</span></div>\n";
  h += RefreshScript(d.refresh_seconds);
  h += "</body></html>\n";
  return h;
}

}  // namespace rollwear
