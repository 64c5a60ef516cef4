// The per-roll family of the diagnosis (diagnosis_stages_internal.h,
// RunRollFamily): each physical roll's own wear resistance, a random
// effect over roll_id, tried after the rounds on what they leave.
//
// The heterogeneity test and the spread follow core/fit/roll_effects.h:
// per roll r, on the training readings i of the current model's prediction
// x_i with noise sd s_i (w_i = 1 / s_i^2),
//   mhat_r = sum w x y / sum w x^2,  v_r = 1 / sum w x^2,
//   Q = sum_r (mhat_r - mbar)^2 / v_r ~ chi2(R - 1) when the rolls do not
//   differ (Cochran 1954, Biometrics 10:101),
//   tau^2 = max(0, (Q - (R - 1)) / (S1 - S2 / S1)),  S1 = sum 1/v_r,
//   S2 = sum 1/v_r^2 (DerSimonian & Laird 1986, Controlled Clinical Trials
//   7:177).
// The term's prior on log m_r is N(0, ln(1 + tau^2)) (the log-normal with
// that relative spread): a roll with few readings stays near its type.
//
// Thread-safety: called from Diagnose() only (one thread; CrossValidate
// runs its fits on options.num_threads).
#include <cmath>
#include <cstdio>
#include <functional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/base/distributions.h"
#include "core/dataset/dataset.h"
#include "core/diagnosis/diagnosis_alternatives.h"
#include "core/diagnosis/diagnosis_stages_internal.h"
#include "core/fit/term_refit.h"

namespace rollwear::diag {
namespace {

struct Heterogeneity {
  int rolls = 0;
  double q = 0, p_value = 1, tau = 0;
  double tau2 = 0;  // DerSimonian & Laird's tau^2 (absolute)
  double c = 0;     // S1 - S2 / S1: E[Q] = (R - 1) + tau^2 c
};

// Over the training readings i of `train` for which keep(i) holds (every
// reading when keep is empty): pred[i] the current model's wear, y[i] the
// reading less the model's measurement offsets (so that x_i and y_i are
// both wear), sd the noise sd (indexed like td.obs).
Heterogeneity RollHeterogeneity(const TermData& td, int k,
                                const std::vector<int>& train,
                                const std::vector<double>& pred,
                                const std::vector<double>& y,
                                const std::vector<double>& sd,
                                const DiagnosisOptions& options,
                                const std::function<bool(size_t)>& keep = {}) {
  const int levels = static_cast<int>(td.catalog[k].levels.size());
  std::vector<double> sxy(levels, 0.0), sxx(levels, 0.0);
  std::vector<int> count(levels, 0);
  for (size_t i = 0; i < train.size(); ++i) {
    const TermObservation& ob = td.obs[train[i]];
    if (ob.pass_end <= ob.pass_begin || (keep && !keep(i))) continue;
    const int l = LevelIndex(td.z[k][ob.pass_begin]);
    if (l < 0 || l >= levels || !(pred[i] > 0)) continue;
    const double w = 1.0 / (sd[train[i]] * sd[train[i]]);
    sxy[l] += w * pred[i] * y[i];
    sxx[l] += w * pred[i] * pred[i];
    ++count[l];
  }
  std::vector<double> m, v;
  for (int l = 0; l < levels; ++l) {
    if (count[l] < options.thresholds.min_readings_per_roll || !(sxx[l] > 0))
      continue;
    m.push_back(sxy[l] / sxx[l]);
    v.push_back(1.0 / sxx[l]);
  }
  Heterogeneity h;
  h.rolls = static_cast<int>(m.size());
  if (h.rolls < 3) return h;
  double s1 = 0, s2 = 0, sm = 0;
  for (size_t r = 0; r < m.size(); ++r) {
    s1 += 1 / v[r];
    s2 += 1 / (v[r] * v[r]);
    sm += m[r] / v[r];
  }
  const double mbar = sm / s1;
  for (size_t r = 0; r < m.size(); ++r)
    h.q += (m[r] - mbar) * (m[r] - mbar) / v[r];
  const double df = static_cast<double>(h.rolls - 1);
  h.p_value = ChiSquareSurvival(h.q, df);
  h.c = s1 - s2 / s1;
  h.tau2 = std::max(0.0, (h.q - df) / h.c);
  h.tau = std::sqrt(h.tau2) / mbar;  // relative to the rolls' mean multiplier
  return h;
}

// A roll's own wear resistance goes with the roll wherever it runs: the
// rolls must scatter (Q at everywhere_alpha, diagnosis_thresholds.h) within
// every stand, position and roll type that has min_group_rolls rolls with
// readings and where the pooled spread would show plainly (its expected Q,
// (R_g - 1) + tau^2 c_g, beyond the chi-square's plain_alpha point: a group
// too small to see it is not evidence against it). A scatter at one place
// only is something of that place (a roll type's covariate at one stand,
// say), not of the rolls. Returns "" or why not.

// The groupings a roll's own resistance must hold across: per training
// reading (index into train), its stand, its position and its roll type.
struct Grouping {
  const char* name;
  std::vector<std::string> label;
};

std::vector<Grouping> Groupings(const TermData& td,
                                const std::vector<int>& train) {
  std::vector<Grouping> g = {
      {"stand", {}}, {"position", {}}, {"roll type", {}}};
  for (int o : train) {
    const std::string& p = td.positions[td.obs[o].position];
    const size_t slash = p.find('/');
    g[0].label.push_back(p.substr(0, slash));
    g[1].label.push_back(slash == std::string::npos ? "" : p.substr(slash + 1));
    const int t = td.obs[o].roll_type;
    g[2].label.push_back(t >= 0 && t < static_cast<int>(td.roll_types.size())
                             ? td.roll_types[t]
                             : "");
  }
  return g;
}

// Returns "" or why not.
std::string ScatterNotEverywhere(const TermData& td, int k,
                                 const std::vector<int>& train,
                                 const std::vector<double>& pred,
                                 const std::vector<double>& y,
                                 const std::vector<double>& sd,
                                 const Heterogeneity& pooled,
                                 const DiagnosisOptions& options) {
  for (const Grouping& grouping : Groupings(td, train)) {
    const std::set<std::string> labels(grouping.label.begin(),
                                       grouping.label.end());
    if (labels.size() < 2) continue;
    std::vector<std::pair<std::string, Heterogeneity>> each;
    for (const std::string& label : labels) {
      const Heterogeneity g = RollHeterogeneity(
          td, k, train, pred, y, sd, options,
          [&](size_t i) { return grouping.label[i] == label; });
      if (g.rolls >= options.thresholds.min_group_rolls)
        each.emplace_back(label, g);
    }
    for (const auto& [label, g] : each) {
      const double df = g.rolls - 1;
      const double expected_q = df + pooled.tau2 * g.c;
      if (g.p_value < options.thresholds.everywhere_alpha ||
          ChiSquareSurvival(expected_q, df) >= options.thresholds.plain_alpha)
        continue;
      char text[200];
      std::snprintf(
          text, sizeof text,
          "inconsistent across %s: the rolls do not scatter at %s %s "
          "(Q = %.1f on %d df, p = %.2g): not a property of the rolls",
          grouping.name, grouping.name, label.c_str(), g.q, g.rolls - 1,
          g.p_value);
      return text;
    }
  }
  return "";
}

TermSpec RollTerm(const TermData& td, int k, double tau) {
  TermSpec s;
  s.covariate = k;
  s.term.covariate = kRollIdName;
  s.term.form = TermForm::kRollEffect;
  s.term.levels = td.catalog[k].levels;
  s.term.num_levels = static_cast<int>(s.term.levels.size());
  s.term.params.assign(s.term.num_levels, 0.0);
  s.prior_sd = std::sqrt(std::log1p(tau * tau));
  s.term.scale = s.prior_sd;
  s.lower.assign(s.term.num_levels, -3.0);
  s.upper.assign(s.term.num_levels, 3.0);
  return s;
}

// A calendar rival: quantile bins (options.num_bins) of covariate `name`
// over the training readings; nullopt-like (covariate -1) when it is
// missing or constant.
TermSpec CalendarRival(const TermData& td, const std::vector<int>& train,
                       const char* name, int bins) {
  TermSpec s;
  const int k = td.CovariateIndex(name);
  if (k < 0) return s;
  std::vector<double> edges;
  for (int b = 1; b < bins; ++b) {
    const double e =
        CovariateQuantile(td, train, k, static_cast<double>(b) / bins);
    if (std::isfinite(e) && (edges.empty() || e > edges.back()))
      edges.push_back(e);
  }
  if (edges.empty()) return s;
  s.covariate = k;
  s.term.covariate = name;
  s.term.form = TermForm::kBinned;
  s.term.edges = edges;
  s.term.params.assign(edges.size(), 0.0);
  s.lower.assign(edges.size(), -3.0);
  s.upper.assign(edges.size(), 3.0);
  return s;
}

void Refuse(const Heterogeneity& h, const std::string& why,
            DiagnosisReport* report) {
  RunnerUp r;
  r.round = static_cast<int>(report->findings.size());
  r.covariate = kRollIdName;
  r.form = TermFormName(TermForm::kRollEffect);
  r.p_adjusted = h.p_value;
  r.reason = why;
  r.refusal = RefusalKind::kRollFamily;
  report->runners_up.push_back(std::move(r));
}

void FillFinding(const DiagnosisState& st, const Heterogeneity& h,
                 const Fitted& before, const Fitted& with,
                 const CvResult& cv_before, const CvResult& cv_with,
                 Finding* f) {
  const TermSpec& spec = with.terms.back();
  f->covariate = kRollIdName;
  f->level = "roll";
  f->mechanism = "roll_wear_resistance";
  f->shape = "per_roll";
  f->form = TermFormName(TermForm::kRollEffect);
  f->term = spec.term;
  f->parameters["tau"] = h.tau;
  f->parameters["rolls"] = h.rolls;
  f->lr = h.q;
  f->df = h.rolls - 1;
  f->p_value = h.p_value;
  f->p_adjusted = h.p_value;
  f->cv_gap_before_um = cv_before.gap;
  f->cv_gap_after_um = cv_with.gap;
  f->cv_mse_ratio = cv_with.mse / cv_before.mse;
  f->gap_val_before_um = Gap(
      st.td, st.val, PredictTerms(st.td, st.val, before.log_k, before.terms));
  f->gap_val_after_um =
      Gap(st.td, st.val, PredictTerms(st.td, st.val, with.log_k, with.terms));
  // The rolls furthest from their type, for the sentence.
  int lo = 0, hi = 0;
  for (int l = 1; l < spec.term.num_levels; ++l) {
    if (spec.term.params[l] < spec.term.params[lo]) lo = l;
    if (spec.term.params[l] > spec.term.params[hi]) hi = l;
  }
  char text[512];
  std::snprintf(
      text, sizeof text,
      "Each physical roll wears at its own rate under the same strips "
      "(its material, supplier or heat treatment): the %d rolls with "
      "training readings scatter by %.0f %% (between-roll sd of the wear "
      "multiplier, Cochran's Q = %.1f on %d df); roll %s wears x %.2f, "
      "roll %s x %.2f. A roll the model has not seen starts at its "
      "type's value.",
      h.rolls, 100 * h.tau, h.q, h.rolls - 1, spec.term.levels[hi].c_str(),
      std::exp(spec.term.params[hi]), spec.term.levels[lo].c_str(),
      std::exp(spec.term.params[lo]));
  f->explanation = text;
}

}  // namespace

namespace {

// Whether the fitted multipliers follow a recorded roll-level quantity
// (hardness, diameter, a mounts.csv number): Pearson's r over the rolls of
// b_r against the roll's mean of the covariate on its training readings,
// t^2 = r^2 (n - 2) / (1 - r^2) ~ F(1, n - 2), any of the tests at the
// round's level (RoundFamily, diagnosis_alternatives.h). Returns "" or why
// not: such a scatter is that quantity's, not the rolls' own.
std::string FollowsARecordedQuantity(const TermData& td,
                                     const std::vector<int>& train,
                                     const TermSpec& roll,
                                     const DiagnosisOptions& options) {
  const int levels = roll.term.num_levels;
  // Per eligible covariate and roll type (-1: all rolls), Bonferroni over
  // those tests.
  const auto eligible = [&](const CovariateSpec& spec) {
    return spec.level == CovariateLevel::kRoll &&
           spec.kind == CovariateKind::kNumeric && !spec.locate_only;
  };
  double tests = 0;
  for (const CovariateSpec& spec : td.catalog) {
    if (eligible(spec)) tests += static_cast<double>(td.roll_types.size() + 1);
  }
  for (int c = 0; c < static_cast<int>(td.catalog.size()); ++c) {
    const CovariateSpec& spec = td.catalog[c];
    if (spec.level != CovariateLevel::kRoll ||
        spec.kind != CovariateKind::kNumeric || spec.locate_only) {
      continue;
    }
    for (int type = -1; type < static_cast<int>(td.roll_types.size()); ++type) {
      std::vector<double> sum(levels, 0.0);
      std::vector<int> n(levels, 0);
      for (int o : train) {
        const TermObservation& ob = td.obs[o];
        if (ob.pass_end <= ob.pass_begin || (type >= 0 && ob.roll_type != type))
          continue;
        const int l = LevelIndex(td.z[roll.covariate][ob.pass_begin]);
        const double z = td.obs_z[c][o];
        if (l < 0 || l >= levels || !std::isfinite(z)) continue;
        sum[l] += z;
        ++n[l];
      }
      std::vector<double> x, y;
      for (int l = 0; l < levels; ++l) {
        if (n[l] == 0) continue;
        x.push_back(sum[l] / n[l]);
        y.push_back(roll.term.params[l]);
      }
      const double m = static_cast<double>(x.size());
      if (m < 5) continue;
      double mx = 0, my = 0;
      for (size_t i = 0; i < x.size(); ++i) mx += x[i] / m, my += y[i] / m;
      double sxy = 0, sxx = 0, syy = 0;
      for (size_t i = 0; i < x.size(); ++i) {
        sxy += (x[i] - mx) * (y[i] - my);
        sxx += (x[i] - mx) * (x[i] - mx);
        syy += (y[i] - my) * (y[i] - my);
      }
      if (!(sxx > 0 && syy > 0)) continue;
      const double r = sxy / std::sqrt(sxx * syy);
      const double p =
          FSurvival(r * r * (m - 2) / std::max(1e-12, 1 - r * r), 1, m - 2);
      if (!RoundFamily(options, tests).Rejects(p)) continue;
      char text[240];
      std::snprintf(text, sizeof text,
                    "the rolls' multipliers follow %s%s%s (r = %.2f over %d "
                    "rolls, p = %.2g): "
                    "a recorded quantity, not the rolls' own",
                    spec.name.c_str(), type >= 0 ? " on roll type " : "",
                    type >= 0 ? td.roll_types[type].c_str() : "", r,
                    static_cast<int>(m), p);
      return text;
    }
  }
  return "";
}

// The cross-validated test of `with` beside the current model and beside
// each calendar rival; "" or why not.
std::string HeldOutVerdict(const DiagnosisOptions& options,
                           const DiagnosisState& st,
                           const std::vector<double>& sd, const Fitted& cur,
                           const Fitted& with, CvResult* cv_cur,
                           CvResult* cv_with) {
  std::vector<Fitted> models = {cur, with};
  std::vector<std::string> rivals;
  for (const char* name : {"started_at", kRollCampaignsBeforeName}) {
    const TermSpec rival =
        CalendarRival(st.td, st.train, name, options.num_bins);
    if (rival.covariate < 0) continue;
    const Fitted r = FitWith(st, sd, cur, rival);
    const Fitted rw =
        r.usable ? FitWith(st, sd, r, with.terms.back()) : Fitted{};
    if (!r.usable || !rw.usable) continue;
    models.push_back(r);
    models.push_back(rw);
    rivals.push_back(name);
  }
  std::vector<const Fitted*> pointers;
  for (const Fitted& m : models) pointers.push_back(&m);
  const std::vector<CvResult> cv =
      CrossValidate(st, sd, pointers, options.num_threads);
  *cv_cur = cv[0];
  *cv_with = cv[1];
  const double keep = 1 - options.min_cv_improvement;
  if (!(cv[1].mse <= keep * cv[0].mse)) {
    return "rolls scatter (Q test) but per-roll multipliers do not predict "
           "held-out "
           "campaigns better";
  }
  for (size_t r = 0; r < rivals.size(); ++r) {
    if (!(cv[3 + 2 * r].mse <= keep * cv[2 + 2 * r].mse)) {
      return "not distinguishable from a drift along " + rivals[r] +
             ": per-roll multipliers add nothing held out beside it";
    }
  }
  return "";
}

// The rolls' scatter under `model` (its own noise sd): each training
// reading's wear alone (a measurement term's offset does not scale with the
// roll) in *pred, the reading less the model's offsets in *y.
Heterogeneity ScatterUnder(const DiagnosisState& st,
                           const DiagnosisOptions& options,
                           const std::vector<double>& sd, const Fitted& model,
                           int k, std::vector<double>* pred,
                           std::vector<double>* y) {
  const TermData& td = st.td;
  *pred = PredictTerms(td, st.train, model.log_k, model.terms,
                       /*wear_only=*/true);
  const std::vector<double> full =
      PredictTerms(td, st.train, model.log_k, model.terms);
  y->resize(st.train.size());
  for (size_t i = 0; i < y->size(); ++i) {
    (*y)[i] = td.obs[st.train[i]].measured_um - (full[i] - (*pred)[i]);
  }
  return RollHeterogeneity(td, k, st.train, *pred, *y, sd, options);
}

}  // namespace

bool RollScatterTerm(const DiagnosisState& st, const DiagnosisOptions& options,
                     const std::vector<double>& sd, const Fitted& model,
                     TermSpec* term) {
  const int k = st.td.CovariateIndex(kRollIdName);
  if (k < 0) return false;
  std::vector<double> pred, y;
  const Heterogeneity h = ScatterUnder(st, options, sd, model, k, &pred, &y);
  if (h.rolls < 3 || !(h.tau > 0)) return false;
  *term = RollTerm(st.td, k, h.tau);
  return true;
}

bool RunRollFamily(const DiagnosisOptions& options, DiagnosisState* st,
                   DiagnosisReport* report) {
  const TermData& td = st->td;
  const int k = td.CovariateIndex(kRollIdName);
  if (k < 0 || st->fit_sets.empty() ||
      static_cast<int>(report->findings.size()) >= options.max_findings) {
    return false;
  }
  std::vector<double> sd;
  const Fitted cur =
      FitWithOwnNoise(*st, options, st->current.log_k, st->current.terms, &sd);
  if (!cur.usable) return false;
  std::vector<double> pred, y;
  const Heterogeneity h = ScatterUnder(*st, options, sd, cur, k, &pred, &y);
  if (h.rolls < 3 || h.p_value >= options.alpha || !(h.tau > 0)) return false;
  std::string why =
      ScatterNotEverywhere(td, k, st->train, pred, y, sd, h, options);
  const Fitted with =
      why.empty() ? FitWith(*st, sd, cur, RollTerm(td, k, h.tau)) : Fitted{};
  if (why.empty() && !with.usable) why = "the per-roll fit did not converge";
  if (why.empty()) {
    why = FollowsARecordedQuantity(td, st->train, with.terms.back(), options);
  }
  CvResult cv_cur, cv_with;
  if (why.empty())
    why = HeldOutVerdict(options, *st, sd, cur, with, &cv_cur, &cv_with);
  if (!why.empty()) {
    Refuse(h, why, report);
    return false;
  }
  Fitted adopted = with;
  SetRollEffectSpread(td, st->train, sd, adopted.log_k, &adopted.terms);
  Finding f;
  FillFinding(*st, h, cur, adopted, cv_cur, cv_with, &f);
  report->findings.push_back(std::move(f));
  st->current = std::move(adopted);
  return true;
}

}  // namespace rollwear::diag
