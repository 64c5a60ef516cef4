#include "core/report/diagnosis_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "core/report/svg_plot.h"

namespace rollwear {
namespace {

constexpr const char* kBefore = "#d62728";
constexpr const char* kAfter = "#1f77b4";

std::string F(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), fmt, v);
  return buf;
}

std::string Sci(double p) {
  char buf[32];
  if (p < 1e-4) std::snprintf(buf, sizeof(buf), "%.1e", p);
  else std::snprintf(buf, sizeof(buf), "%.4f", p);
  return buf;
}

// Mean residual (measured - predicted) in quantile bins of x, before and after.
PlotSpec ResidualVsCovariate(const DiagnosisReport& r, const std::string& cov) {
  std::vector<std::tuple<double, double, double>> pts;  // x, before, after
  for (const DiagnosisPoint& p : r.points) {
    auto it = p.covariates.find(cov);
    if (it == p.covariates.end() || !std::isfinite(it->second)) continue;
    pts.emplace_back(it->second, p.measured_um - p.before_um, p.measured_um - p.after_um);
  }
  std::sort(pts.begin(), pts.end());
  PlotSpec s;
  s.title = "Residual against " + cov;
  s.x_label = cov + " (campaign aggregate)";
  s.y_label = "measured - predicted wear (µm)";
  s.zero_line = true;
  PlotSeries sb = PlotSeries::Make("", "#f3b3b3", PlotSeries::Style::kPoints);
  PlotSeries sa = PlotSeries::Make("", "#b3cde3", PlotSeries::Style::kPoints);
  sb.radius = sa.radius = 1.8;
  sb.opacity = sa.opacity = 0.5;
  for (const auto& [x, b, a] : pts) {
    sb.x.push_back(x);
    sb.y.push_back(b);
    sa.x.push_back(x);
    sa.y.push_back(a);
  }
  PlotSeries mb = PlotSeries::Make("before (bin means)", kBefore, PlotSeries::Style::kLine);
  PlotSeries ma = PlotSeries::Make("after (bin means)", kAfter, PlotSeries::Style::kLine);
  const size_t bins = 10;
  for (size_t b = 0; b < bins && !pts.empty(); ++b) {
    const size_t lo = b * pts.size() / bins, hi = (b + 1) * pts.size() / bins;
    if (hi <= lo) continue;
    double x = 0, yb = 0, ya = 0;
    for (size_t i = lo; i < hi; ++i) {
      x += std::get<0>(pts[i]);
      yb += std::get<1>(pts[i]);
      ya += std::get<2>(pts[i]);
    }
    const double n = static_cast<double>(hi - lo);
    mb.x.push_back(x / n);
    mb.y.push_back(yb / n);
    ma.x.push_back(x / n);
    ma.y.push_back(ya / n);
  }
  s.series = {sb, sa, mb, ma};
  return s;
}

std::string ParityPlots(const DiagnosisReport& r) {
  std::set<int> stands;
  for (const DiagnosisPoint& p : r.points) stands.insert(p.stand);
  std::string out;
  for (int stand : stands) {
    PlotSpec s;
    s.title = "F" + std::to_string(stand) + ": measured vs predicted (validation campaigns)";
    s.x_label = "measured centre wear (µm)";
    s.y_label = "predicted centre wear (µm)";
    s.identity_line = true;
    PlotSeries b = PlotSeries::Make("baseline", kBefore, PlotSeries::Style::kPoints);
    PlotSeries a = PlotSeries::Make(r.findings.empty() ? "baseline (no term adopted)" : "with adopted terms", kAfter,
                 PlotSeries::Style::kPoints);
    for (const DiagnosisPoint& p : r.points) {
      if (p.stand != stand || !p.validation) continue;
      b.x.push_back(p.measured_um);
      b.y.push_back(p.before_um);
      a.x.push_back(p.measured_um);
      a.y.push_back(p.after_um);
    }
    s.series = r.findings.empty() ? std::vector<PlotSeries>{b} : std::vector<PlotSeries>{b, a};
    out += "<figure>" + RenderSvg(s) + "</figure>\n";
  }
  return out;
}

// Mean residual by wear amplitude (baseline prediction), before and after.
std::string AmplitudePlot(const DiagnosisReport& r) {
  const std::vector<std::string> cats = {"< 150 µm", "150 - 300 µm", ">= 300 µm"};
  std::vector<double> sb(3, 0), sa(3, 0), n(3, 0);
  for (const DiagnosisPoint& p : r.points) {
    const int g = p.before_um < 150 ? 0 : (p.before_um < 300 ? 1 : 2);
    sb[g] += p.measured_um - p.before_um;
    sa[g] += p.measured_um - p.after_um;
    n[g] += 1;
  }
  PlotSpec s;
  s.title = "Mean residual by predicted wear (all measured campaigns)";
  s.x_label = "baseline predicted wear";
  s.y_label = "mean measured - predicted (µm)";
  s.categories = cats;
  s.zero_line = true;
  PlotSeries b = PlotSeries::Make("baseline", kBefore, PlotSeries::Style::kBars);
  PlotSeries a = PlotSeries::Make("with adopted terms", kAfter, PlotSeries::Style::kBars);
  for (int g = 0; g < 3; ++g) {
    if (n[g] == 0) continue;
    b.x.push_back(g);
    b.y.push_back(sb[g] / n[g]);
    a.x.push_back(g);
    a.y.push_back(sa[g] / n[g]);
  }
  s.series = {b, a};
  std::string caption = "<p>Positive bars: the model predicts less wear than the grinder "
                        "measures. Counts per group:";
  for (int g = 0; g < 3; ++g) caption += " " + XmlEscape(cats[g]) + ": " + F("%.0f", n[g]) + ";";
  return "<figure>" + RenderSvg(s) + "</figure>" + caption + "</p>\n";
}

// The page head and style sheet.
std::string HtmlHead() {
  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
       "<title>rollwear diagnosis</title><style>"
       "body{font-family:sans-serif;max-width:1100px;margin:1em auto;padding:0 1em;color:#222}"
       "table{border-collapse:collapse;margin:0.5em 0}td,th{border:1px solid #ccc;"
       "padding:3px 8px;text-align:left}th{background:#f4f4f4}figure{display:inline-block;"
       "margin:0.5em}.verdict{font-size:1.2em;padding:0.6em;border-radius:4px}"
       ".found{background:#fff3cd}.quiet{background:#d4edda}</style></head><body>\n";
  return h;
}

// The structure the final model leaves unexplained and the candidates the
// proxy guard did not adopt.
std::string UnexplainedHtml(const DiagnosisReport& r) {
  std::string h;
  if (!r.unexplained.empty()) {
    h += "<table><tr><th>unexplained mismatch at</th><th>mean residual (µm)</th>"
         "<th>p-value (Bonferroni)</th><th>check</th></tr>";
    for (const Unexplained& u : r.unexplained) {
      h += "<tr><td>" + XmlEscape(u.where) + "</td><td>" + F("%+.1f", u.mean_residual_um) +
           "</td><td>" + Sci(u.p_adjusted) + "</td><td>" + XmlEscape(u.dimension) +
           "</td></tr>";
    }
    h += "</table>\n";
  }
  if (!r.runners_up.empty()) {
    h += "<table><tr><th>not adopted</th><th>form</th><th>p-value</th><th>why</th></tr>";
    for (const RunnerUp& u : r.runners_up) {
      h += "<tr><td>" + XmlEscape(u.covariate) + "</td><td>" + XmlEscape(u.form) +
           "</td><td>" + Sci(u.p_adjusted) + "</td><td>" + XmlEscape(u.reason) + "</td></tr>";
    }
    h += "</table>\n";
  }
  return h;
}

// The verdict, the gap table and the observation counts.
std::string VerdictHtml(const DiagnosisReport& r) {
  std::string h;
  h += "<h1>Wear model diagnosis</h1>\n";
  const bool found = r.verdict == "missing_physics_found";
  h += std::string("<p class=\"verdict ") + (r.verdict == "no_significant_mismatch" ? "quiet" : "found") + "\">";
  if (found) {
    h += "The " + XmlEscape(r.law) + " wear model leaves out " +
         std::to_string(r.findings.size()) +
         (r.findings.size() == 1 ? " effect" : " effects") +
         " that the grinder measurements show. Adding " +
         (r.findings.size() == 1 ? "it" : "them") + " lowers the average wear gap on held-out "
         "campaigns from " + F("%.1f", r.baseline_gap_val_um) + " µm to " +
         F("%.1f", r.final_gap_val_um) + " µm.";
  } else if (r.verdict == "mismatch_located_unexplained") {
    h += "Mismatch located, not explained: the residuals of the " + XmlEscape(r.law) +
         " wear model show significant structure (below) that no recorded quantity "
         "explains. No physics is named.";
  } else {
    h += "No significant mismatch: the " + XmlEscape(r.law) +
         " wear model explains the grinder measurements as well as any candidate term "
         "(average wear gap on held-out campaigns " + F("%.1f", r.baseline_gap_val_um) + " µm).";
  }
  h += "</p>\n";
  h += UnexplainedHtml(r);
  h += "<table><tr><th></th><th>training gap (µm)</th><th>validation gap (µm)</th></tr>"
       "<tr><td>baseline (" + XmlEscape(r.law) + ", option 1)</td><td>" +
       F("%.1f", r.baseline_gap_train_um) + "</td><td>" + F("%.1f", r.baseline_gap_val_um) +
       "</td></tr><tr><td>with adopted terms</td><td>" + F("%.1f", r.final_gap_train_um) +
       "</td><td>" + F("%.1f", r.final_gap_val_um) + "</td></tr></table>\n";
  h += "<p>" + std::to_string(r.n_train) + " training and " + std::to_string(r.n_val) +
       " validation measurements (2/3-1/3 split by campaign); the validation campaigns "
       "played no part in choosing or fitting any term.</p>\n";
  return h;
}

// Finding number `idx`: mechanism, evidence, parameters, alternatives and
// its residual plot.
std::string FindingHtml(const DiagnosisReport& r, const Finding& f, int idx) {
  std::string h;
  h += "<h2>Finding " + std::to_string(idx) + ": " + XmlEscape(f.mechanism) +
       "</h2>\n";
  h += "<p><b>Covariate:</b> " + XmlEscape(f.covariate) + " (" +
       XmlEscape(f.level) + " level); <b>shape:</b> " + XmlEscape(f.shape) +
       "; <b>term:</b> " + XmlEscape(f.form) + ".</p>\n<p>" +
       XmlEscape(f.explanation) + "</p>\n";
  h += "<table><tr><th>evidence</th><th>value</th></tr>"
       "<tr><td>likelihood ratio (df " +
       std::to_string(f.df) + ")</td><td>" + F("%.1f", f.lr) +
       "</td></tr><tr><td>p-value, Bonferroni-adjusted over all "
       "candidates</td><td>" +
       Sci(f.p_adjusted) +
       "</td></tr>"
       "<tr><td>cross-validated gap on training campaigns</td><td>" +
       F("%.1f", f.cv_gap_before_um) + " → " + F("%.1f", f.cv_gap_after_um) +
       " µm</td></tr><tr><td>validation gap</td><td>" +
       F("%.1f", f.gap_val_before_um) + " → " + F("%.1f", f.gap_val_after_um) +
       " µm</td></tr></table>\n";
  h += "<table><tr><th>parameter</th><th>value</th></tr>";
  for (const auto& [k, v] : f.parameters) {
    h += "<tr><td>" + XmlEscape(k) + "</td><td>" + F("%.5g", v) + "</td></tr>";
  }
  h += "</table>\n";
  if (!f.carriers.empty()) {
    h += "<p>Carried by: ";
    for (const std::string& c : f.carriers) h += XmlEscape(c) + " ";
    h += "(one mechanism; the data do not say which of them drives the "
         "wear).</p>\n";
  }
  if (!f.alternatives.empty()) {
    h += "<p>Nearly as good a fit with: ";
    for (const std::string& a : f.alternatives) h += XmlEscape(a) + " ";
    h += "(correlated quantities; the named covariate fits best).</p>\n";
  }
  // A roll id's level index is no scale to bin residuals along.
  if (f.form != "roll_effect") {
    h += "<figure>" + RenderSvg(ResidualVsCovariate(r, f.covariate)) +
         "</figure>\n";
  }
  return h;
}

// The residual breakdowns (at most 12), as a table.
std::string LocateHtml(const DiagnosisReport& r) {
  std::string h;
  h += "<p>Baseline residuals broken down by dimension (strongest evidence first; "
       "ANOVA F test for groups, Pearson t test of the relative residual for numeric "
       "covariates). Effect: the largest mean relative residual of a group, or |r|.</p>"
       "<table><tr><th>dimension</th><th>test</th><th>p-value</th><th>effect</th>"
       "<th>groups: mean residual µm (n)</th></tr>";
  for (size_t i = 0; i < r.locate.size() && i < 12; ++i) {
    const Breakdown& b = r.locate[i];
    std::string groups;
    for (const Breakdown::Group& g : b.groups) {
      groups += XmlEscape(g.label) + ": " + F("%+.1f", g.mean_residual_um) + " (" +
                std::to_string(g.n) + "); ";
    }
    h += "<tr><td>" + XmlEscape(b.dimension) + "</td><td>" + b.test + "</td><td>" +
         Sci(b.p_value) + "</td><td>" + F("%.3f", b.effect_size) + "</td><td>" + groups +
         "</td></tr>";
  }
  return h;
}

// The first round's candidates, and the closing line.
std::string FirstRoundHtml(const DiagnosisReport& r) {
  std::string h;
  h += "</table>\n<h2>Candidate terms tried first</h2>\n<table><tr><th>covariate</th>"
       "<th>form</th><th>df</th><th>LR</th><th>p adjusted</th><th>CV error ratio</th></tr>";
  for (const CandidateResult& c : r.first_round) {
    h += "<tr><td>" + XmlEscape(c.covariate) + "</td><td>" + XmlEscape(c.form) + "</td><td>" +
         std::to_string(c.df) + "</td><td>" + (c.lr > 0 ? F("%.1f", c.lr) : "screened") +
         "</td><td>" + Sci(c.p_adjusted) + "</td><td>" +
         (std::isfinite(c.cv_mse_ratio) ? F("%.3f", c.cv_mse_ratio) : "–") + "</td></tr>";
  }
  h += "</table>\n<p>Generated by rollwear diagnose in " + F("%.1f", r.seconds) +
       " s.</p></body></html>\n";
  return h;
}

}  // namespace

std::string DiagnosisHtml(const DiagnosisReport& r) {
  std::string h = HtmlHead();
  h += VerdictHtml(r);
  int idx = 1;
  for (const Finding& f : r.findings) h += FindingHtml(r, f, idx++);
  h += "<h2>Measured against predicted, per stand</h2>\n" + ParityPlots(r);
  h += "<h2>Where the mismatch lives</h2>\n" + AmplitudePlot(r);
  h += LocateHtml(r);
  h += FirstRoundHtml(r);
  return h;
}

}  // namespace rollwear
