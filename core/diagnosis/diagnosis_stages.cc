// The stages of Diagnose() (see diagnosis_stages_internal.h): baseline, data,
// folds, and the rounds of screen / refit / test / cross-validate / guard
// (diagnosis_winner.cc, then diagnosis_joint.cc) / adopt. The summary of the
// final model is diagnosis_summary.cc.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <string>
#include <unordered_map>
#include <utility>

#include "core/base/distributions.h"
#include "core/base/parallel.h"
#include "core/base/random.h"
#include "core/diagnosis/diagnosis_stages_internal.h"
#include "core/model/aggregation.h"
#include "core/model/metrics.h"

namespace rollwear::diag {

double Gap(const TermData& td, const std::vector<int>& obs,
           const std::vector<double>& pred) {
  if (obs.empty()) return 0;
  double s = 0;
  for (size_t i = 0; i < obs.size(); ++i) {
    s += std::abs(td.obs[obs[i]].measured_um - pred[i]);
  }
  return s / static_cast<double>(obs.size());
}

namespace {

// Best fit of current + candidate over the candidate's starting points.
Fitted FitTermCandidate(const TermData& td, const std::vector<int>& subset,
                        const std::vector<double>& sd, const Fitted& current,
                        const Candidate& cand) {
  std::vector<std::vector<double>> starts = cand.starts;
  if (starts.empty()) starts.push_back(cand.spec.term.params);
  Fitted best;
  for (const std::vector<double>& start : starts) {
    std::vector<TermSpec> terms = current.terms;
    terms.push_back(cand.spec);
    terms.back().term.params = start;
    Fitted f = Fit(td, subset, sd, current.log_k, terms);
    if (f.usable && (!best.usable || f.rss < best.rss)) best = std::move(f);
  }
  return best;
}

}  // namespace

std::vector<CvResult> CrossValidate(const DiagnosisState& st,
                                    const std::vector<double>& sd,
                                    const std::vector<const Fitted*>& models,
                                    int num_threads) {
  const TermData& td = st.td;
  const int folds = static_cast<int>(st.fit_sets.size());
  std::vector<std::vector<double>> preds(models.size() * folds);
  ParallelFor(static_cast<int>(preds.size()), num_threads, [&](int task) {
    const Fitted& start = *models[task / folds];
    const int f = task % folds;
    Fitted fold = Fit(td, st.fit_sets[f], sd, start.log_k, start.terms);
    if (!fold.usable) fold = start;
    preds[task] = PredictTerms(td, st.held_out[f], fold.log_k, fold.terms);
  });
  std::vector<CvResult> out(models.size());
  for (size_t m = 0; m < models.size(); ++m) {
    CvResult& cv = out[m];
    int n = 0;
    for (int f = 0; f < folds; ++f) {
      const std::vector<double>& pred = preds[m * folds + f];
      for (size_t i = 0; i < pred.size(); ++i) {
        const int o = st.held_out[f][i];
        const double e = td.obs[o].measured_um - pred[i];
        cv.mse += (e / sd[o]) * (e / sd[o]);
        cv.gap += std::abs(e);
        ++n;
      }
    }
    if (n > 0) {
      cv.mse /= n;
      cv.gap /= n;
    }
  }
  return out;
}

namespace {

// The score-test screen of one round: every candidate's smallest p-value
// over its starts, the candidate with that start only, and the number of
// tests (for the Bonferroni adjustment).
struct Screen {
  int num_tests = 0;
  std::vector<double> score_p;
  std::vector<Candidate> best_start;
};

// A calendar step's change point, refined: the candidate's edge t is one of
// thresholds.step_grid grid quantiles; every distinct training value of the
// covariate between the neighbouring grid points (and inside the trimmed
// range, the 1/step_grid and 1 - 1/step_grid quantiles, so a step leaves at
// least a twentieth of the data on each side) is tried as the edge, and the one
// with the largest score statistic kept (its statistic and p-value with
// it). Returns the number of edges the scan could have tried over the
// whole trimmed range: the round's Bonferroni count takes all of them (a
// union bound over the scan, conservative next to the sup-LR reference of
// Andrews 1993, Econometrica 61:821).
int RefineStep(const TermData& td, const std::vector<int>& train,
               const DiagnosisThresholds& thresholds, const ScoreScreen& score,
               Candidate* c, double* p) {
  TermSpec spec = c->spec;
  const WeightedValues w = Collect(td, train, spec.covariate);
  const double t = spec.term.edges[0];
  double below = 0;
  for (const auto& [z, wt] : w.v) below += z < t ? wt : 0.0;
  const double f = below / w.total, step = 1.0 / thresholds.step_grid;
  const double first = Quantile(w, step), final = Quantile(w, 1 - step);
  const double lo = std::max(first, Quantile(w, std::max(0.0, f - step)));
  const double hi = std::min(final, Quantile(w, std::min(1.0, f + step)));
  int possible = 0;
  double seen = -std::numeric_limits<double>::infinity();
  for (const auto& [z, wt] : w.v) {
    if (!(z > seen)) continue;
    seen = z;
    if (z >= first && z <= final) ++possible;
    if (z < lo || z > hi) continue;
    spec.term.edges = {z};
    int df = 0;
    const double s = score.Statistic(spec, &df);
    const double pz = df > 0 ? ChiSquareSurvival(s, df) : 1.0;
    if (pz < *p) {
      *p = pz;
      c->spec.term.edges = {z};
    }
  }
  return possible;
}

// Screens every candidate (and every grid start of its non-linear
// parameter) with the score test.
Screen ScreenCandidates(const DiagnosisState& st, const std::vector<double>& sd,
                        const std::vector<Candidate>& cands, int num_threads) {
  const TermData& td = st.td;
  const Fitted& current = st.current;
  const int nc = static_cast<int>(cands.size());
  Screen screen;
  for (const Candidate& c : cands) {
    screen.num_tests += std::max<int>(1, c.starts.size());
  }
  screen.score_p.assign(nc, 1.0);
  screen.best_start = cands;  // each with its best start only
  std::vector<double>& score_p = screen.score_p;
  std::vector<Candidate>& best_start = screen.best_start;
  const ScoreScreen score(td, st.train, sd, current.log_k, current.terms);
  ParallelFor(nc, num_threads, [&](int i) {
    std::vector<std::vector<double>> starts = cands[i].starts;
    if (starts.empty()) starts.push_back(cands[i].spec.term.params);
    for (const std::vector<double>& start : starts) {
      TermSpec spec = cands[i].spec;
      spec.term.params = start;
      int df = 0;
      const double s = score.Statistic(spec, &df);
      const double p = df > 0 ? ChiSquareSurvival(s, df) : 1.0;
      if (p < score_p[i] || best_start[i].starts.size() > 1) {
        if (p <= score_p[i]) best_start[i].starts = {start};
        score_p[i] = std::min(score_p[i], p);
      }
    }
  });
  // The strongest grid step of each calendar covariate (and scope), refined.
  std::map<std::pair<int, std::string>, int> strongest_step;
  for (int i = 0; i < nc; ++i) {
    if (!IsStep(cands[i].spec)) continue;
    const auto key = std::make_pair(cands[i].spec.covariate,
                                    cands[i].spec.term.scope.Label());
    auto [it, fresh] = strongest_step.emplace(key, i);
    if (!fresh && score_p[i] < score_p[it->second]) it->second = i;
  }
  std::vector<int> steps;
  std::map<std::pair<int, std::string>, int> grid;  // step candidates per key
  for (const auto& [key, i] : strongest_step) steps.push_back(i);
  for (int i = 0; i < nc; ++i) {
    if (IsStep(cands[i].spec)) {
      ++grid[{cands[i].spec.covariate, cands[i].spec.term.scope.Label()}];
    }
  }
  std::vector<int> possible(steps.size(), 0);
  ParallelFor(static_cast<int>(steps.size()), num_threads, [&](int j) {
    possible[j] = RefineStep(td, st.train, st.thresholds, score,
                             &best_start[steps[j]], &score_p[steps[j]]);
  });
  // Bonferroni over every edge the scan could have tried (the grid points
  // are already counted).
  for (size_t j = 0; j < steps.size(); ++j) {
    const Candidate& c = cands[steps[j]];
    screen.num_tests += std::max(
        0, possible[j] - grid[{c.spec.covariate, c.spec.term.scope.Label()}]);
  }
  return screen;
}

// Refits only the strongest screened candidates (at most max_refits, 6, and
// only while the Bonferroni-adjusted score p-value stays <=
// max_refit_score_p, 0.5; diagnosis_thresholds.h); the others stay
// unusable.
std::vector<Fitted> RefitStrongest(const DiagnosisState& st,
                                   const std::vector<double>& sd,
                                   const Screen& screen, int num_threads) {
  const int nc = static_cast<int>(screen.score_p.size());
  const std::vector<double>& score_p = screen.score_p;
  std::vector<int> by_score(nc);
  for (int i = 0; i < nc; ++i) by_score[i] = i;
  std::sort(by_score.begin(), by_score.end(),
            [&](int a, int b) { return score_p[a] < score_p[b]; });
  std::vector<int> to_fit;
  for (int i : by_score) {
    if (to_fit.size() >= static_cast<size_t>(st.thresholds.max_refits) ||
        score_p[i] * screen.num_tests > st.thresholds.max_refit_score_p)
      break;
    // One gate per term: the gates of one term are one description at
    // different thresholds, and would otherwise crowd the top six.
    if (GateOfATermIn(screen.best_start, i, to_fit)) continue;
    to_fit.push_back(i);
  }
  AddUngatedTwins(screen.best_start, &to_fit);
  AddRivalGates(screen.best_start, score_p,
                st.thresholds.max_refit_score_p / screen.num_tests, &to_fit);
  // The strongest cell is always refitted, so the proxy guard can compare a
  // covariate winner with the structural description (NoBetterThanCell,
  // diagnosis_winner.cc) even when covariate variants crowd the top six.
  for (int i : by_score) {
    if (screen.best_start[i].spec.term.form != TermForm::kCell) continue;
    if (std::find(to_fit.begin(), to_fit.end(), i) == to_fit.end())
      to_fit.push_back(i);
    break;
  }
  std::vector<Fitted> fits(nc);
  ParallelFor(static_cast<int>(to_fit.size()), num_threads, [&](int j) {
    fits[to_fit[j]] = FitTermCandidate(st.td, st.train, sd, st.current,
                                       screen.best_start[to_fit[j]]);
  });
  return fits;
}

// Each candidate's result: the score test, replaced by the likelihood-ratio
// test where the candidate was refitted.
std::vector<CandidateResult> TestCandidates(const DiagnosisState& st,
                                            const std::vector<Candidate>& cands,
                                            const Screen& screen,
                                            const std::vector<Fitted>& fits) {
  const int nc = static_cast<int>(cands.size());
  const double n = static_cast<double>(st.train.size());
  std::vector<CandidateResult> results(nc);
  for (int i = 0; i < nc; ++i) {
    CandidateResult& r = results[i];
    r.covariate = cands[i].spec.term.covariate;
    r.form = TermFormName(cands[i].spec.term.form);
    r.df = cands[i].spec.term.NumParams();
    r.cv_mse_ratio = std::nan("");
    r.p_value = screen.score_p[i];  // replaced by the LR test if refitted
    r.p_adjusted = std::min(1.0, r.p_value * screen.num_tests);
    if (!fits[i].usable) continue;
    r.lr = NestedLr(n, st.current.rss, fits[i].rss);
    r.p_value = ChiSquareSurvival(r.lr, r.df);
    r.p_adjusted = std::min(1.0, r.p_value * screen.num_tests);
  }
  return results;
}

// The cross-validation of one round: candidates by LR (strongest first),
// the significant ones cross-validated (at most 3), the current model's
// and each of their CV results.
struct CvRound {
  std::vector<int> order, to_cv;
  CvResult base;
  std::vector<CvResult> cand;  // aligned with to_cv
};

CvRound CrossValidateSignificant(const DiagnosisState& st,
                                 const std::vector<double>& sd,
                                 const std::vector<Fitted>& fits,
                                 const std::vector<CandidateResult>& results,
                                 const DiagnosisOptions& options) {
  const int nc = static_cast<int>(results.size());
  CvRound cv;
  cv.order.resize(nc);
  for (int i = 0; i < nc; ++i) cv.order[i] = i;
  std::sort(cv.order.begin(), cv.order.end(),
            [&](int a, int b) { return results[a].lr > results[b].lr; });
  for (int i : cv.order) {
    if (fits[i].usable && results[i].p_adjusted < options.alpha &&
        cv.to_cv.size() <
            static_cast<size_t>(options.thresholds.max_cross_validated) &&
        !GatedCopyIn(fits, i, cv.to_cv)) {
      cv.to_cv.push_back(i);
    }
  }
  // A gated candidate's significant ungated twin too (GateRequired).
  AddFittedTwins(fits, results, options.alpha, &cv.to_cv);
  // And the strongest significant cell, which the proxy guard compares
  // covariate winners with (NoBetterThanCell takes accepted cells only).
  for (int i : cv.order) {
    if (!fits[i].usable || fits[i].terms.back().term.form != TermForm::kCell)
      continue;
    if (results[i].p_adjusted < options.alpha &&
        std::find(cv.to_cv.begin(), cv.to_cv.end(), i) == cv.to_cv.end()) {
      cv.to_cv.push_back(i);
    }
    break;
  }
  if (cv.to_cv.empty()) return cv;
  // The current model first, then the candidates.
  std::vector<const Fitted*> models = {&st.current};
  for (int i : cv.to_cv) models.push_back(&fits[i]);
  std::vector<CvResult> res =
      CrossValidate(st, sd, models, options.num_threads);
  cv.base = res[0];
  cv.cand.assign(res.begin() + 1, res.end());
  return cv;
}

// Sets cv_mse_ratio and accepted of the cross-validated results; returns
// the accepted ones by penalised CV ratio, best first.
std::vector<int> RankAccepted(const CvRound& cv,
                              const DiagnosisOptions& options,
                              std::vector<CandidateResult>* results) {
  std::vector<int> accepted;
  for (size_t j = 0; j < cv.to_cv.size(); ++j) {
    CandidateResult& r = (*results)[cv.to_cv[j]];
    r.cv_mse_ratio = cv.base.mse > 0 ? cv.cand[j].mse / cv.base.mse : 1.0;
    r.accepted = r.cv_mse_ratio < 1 - options.min_cv_improvement;
    if (r.accepted) accepted.push_back(cv.to_cv[j]);
  }
  auto penalised = [&](int i) {
    const CandidateResult& c = (*results)[i];
    return c.cv_mse_ratio + options.cv_penalty_per_parameter * c.df;
  };
  std::stable_sort(accepted.begin(), accepted.end(),
                   [&](int a, int b) { return penalised(a) < penalised(b); });
  return accepted;
}

// The top 15 candidates of the first round by p-value (ties in LR order).
void RecordFirstRound(const std::vector<int>& order,
                      const std::vector<CandidateResult>& results,
                      DiagnosisReport* report) {
  std::vector<int> by_p = order;
  std::stable_sort(by_p.begin(), by_p.end(), [&](int a, int b) {
    return results[a].p_value < results[b].p_value;
  });
  for (size_t i = 0; i < by_p.size() && i < 15; ++i) {
    report->first_round.push_back(results[by_p[i]]);
  }
}

// The winner's test figures and the accepted alternatives that explain the
// data about as well (CV ratio within thresholds.alternatives_cv_margin)
// over another covariate that could be named (not a cell, not a
// locate-only covariate).
Finding FindingFromTests(const DiagnosisState& st, const CvRound& cv,
                         const std::vector<CandidateResult>& results,
                         int winner) {
  const TermData& td = st.td;
  Finding f;
  const CandidateResult& wr = results[winner];
  f.lr = wr.lr;
  f.df = wr.df;
  f.p_value = wr.p_value;
  f.p_adjusted = wr.p_adjusted;
  f.cv_mse_ratio = wr.cv_mse_ratio;
  f.cv_gap_before_um = cv.base.gap;
  for (size_t j = 0; j < cv.to_cv.size(); ++j) {
    if (cv.to_cv[j] == winner) f.cv_gap_after_um = cv.cand[j].gap;
  }
  for (size_t j = 0; j < cv.to_cv.size(); ++j) {
    const CandidateResult& r = results[cv.to_cv[j]];
    // A cell is a place, not a covariate: not an alternative name; nor is
    // a covariate the diagnosis only locates along (roll_campaigns_before).
    const int c = td.CovariateIndex(r.covariate);
    if (r.accepted && r.covariate != wr.covariate &&
        r.covariate != kCellCovariateName &&
        !(c >= 0 && td.catalog[c].locate_only) &&
        r.cv_mse_ratio <=
            wr.cv_mse_ratio + st.thresholds.alternatives_cv_margin &&
        std::find(f.alternatives.begin(), f.alternatives.end(), r.covariate) ==
            f.alternatives.end()) {
      f.alternatives.push_back(r.covariate);
    }
  }
  return f;
}

// Step 6 (report). Refits the winner with standard errors (keeping its round
// fit if that fails), names it and fills the validation gaps of `f`; returns
// the adopted model.
Fitted AdoptWinner(const DiagnosisState& st, const std::vector<double>& sd,
                   const Fitted& winner_fit, Finding* f) {
  const TermData& td = st.td;
  std::vector<double> se;
  Fitted adopted =
      Fit(td, st.train, sd, winner_fit.log_k, winner_fit.terms, true, &se);
  if (!adopted.usable) adopted = winner_fit;
  const TermSpec& spec = adopted.terms.back();
  f->term = spec.term;
  const int offset = static_cast<int>(se.size()) - spec.term.NumParams();
  if (offset >= 0) {
    for (int j = 0; j < spec.term.NumParams(); ++j) {
      f->parameter_std_errors["param" + std::to_string(j)] = se[offset + j];
    }
  }
  NameFinding(td, st.train, spec, f);
  const Fitted& current = st.current;
  f->gap_val_before_um =
      Gap(td, st.val, PredictTerms(td, st.val, current.log_k, current.terms));
  f->gap_val_after_um =
      Gap(td, st.val, PredictTerms(td, st.val, adopted.log_k, adopted.terms));
  return adopted;
}

}  // namespace

Fitted Fit(const TermData& td, const std::vector<int>& subset,
           const std::vector<double>& sd, const std::vector<double>& log_k,
           std::vector<TermSpec> terms, bool errors,
           std::vector<double>* term_se) {
  Fitted f;
  StatusOr<TermFitResult> r = FitTerms(td, subset, sd, log_k, terms, errors);
  if (!r.ok()) return f;
  f.log_k = r->log_k;
  f.terms = r->terms;
  f.rss = r->weighted_rss;
  f.usable = r->usable;
  if (term_se != nullptr) *term_se = r->term_std_error;
  return f;
}

Fitted FitWithOwnNoise(const DiagnosisState& st,
                       const DiagnosisOptions& options,
                       const std::vector<double>& log_k,
                       const std::vector<TermSpec>& terms,
                       std::vector<double>* sd) {
  std::vector<double> own =
      TermNoiseSd(st.td, st.train, log_k, terms, nullptr, options.robust);
  Fitted f = Fit(st.td, st.train, own, log_k, terms);
  if (sd != nullptr) *sd = std::move(own);
  return f;
}

StatusOr<DiagnosisState> BuildState(const Dataset& data,
                                    const DiagnosisOptions& options,
                                    const Baseline& base,
                                    DiagnosisReport* report) {
  DiagnosisState st;
  st.thresholds = options.thresholds;
  ROLLWEAR_ASSIGN_OR_RETURN(st.td, BuildTermData(data, options.law));
  // The term fits shrink the grades where the baseline did, with its tau
  // (term_fit.h).
  const GradeShrinkage& shrunk = base.calibration.result.grade_shrinkage;
  if (shrunk.applied) st.td.grade_prior_sd = shrunk.tau;
  st.train_campaigns.insert(base.split.train.begin(), base.split.train.end());
  for (int o = 0; o < static_cast<int>(st.td.obs.size()); ++o) {
    (st.train_campaigns.count(st.td.obs[o].campaign) ? st.train : st.val)
        .push_back(o);
    st.all.push_back(o);
  }
  report->n_train = static_cast<int>(st.train.size());
  report->n_val = static_cast<int>(st.val.size());
  for (double k : base.calibration.result.model.k) {
    st.current.log_k.push_back(std::log(k));
  }
  st.before_all = PredictTerms(st.td, st.all, st.current.log_k, {});
  std::vector<double> p, e;
  for (int o : st.train) {
    p.push_back(st.before_all[o]);
    e.push_back(st.td.obs[o].measured_um - st.before_all[o]);
  }
  const RobustNoise noise = FitRobustNoise(p, e);
  if (options.robust) {
    for (int o : st.all) st.locate_sd.push_back(noise.SdAt(st.before_all[o]));
  }
  return st;
}

void MakeFolds(const DiagnosisOptions& options, const CampaignSplit& split,
               DiagnosisState* st) {
  std::vector<int> camps(split.train.begin(), split.train.end());
  Random rng(options.split_seed * 7919 + 17);
  rng.Shuffle(&camps);
  std::unordered_map<int, int> fold_of;
  for (size_t i = 0; i < camps.size(); ++i) {
    fold_of[camps[i]] = static_cast<int>(i) % options.cv_folds;
  }
  st->fit_sets.assign(options.cv_folds, {});
  st->held_out.assign(options.cv_folds, {});
  for (int o : st->train) {
    const int f = fold_of[st->td.obs[o].campaign];
    for (int g = 0; g < options.cv_folds; ++g) {
      (g == f ? st->held_out[g] : st->fit_sets[g]).push_back(o);
    }
  }
}

bool RunRound(int round, const Dataset& data, const DiagnosisOptions& options,
              std::set<int>* used, PhaseClock* phase, DiagnosisState* st,
              DiagnosisReport* report) {
  const TermData& td = st->td;
  std::vector<double> sd;
  const Fitted cur =
      FitWithOwnNoise(*st, options, st->current.log_k, st->current.terms, &sd);
  phase->Mark("round_fit");
  if (!cur.usable) return false;
  st->current = cur;
  if (st->unscoped.empty())
    st->unscoped = UnscopedCandidates(td, st->train, options);
  std::vector<TermScope> adopted_cells;
  for (const TermSpec& t : st->current.terms) {
    if (t.term.form == TermForm::kCell) adopted_cells.push_back(t.term.scope);
  }
  const std::vector<Candidate> cands = MakeCandidates(
      td, st->train, *used, st->unscoped, options.thresholds, adopted_cells);
  phase->Mark("candidates");
  if (cands.empty()) return false;
  // Screen every candidate with the score test, then refit only the
  // strongest.
  const Screen screen = ScreenCandidates(*st, sd, cands, options.num_threads);
  phase->Mark("screen");
  const std::vector<Fitted> fits =
      RefitStrongest(*st, sd, screen, options.num_threads);
  phase->Mark("refit");
  std::vector<CandidateResult> results =
      TestCandidates(*st, cands, screen, fits);
  // Cross-validate the significant ones (strongest first).
  const CvRound cv = CrossValidateSignificant(*st, sd, fits, results, options);
  phase->Mark("cross_validation");
  const std::vector<int> accepted = RankAccepted(cv, options, &results);
  if (round == 0) RecordFirstRound(cv.order, results, report);
  // The proxy guard, best accepted candidate first.
  RoundRefusals refusals;
  int winner = GuardedWinner(round, data, options, *st, sd, accepted, fits,
                             results, screen.num_tests, report, &refusals);
  std::string joint_note;
  if (winner < 0) {
    winner = JointWinner(round, data, options, sd, accepted, fits, results,
                         screen.num_tests, screen.score_p, screen.best_start,
                         refusals, st, report, &joint_note);
  }
  phase->Mark("guard");
  if (winner < 0) {
    for (Unexplained& u : refusals.located)
      report->unexplained.push_back(std::move(u));
    return false;
  }

  // Adopt the winner (step 6: report).
  Finding f = FindingFromTests(*st, cv, results, winner);
  f.carriers = CarriersOf(*st, sd, fits, results, winner);
  std::string twin_note;
  ReferenceChoice reference;
  const Fitted chosen = ChooseOffsetReference(
      *st, sd, OrientTwinCell(*st, sd, fits[winner], &twin_note), &reference);
  if (chosen.usable && chosen.rss < fits[winner].rss) {
    // Another reference fitted better: the finding's LR test is its own
    // (the cross-validation figures stay the tested candidate's).
    const double n = static_cast<double>(st->train.size());
    f.lr = NestedLr(n, st->current.rss, chosen.rss);
    f.p_value = ChiSquareSurvival(f.lr, f.df);
    f.p_adjusted = std::min(1.0, f.p_value * screen.num_tests);
  }
  Fitted adopted = AdoptWinner(*st, sd, chosen, &f);
  f.explanation += twin_note + joint_note;
  NoteUndeterminedSiblings(*st, sd, adopted, &f);
  StateReferenceIdentification(reference, &f);
  report->findings.push_back(f);
  phase->Mark("adopt");
  // One term per covariate; cells stay on offer at the other places.
  if (adopted.terms.back().term.form != TermForm::kCell) {
    used->insert(adopted.terms.back().covariate);
  }
  st->current = adopted;
  return true;
}

}  // namespace rollwear::diag
