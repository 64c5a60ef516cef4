// The guard against proxies (docs/diagnosis.md, "The proxy guard"): before
// a round's winner is named, check that it describes the mismatch and is
// not a stand-in for it.
//  (a) Consistency. With the winner's fit, let D_i be the term's
//      contribution to observation i (prediction with the term minus
//      prediction with the same coefficients without it) and e_i the
//      residual without it, P_i the prediction without it. Per group g of a
//      dimension (listed below) the weighted least
//      squares fit e ~ a_g P + b_g D (w = 1 / sd^2; the a_g P column takes
//      up what the group's multiplicative K coefficients absorb) gives the
//      scale b_g of the effect's shape inside the group, with variance
//      phi [(X'WX)^-1]_DD (phi the weighted mean square of the adopted
//      model's residuals); a global effect has the same b_g (about 1)
//      everywhere.
//      Heterogeneity: Cochran's Q = sum_g (b_g - b_bar)^2 / se_g^2 with
//      b_bar the inverse-variance weighted mean, ~ chi2(G - 1) under
//      homogeneity (Cochran 1954, Biometrics 10:101). This is the
//      linearised test of a term x group interaction with K held at the
//      fit. Significant (p * 5 < alpha, Bonferroni over the dimensions below)
//      and material (some |b_g - b_bar| >= material_scale): not adopted.
//      Within groups. b_bar, with variance 1 / sum_g(1 / se_g^2), is the
//      effect's scale estimated inside the groups only. A term whose fitted
//      effect (scale 1 by construction) comes from the contrast BETWEEN the
//      groups while nothing of its shape holds inside them (b_bar far from
//      1: |b_bar - 1| >= material_scale with p * 5 < alpha for the z test)
//      is a stand-in for a group-level effect (a cell or a scoped K), e.g. a
//      contact length term on one roll type whose contact length differs
//      between the two stands it runs in: not adopted.
//      The dimensions: stand, roll position, roll type, stand x roll type
//      cell, and the quartiles of every other numeric wear-rate covariate
//      (campaign-aggregated; started_at not for a calendar-time term),
//      Bonferroni over all of them. A proxy for a drift or a step in time
//      has no shape inside a quarter of the period (b_bar near 0); an
//      interaction (an effect of temperature only at high speed) changes
//      scale across the other quantity's quartiles (Cochran's Q).
//  (b) Look again (diagnosis_look_again.cc): the breakdown that located
//      the mismatch most strongly must be materially reduced by the term;
//      roll-to-roll scatter left behind is judged beside a per-roll term.
//  (c) Along time (diagnosis_along_time.cc): a calendar-time term must take
//      away at least half of the lag-1 autocovariance of the time-ordered
//      campaign means of the residuals, when that is significant.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>

#include "core/base/distributions.h"
#include "core/diagnosis/diagnosis_alternatives.h"
#include "core/diagnosis/diagnosis_look_again.h"
#include "core/diagnosis/diagnosis_stages_internal.h"
#include "core/fit/robust.h"

namespace rollwear::diag {
namespace {

struct Heterogeneity {
  double q = 0, p = 1, max_dev = 0;
  // The within-group scale b_bar and the p-value of b_bar = 1 (two-sided z).
  double b_bar = 1, p_within = 1;
  int groups = 0;
  std::string group;         // the group with the largest |b_g|
  double group_mean_um = 0;  // its mean residual before the round
};

// Per group: weighted least squares of e on (p0, D); the level column p0
// takes up what a change of the group's K coefficients would (they are
// multiplicative), so b_g measures the shape of the effect inside the group.
// `before`: the residuals of the model without any version of the term,
// for the group's mean residual.
Heterogeneity Cochran(const std::vector<std::string>& label,
                      const std::vector<double>& e,
                      const std::vector<double>& p0,
                      const std::vector<double>& d,
                      const std::vector<double>& w,
                      const std::vector<double>& before, double phi,
                      const DiagnosisThresholds& thresholds) {
  struct Sums {
    double pp = 0, pd = 0, dd = 0, pe = 0, de = 0, se = 0;
    int n = 0;
  };
  std::map<std::string, Sums> by;
  for (size_t i = 0; i < label.size(); ++i) {
    if (label[i].empty()) continue;  // no value: in no group
    Sums& s = by[label[i]];
    s.pp += w[i] * p0[i] * p0[i];
    s.pd += w[i] * p0[i] * d[i];
    s.dd += w[i] * d[i] * d[i];
    s.pe += w[i] * p0[i] * e[i];
    s.de += w[i] * d[i] * e[i];
    s.se += before[i];
    ++s.n;
  }
  struct Scale {
    std::string group;
    double b, var, mean_um;
  };
  std::vector<Scale> used;
  double sum_wb = 0, sum_w = 0;
  for (const auto& [g, s] : by) {
    const double det = s.pp * s.dd - s.pd * s.pd;
    // The partial variance of D given p0 must not vanish.
    if (s.n < thresholds.min_group_observations || !(det > 1e-9 * s.pp * s.dd))
      continue;
    const double b = (s.pp * s.de - s.pd * s.pe) / det;
    const double var = phi * s.pp / det;
    used.push_back({g, b, var, s.se / s.n});
    sum_wb += b / var;
    sum_w += 1 / var;
  }
  Heterogeneity h;
  if (used.empty() || !(sum_w > 0)) return h;
  const double b_bar = sum_wb / sum_w;
  h.b_bar = b_bar;
  h.groups = static_cast<int>(used.size());
  // (b_bar - 1)^2 * sum_w ~ chi2(1): the two-sided z test of b_bar = 1.
  h.p_within = ChiSquareSurvival((b_bar - 1) * (b_bar - 1) * sum_w, 1.0);
  if (used.size() < 2) {
    h.group = used[0].group;
    h.group_mean_um = used[0].mean_um;
    return h;
  }
  double largest = -1;
  for (const Scale& sc : used) {
    h.q += (sc.b - b_bar) * (sc.b - b_bar) / sc.var;
    h.max_dev = std::max(h.max_dev, std::abs(sc.b - b_bar));
    if (std::abs(sc.b) > largest) {  // where the effect lives
      largest = std::abs(sc.b);
      h.group = sc.group;
      h.group_mean_um = sc.mean_um;
    }
  }
  h.p = ChiSquareSurvival(h.q, static_cast<double>(used.size() - 1));
  return h;
}

// Each training observation's quartile ("Q1".."Q4") of covariate k as the
// model aggregates it over the campaign (TermData::obs_z); "" where missing.
std::vector<std::string> Quartiles(const TermData& td,
                                   const std::vector<int>& train, int k) {
  std::vector<std::string> out(train.size());
  std::vector<double> sorted;
  for (int o : train) {
    if (!std::isnan(td.obs_z[k][o])) sorted.push_back(td.obs_z[k][o]);
  }
  if (sorted.size() < 4) return out;
  std::sort(sorted.begin(), sorted.end());
  const auto at = [&](double q) {
    return sorted[static_cast<size_t>(q * (sorted.size() - 1))];
  };
  const std::array<double, 3> edges = {at(0.25), at(0.5), at(0.75)};
  for (size_t i = 0; i < train.size(); ++i) {
    const double t = td.obs_z[k][train[i]];
    if (std::isnan(t)) continue;
    out[i] = "Q" + std::to_string(QuartileOf(t, edges) + 1);
  }
  return out;
}

// The guard's refusal of a term inconsistent over dimension `name`: the
// reason and, as an unexplained location, the group where the effect lives.
GuardResult Refused(const std::string& reason, const std::string& name,
                    const Heterogeneity& h, const char* test, double statistic,
                    double p, double dims) {
  GuardResult r;
  r.pass = false;
  r.reason = reason;
  r.located.dimension = "effect_by_" + name;
  r.located.where = name + "=" + h.group;
  r.located.test = test;
  r.located.statistic = statistic;
  r.located.mean_residual_um = h.group_mean_um;
  r.located.p_value = p;
  r.located.p_adjusted = std::min(1.0, dims * p);
  return r;
}

// The dimensions of the consistency and within-group tests: stand, roll
// position, roll type, the stand x roll type cell, the levels of every text
// column of mounts.csv and campaigns.csv, and the quartiles of every
// other numeric wear-rate covariate (an effect whose scale changes sign or
// size with another quantity is an interaction the term does not describe,
// e.g. a temperature effect that exists only at high speed). A calendar-time
// term is itself about time: its shape inside a quarter of the period says
// nothing (a step drift is flat in three of them), so started_at is not a
// dimension for it.
void GuardDimensions(const TermData& td, const std::vector<int>& train,
                     const std::string& cov,
                     const std::vector<std::string>& stand,
                     const std::vector<std::string>& position,
                     const std::vector<std::string>& roll_type,
                     std::vector<std::string>* names,
                     std::vector<std::vector<std::string>>* labels) {
  std::vector<std::string> cell(stand.size());
  for (size_t i = 0; i < stand.size(); ++i)
    cell[i] = stand[i] + "/" + roll_type[i];
  *names = {"stand", "position", "roll_type", "stand_roll_type"};
  *labels = {stand, position, roll_type, cell};
  ModelTerm term;
  term.covariate = cov;
  const bool calendar = IsCalendarTerm(td, term);
  for (int k = 0; k < static_cast<int>(td.catalog.size()); ++k) {
    const CovariateSpec& c = td.catalog[k];
    if (c.source == CovariateSource::kRollId) continue;  // not a group of rolls
    // A text column of mounts.csv or campaigns.csv holds one level per
    // reading: its levels are groups like the stands (the pass-level ones
    // are split by level in diagnosis_split.cc).
    if (c.kind == CovariateKind::kFactor && c.name != cov &&
        (c.level == CovariateLevel::kRoll ||
         c.level == CovariateLevel::kCampaign)) {
      std::vector<std::string> level(train.size());
      for (size_t i = 0; i < train.size(); ++i) {
        const double z = td.obs_z[k][train[i]];
        const int l = LevelIndex(z);
        if (l >= 0 && l < static_cast<int>(c.levels.size()))
          level[i] = c.levels[l];
      }
      names->push_back(c.name);
      labels->push_back(std::move(level));
      continue;
    }
    if (c.kind != CovariateKind::kNumeric ||
        c.level == CovariateLevel::kMeasurement ||
        c.source == CovariateSource::kCell || c.name == cov ||
        (calendar && c.source == CovariateSource::kStartedAt)) {
      continue;
    }
    names->push_back(c.name);
    labels->push_back(Quartiles(td, train, k));
  }
}

}  // namespace

namespace {

// What every proxy guard reads: the candidate (the last term of
// `with_term`), the state, and the predictions and residuals of the
// training readings computed once for it.
struct ProxyGuardContext {
  ProxyGuardContext(const Dataset& data_in, const DiagnosisState& st_in,
                    const DiagnosisOptions& options_in,
                    const std::vector<double>& sd_in,
                    const std::vector<Breakdown>& located_before_in,
                    const Fitted& with_term_in,
                    const std::vector<std::string>& refused_in)
      : data(data_in),
        st(st_in),
        options(options_in),
        sd(sd_in),
        located_before(located_before_in),
        with_term(with_term_in),
        refused(refused_in) {}

  const Dataset& data;
  const DiagnosisState& st;
  const DiagnosisOptions& options;
  const std::vector<double>& sd;
  const std::vector<Breakdown>& located_before;
  const Fitted& with_term;
  // The covariates of the round's candidates the guards refused before.
  const std::vector<std::string>& refused;
  // With the term (p1), without it (p0), the adopted model (pc).
  std::vector<double> p1, p0, pc;
  // Residual without the term, the term's contribution, weight 1/sd^2,
  // residual under the adopted model, sd (clip), per training reading.
  std::vector<double> e, d, w, before, clip;
  double phi = 0;  // weighted mean square with the term
  // The groups it must be consistent across (stand, position, roll type,
  // text columns, quartiles), and the pass-level factors' splits.
  std::vector<std::string> names;
  std::vector<std::vector<std::string>> labels;
  std::vector<SplitHeterogeneity> split;
  double dims = 0;  // Bonferroni: the number of looks
  double num_tests = 1;  // the round's Bonferroni count
};

ProxyGuardContext MakeProxyGuardContext(
    const Dataset& data, const DiagnosisState& st,
    const DiagnosisOptions& options, const std::vector<double>& sd,
    const std::vector<Breakdown>& located_before, const Fitted& with_term,
    const std::vector<std::string>& refused) {
  ProxyGuardContext c(data, st, options, sd, located_before, with_term,
                      refused);
  const TermData& td = st.td;
  std::vector<TermSpec> without = with_term.terms;
  without.pop_back();
  c.p1 = PredictTerms(td, st.train, with_term.log_k, with_term.terms);
  c.p0 = PredictTerms(td, st.train, with_term.log_k, without);
  c.pc = PredictTerms(td, st.train, st.current.log_k, st.current.terms);
  const size_t n = st.train.size();
  c.e.resize(n), c.d.resize(n), c.w.resize(n), c.clip.resize(n);
  c.before.resize(n);
  std::vector<std::string> stand(n), position(n), roll_type(n);
  for (size_t i = 0; i < n; ++i) {
    const int o = st.train[i];
    const TermObservation& ob = td.obs[o];
    c.w[i] = 1.0 / (sd[o] * sd[o]);
    c.e[i] = ob.measured_um - c.p0[i];
    c.before[i] = ob.measured_um - c.pc[i];
    c.d[i] = c.p1[i] - c.p0[i];
    const double r1 = ob.measured_um - c.p1[i];
    c.phi += c.w[i] * r1 * r1;
    c.clip[i] = sd[o];
    stand[i] = "F" + std::to_string(SlotStand(ob.slot));
    position[i] = SlotPosition(ob.slot) == Position::kTop ? "top" : "bottom";
    roll_type[i] = ob.roll_type >= 0 ? td.roll_types[ob.roll_type] : "?";
  }
  c.phi /= std::max<size_t>(1, n);
  GuardDimensions(td, st.train, with_term.terms.back().term.covariate, stand,
                  position, roll_type, &c.names, &c.labels);
  c.split = SplitByPassFactors(st, with_term, c.e, c.w, c.phi);
  c.dims = static_cast<double>(c.names.size()) +
           static_cast<double>(std::count_if(
               c.split.begin(), c.split.end(),
               [](const SplitHeterogeneity& s) { return !s.inside_gate; }));
  return c;
}

// The strongest inconsistent split (of the deferred ones or the others)
// names where the effect lives (a flag term is split by every pass-level
// quartile factor too, and the covariate the effect follows differs most):
// by the standardised statistic (W - df) / sqrt(2 df), df = levels - 1,
// since p-values this small underflow alike.
GuardResult StrongestSplit(const ProxyGuardContext& c, bool deferred) {
  const auto standardised = [](const SplitHeterogeneity& s) {
    const double df = std::max(1, s.levels - 1);
    return (s.wald - df) / std::sqrt(2 * df);
  };
  const SplitHeterogeneity* strongest = nullptr;
  for (const SplitHeterogeneity& s : c.split) {
    if (s.deferred == deferred && !s.inside_gate &&
        s.p * c.dims < c.options.alpha &&
        s.max_dev >= c.options.thresholds.material_scale &&
        (strongest == nullptr || standardised(s) > standardised(*strongest))) {
      strongest = &s;
    }
  }
  if (strongest == nullptr) return GuardResult{};
  Heterogeneity h;
  h.group = strongest->level;
  h.group_mean_um = strongest->level_size_um;  // the effect's size there
  return Refused("inconsistent across " + strongest->factor, strongest->factor,
                 h, "wald_by_level", strongest->wald, strongest->p, c.dims);
}

// Each group dimension in turn: the term's scale differs between its
// groups (Cochran's Q), or the effect lives between the groups and not
// within them.
GuardResult GroupConsistency(const ProxyGuardContext& c) {
  const DiagnosisThresholds& t = c.options.thresholds;
  for (size_t di = 0; di < c.names.size(); ++di) {
    const char* name = c.names[di].c_str();
    const Heterogeneity h =
        Cochran(c.labels[di], c.e, c.p0, c.d, c.w, c.before, c.phi, t);
    if (h.p * c.dims < c.options.alpha && h.max_dev >= t.material_scale) {
      return Refused(std::string("inconsistent across ") + name, name, h,
                     "cochran_q", h.q, h.p, c.dims);
    }
    if (h.p_within * c.dims < c.options.alpha &&
        std::abs(h.b_bar - 1) >= t.material_scale) {
      char buf[120];
      std::snprintf(buf, sizeof(buf),
                    "effect lives between groups of %s, not within them (scale "
                    "within %.2f)",
                    name, h.b_bar);
      return Refused(buf, name, h, "within_group_z", h.b_bar, h.p_within,
                     c.dims);
    }
  }
  return GuardResult{};
}

// The interaction with a refused candidate: the term's scale differs
// across the levels (or quartiles) of a covariate whose own term the guards
// refused earlier in the round. The two then carry one structure that
// neither describes, an interaction, and the term that passed is its
// weaker reading (an interaction of temperature and speed without main
// effects: temperature refused as inconsistent across grade, then speed
// named at F6, its scale differing across the temperature quartiles,
// DiagnosisProxyTest.AnInteractionWithARefusedCovariateIsNotNamed). The
// refused covariates are hypotheses chosen before this look, so the split
// Wald tests (SplitByPassFactors) along them are corrected for their number
// only, not for every dimension the consistency tests look at (Bonferroni
// over a pre-specified family), at the level of the alternatives
// (thresholds.alternative_alpha, diagnosis_alternatives.h): like them it
// decides whether the data say the named covariate alone carries the mismatch,
// and a refusal here costs a "located" where a wrong pass costs a wrong name.
GuardResult InteractsWithRefused(const ProxyGuardContext& c) {
  std::vector<const SplitHeterogeneity*> along;
  for (const SplitHeterogeneity& s : c.split) {
    if (!s.inside_gate && std::find(c.refused.begin(), c.refused.end(),
                                    s.factor) != c.refused.end()) {
      along.push_back(&s);
    }
  }
  const double m = static_cast<double>(along.size());
  const Multiplicity family = AnyOf(c.options.thresholds, m);
  const SplitHeterogeneity* strongest = nullptr;
  for (const SplitHeterogeneity* s : along) {
    if (family.Rejects(s->p) &&
        s->max_dev >= c.options.thresholds.material_scale &&
        (strongest == nullptr || s->p < strongest->p)) {
      strongest = s;
    }
  }
  if (strongest == nullptr) return GuardResult{};
  Heterogeneity h;
  h.group = strongest->level;
  h.group_mean_um = strongest->level_size_um;
  const std::string& cov = c.with_term.terms.back().term.covariate;
  return Refused("its effect differs across " + strongest->factor +
                     ", whose own term was refused: an interaction of " + cov +
                     " and " + strongest->factor + " that no family describes",
                 strongest->factor, h, "wald_by_level", strongest->wald,
                 strongest->p, m);
}

// A gated term's effect is one multiplier on every pass beyond its
// threshold: its scale must not differ between the near and the far half of
// the passes inside the gate (SplitByPassFactors' inside_gate split, by the
// gate covariate). One hypothesis the gate's own form implies, so tested at
// thresholds.alternative_alpha without the consistency guards' Bonferroni: a
// slope along the gate covariate on the flag's passes (speed acting on
// lubricated passes only) otherwise reads as the flag behind a gate.
GuardResult ConstantInsideGate(const ProxyGuardContext& c) {
  const TermScope& scope = c.with_term.terms.back().term.scope;
  if (scope.gate.empty()) return GuardResult{};
  if (std::none_of(c.split.begin(), c.split.end(),
                   [](const SplitHeterogeneity& s) { return s.inside_gate; })) {
    // Not checked is not passed: too few of its passes on one half.
    GuardResult r;
    r.pass = false;
    r.reason =
        "whether its effect is constant inside its gate cannot be tested "
        "(too few of its passes on one half)";
    return r;
  }
  const Multiplicity one = AnyOf(c.options.thresholds, 1);
  for (const SplitHeterogeneity& s : c.split) {
    if (!s.inside_gate || !one.Rejects(s.p) ||
        s.max_dev < c.options.thresholds.material_scale) {
      continue;
    }
    Heterogeneity h;
    h.group = s.level;
    h.group_mean_um = s.level_size_um;
    return Refused(
        "its effect is not constant inside its gate: it differs "
        "across " +
            s.factor + " there",
        s.factor, h, "wald_by_level", s.wald, s.p, 1);
  }
  return GuardResult{};
}

GuardResult AlongTimeIfCalendar(const ProxyGuardContext& c) {
  const ModelTerm& term = c.with_term.terms.back().term;
  if (!IsCalendarTerm(c.st.td, term)) return GuardResult{};
  return LookAlongTime(c.data, c.st, c.options, c.sd, c.pc, c.p1,
                       term.covariate);
}

// One guard of the proxy chain: its name and its check.
struct ProxyGuard {
  const char* name;
  GuardResult (*check)(const ProxyGuardContext&);
};

// The chain, in order: each look comes after the places it may stand in
// for (a slope's quartile splits after stands, positions and roll types,
// which contact length follows). The first refusal stops it.
constexpr ProxyGuard kProxyGuards[] = {
    {"split_by_pass_factor",
     [](const ProxyGuardContext& c) { return StrongestSplit(c, false); }},
    {"group_consistency", GroupConsistency},
    {"split_by_quartile",
     [](const ProxyGuardContext& c) { return StrongestSplit(c, true); }},
    {"gate_required",
     [](const ProxyGuardContext& c) {
       return GateRequired(c.st, c.options, c.sd, c.with_term);
     }},
    {"inside_cell",
     [](const ProxyGuardContext& c) {
       return LookInsideCell(c.st, c.options, c.sd, c.with_term);
     }},
    {"within_scope",
     [](const ProxyGuardContext& c) {
       return LookWithinScope(c.st, c.options, c.sd, c.with_term);
     }},
    {"siblings",
     [](const ProxyGuardContext& c) {
       return LookAtSiblings(c.st, c.options, c.sd, c.with_term);
     }},
    {"along_time", AlongTimeIfCalendar},
    {"grade_order",
     [](const ProxyGuardContext& c) {
       return LookAtGradeOrder(c.st, c.options, c.sd, c.pc, c.p1);
     }},
    {"look_again",
     [](const ProxyGuardContext& c) {
       return LookAgainBesideRolls(
           c.data, c.st, c.options, c.sd, c.with_term, c.clip, c.num_tests,
           LookAgain(c.data, c.st, c.options, c.located_before, c.clip, c.p1));
     }},
    {"interacts_with_refused", InteractsWithRefused},
    {"constant_inside_gate", ConstantInsideGate},
};

}  // namespace

GuardResult GuardAgainstProxy(const Dataset& data, const DiagnosisState& st,
                              const DiagnosisOptions& options,
                              const std::vector<double>& sd,
                              const std::vector<Breakdown>& located_before,
                              const Fitted& with_term, double num_tests,
                              const std::vector<std::string>& refused) {
  ProxyGuardContext c = MakeProxyGuardContext(
      data, st, options, sd, located_before, with_term, refused);
  c.num_tests = num_tests;
  for (const ProxyGuard& guard : kProxyGuards) {
    GuardResult r = guard.check(c);
    if (!r.pass) {
      r.guard = guard.name;
      return r;
    }
  }
  return GuardResult{};
}

}  // namespace rollwear::diag
