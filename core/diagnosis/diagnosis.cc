// The diagnosis engine; see diagnosis.h for the procedure.
#include "core/diagnosis/diagnosis.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <unordered_set>

#include "core/model/aggregation.h"
#include "core/diagnosis/diagnosis_internal.h"
#include "core/base/distributions.h"
#include "core/base/parallel.h"
#include "core/model/k_structure.h"
#include "core/model/metrics.h"
#include "core/base/random.h"
#include "core/fit/study.h"

namespace rollwear {

bool DiagnosisOptions::IsValid(std::string* error) const {
  auto fail = [error](const char* what) {
    if (error != nullptr) *error = what;
    return false;
  };
  if (cv_folds < 2) return fail("cv_folds must be >= 2");
  if (!(alpha > 0 && alpha < 1)) return fail("alpha must be in (0, 1)");
  if (!(min_cv_improvement >= 0 && min_cv_improvement < 1)) {
    return fail("min_cv_improvement must be in [0, 1)");
  }
  if (max_findings < 0) return fail("max_findings must be >= 0");
  if (num_bins < 2) return fail("num_bins must be >= 2");
  if (num_threads < 1) return fail("num_threads must be >= 1");
  return true;
}

namespace {

using diag::Candidate;

struct Fitted {
  std::vector<double> log_k;
  std::vector<TermSpec> terms;
  double rss = 0;
  bool usable = false;
};

double Gap(const TermData& td, const std::vector<int>& obs, const std::vector<double>& pred) {
  if (obs.empty()) return 0;
  double s = 0;
  for (size_t i = 0; i < obs.size(); ++i) s += std::abs(td.obs[obs[i]].measured_um - pred[i]);
  return s / static_cast<double>(obs.size());
}

// Per-observation sd from a noise model fitted to the training residuals of
// the given model (all observations get an sd, from their prediction).

Fitted Fit(const TermData& td, const std::vector<int>& subset, const std::vector<double>& sd,
           const std::vector<double>& log_k, std::vector<TermSpec> terms,
           bool errors = false, std::vector<double>* term_se = nullptr) {
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

struct CvResult {
  double mse = 0, gap = 0;
};

// K-fold cross-validation on training campaigns of the model `terms`
// (current model plus, optionally, one candidate fitted on each fold).
CvResult CrossValidate(const TermData& td, const std::vector<std::vector<int>>& fit_sets,
                       const std::vector<std::vector<int>>& held_out,
                       const std::vector<double>& sd, const Fitted& start) {
  CvResult cv;
  int n = 0;
  for (size_t f = 0; f < fit_sets.size(); ++f) {
    Fitted fold = Fit(td, fit_sets[f], sd, start.log_k, start.terms);
    if (!fold.usable) fold = start;
    const std::vector<double> pred = PredictTerms(td, held_out[f], fold.log_k, fold.terms);
    for (size_t i = 0; i < pred.size(); ++i) {
      const int o = held_out[f][i];
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
  return cv;
}

}  // namespace

StatusOr<DiagnosisReport> Diagnose(const Dataset& data, const DiagnosisOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  std::string error;
  if (!options.IsValid(&error)) return Status::InvalidArgument("diagnosis options: " + error);
  DiagnosisReport report;
  report.law = WearLawName(options.law);
  auto mark = std::chrono::steady_clock::now();
  auto phase = [&report, &mark](const char* name) {
    const auto now = std::chrono::steady_clock::now();
    report.phase_seconds[name] += std::chrono::duration<double>(now - mark).count();
    mark = now;
  };

  // 1. Baseline.
  const DatasetIndex index(data);
  ROLLWEAR_ASSIGN_OR_RETURN(WearStatistics stats,
                            Aggregate(data, index, options.law));
  const CampaignSplit split =
      SplitCampaigns(stats, 2.0 / 3.0, options.split_seed);
  CalibrationOptions co;
  co.law = options.law;
  co.option = 1;
  ROLLWEAR_ASSIGN_OR_RETURN(SplitCalibration base,
                            CalibrateOnSplit(stats, split, co));
  if (!base.result.summary.usable) {
    return Status::NumericalFailure("baseline calibration failed: " +
                                    base.result.summary.BriefReport());
  }
  report.baseline_gap_train_um = base.train.gap_um;
  report.baseline_gap_val_um = base.validation.gap_um;
  phase("baseline");

  ROLLWEAR_ASSIGN_OR_RETURN(const TermData td,
                            BuildTermData(data, options.law));
  const std::unordered_set<int> train_campaigns(split.train.begin(), split.train.end());
  std::vector<int> train, val, all;
  for (int o = 0; o < static_cast<int>(td.obs.size()); ++o) {
    (train_campaigns.count(td.obs[o].campaign) ? train : val).push_back(o);
    all.push_back(o);
  }
  report.n_train = static_cast<int>(train.size());
  report.n_val = static_cast<int>(val.size());
  Fitted current;
  for (double k : base.result.model.k) current.log_k.push_back(std::log(k));
  const std::vector<double> before_all = PredictTerms(td, all, current.log_k, {});
  phase("data");

  // 2. Locate.
  report.locate = diag::Locate(td, data, all, before_all);
  phase("locate");

  // Folds of training campaigns for cross-validation.
  std::vector<int> camps(split.train.begin(), split.train.end());
  Random rng(options.split_seed * 7919 + 17);
  rng.Shuffle(&camps);
  std::unordered_map<int, int> fold_of;
  for (size_t i = 0; i < camps.size(); ++i) fold_of[camps[i]] = static_cast<int>(i) % options.cv_folds;
  std::vector<std::vector<int>> fit_sets(options.cv_folds), held_out(options.cv_folds);
  for (int o : train) {
    const int f = fold_of[td.obs[o].campaign];
    for (int g = 0; g < options.cv_folds; ++g) (g == f ? held_out[g] : fit_sets[g]).push_back(o);
  }

  // 3-4. Hypothesise and test, round after round.
  std::set<int> used;
  for (int round = 0; round < options.max_findings; ++round) {
    const std::vector<double> sd = TermNoiseSd(td, train, current.log_k, current.terms);
    Fitted cur = Fit(td, train, sd, current.log_k, current.terms);
    if (!cur.usable) break;
    current = cur;
    const std::vector<Candidate> cands = diag::MakeCandidates(td, train, used, options);
    const int nc = static_cast<int>(cands.size());
    if (nc == 0) break;
    // Screen every candidate (and every grid start of its non-linear
    // parameter) with the score test, then refit only the strongest.
    phase("refit");
    int num_tests = 0;
    for (const Candidate& c : cands) num_tests += std::max<int>(1, c.starts.size());
    std::vector<double> score_p(nc, 1.0);
    std::vector<Candidate> best_start = cands;  // each with its best start only
    ParallelFor(nc, options.num_threads, [&](int i) {
      std::vector<std::vector<double>> starts = cands[i].starts;
      if (starts.empty()) starts.push_back(cands[i].spec.term.params);
      for (const std::vector<double>& start : starts) {
        TermSpec spec = cands[i].spec;
        spec.term.params = start;
        int df = 0;
        const double s = ScoreStatistic(td, train, sd, current.log_k, current.terms, spec, &df);
        const double p = df > 0 ? ChiSquareSurvival(s, df) : 1.0;
        if (p < score_p[i] || best_start[i].starts.size() > 1) {
          if (p <= score_p[i]) best_start[i].starts = {start};
          score_p[i] = std::min(score_p[i], p);
        }
      }
    });
    phase("screen");
    std::vector<int> by_score(nc);
    for (int i = 0; i < nc; ++i) by_score[i] = i;
    std::sort(by_score.begin(), by_score.end(),
              [&](int a, int b) { return score_p[a] < score_p[b]; });
    std::vector<int> to_fit;
    for (int i : by_score) {
      if (to_fit.size() >= 6 || score_p[i] * num_tests > 0.5) break;
      to_fit.push_back(i);
    }
    std::vector<Fitted> fits(nc);
    ParallelFor(
        static_cast<int>(to_fit.size()), options.num_threads, [&](int j) {
          fits[to_fit[j]] =
              FitTermCandidate(td, train, sd, current, best_start[to_fit[j]]);
        });
    phase("refit");
    const double n = static_cast<double>(train.size());
    std::vector<CandidateResult> results(nc);
    for (int i = 0; i < nc; ++i) {
      CandidateResult& r = results[i];
      r.covariate = cands[i].spec.term.covariate;
      r.form = TermFormName(cands[i].spec.term.form);
      r.df = cands[i].spec.term.NumParams();
      r.cv_mse_ratio = std::nan("");
      r.p_value = score_p[i];  // score test; replaced by the LR test if refitted
      r.p_adjusted = std::min(1.0, r.p_value * num_tests);
      if (!fits[i].usable) continue;
      r.lr = std::max(0.0, n * std::log(current.rss / fits[i].rss));
      r.p_value = ChiSquareSurvival(r.lr, r.df);
      r.p_adjusted = std::min(1.0, r.p_value * num_tests);
    }
    // Cross-validate the significant ones (strongest first, at most 8).
    std::vector<int> order(nc);
    for (int i = 0; i < nc; ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return results[a].lr > results[b].lr; });
    std::vector<int> to_cv;
    for (int i : order) {
      if (fits[i].usable && results[i].p_adjusted < options.alpha && to_cv.size() < 3) {
        to_cv.push_back(i);
      }
    }
    CvResult cv_base;
    if (!to_cv.empty()) cv_base = CrossValidate(td, fit_sets, held_out, sd, current);
    std::vector<CvResult> cv_cand(to_cv.size());
    ParallelFor(static_cast<int>(to_cv.size()), options.num_threads, [&](int j) {
      cv_cand[j] = CrossValidate(td, fit_sets, held_out, sd, fits[to_cv[j]]);
    });
    phase("cross_validation");
    int winner = -1;
    for (size_t j = 0; j < to_cv.size(); ++j) {
      CandidateResult& r = results[to_cv[j]];
      r.cv_mse_ratio = cv_base.mse > 0 ? cv_cand[j].mse / cv_base.mse : 1.0;
      r.accepted = r.cv_mse_ratio < 1 - options.min_cv_improvement;
      auto penalised = [&](const CandidateResult& c) {
        return c.cv_mse_ratio + options.cv_penalty_per_parameter * c.df;
      };
      if (r.accepted && (winner < 0 || penalised(r) < penalised(results[winner]))) {
        winner = to_cv[j];
      }
    }
    if (round == 0) {
      std::vector<int> by_p = order;
      std::stable_sort(by_p.begin(), by_p.end(), [&](int a, int b) {
        return results[a].p_value < results[b].p_value;
      });
      for (size_t i = 0; i < by_p.size() && i < 15; ++i) report.first_round.push_back(results[by_p[i]]);
    }
    if (winner < 0) break;

    // 5. Adopt the winner.
    Finding f;
    const CandidateResult& wr = results[winner];
    f.lr = wr.lr;
    f.df = wr.df;
    f.p_value = wr.p_value;
    f.p_adjusted = wr.p_adjusted;
    f.cv_mse_ratio = wr.cv_mse_ratio;
    f.cv_gap_before_um = cv_base.gap;
    for (size_t j = 0; j < to_cv.size(); ++j) {
      if (to_cv[j] == winner) f.cv_gap_after_um = cv_cand[j].gap;
    }
    for (size_t j = 0; j < to_cv.size(); ++j) {
      const CandidateResult& r = results[to_cv[j]];
      if (r.accepted && r.covariate != wr.covariate &&
          r.cv_mse_ratio <= wr.cv_mse_ratio + 0.01 &&
          std::find(f.alternatives.begin(), f.alternatives.end(), r.covariate) ==
              f.alternatives.end()) {
        f.alternatives.push_back(r.covariate);
      }
    }
    std::vector<double> se;
    Fitted adopted = Fit(td, train, sd, fits[winner].log_k, fits[winner].terms, true, &se);
    if (!adopted.usable) adopted = fits[winner];
    const TermSpec& spec = adopted.terms.back();
    f.term = spec.term;
    const int offset = static_cast<int>(se.size()) - spec.term.NumParams();
    if (offset >= 0) {
      for (int j = 0; j < spec.term.NumParams(); ++j) {
        f.parameter_std_errors["param" + std::to_string(j)] = se[offset + j];
      }
    }
    diag::NameFinding(td, train, spec, &f);
    f.gap_val_before_um = Gap(td, val, PredictTerms(td, val, current.log_k, current.terms));
    f.gap_val_after_um = Gap(td, val, PredictTerms(td, val, adopted.log_k, adopted.terms));
    report.findings.push_back(f);
    phase("refit");
    used.insert(spec.covariate);
    current = adopted;
  }

  report.verdict = report.findings.empty() ? "no_significant_mismatch" : "missing_physics_found";
  const std::vector<double> after_all = PredictTerms(td, all, current.log_k, current.terms);
  std::vector<double> pt, pv;
  for (int o : train) pt.push_back(after_all[o]);
  for (int o : val) pv.push_back(after_all[o]);
  report.final_gap_train_um = Gap(td, train, pt);
  report.final_gap_val_um = Gap(td, val, pv);
  const StatusOr<KStructure> ks =
      KStructure::ForOption(1, td.positions, td.roll_types, td.grades);
  if (ks.ok()) {
    for (int i = 0; i < ks->num_coefficients(); ++i) {
      report.coefficients.emplace_back(ks->CoefficientName(i), std::exp(current.log_k[i]));
    }
  }
  for (const TermSpec& t : current.terms) report.terms.push_back(t.term);
  if (ks.ok()) {
    WearModel& m = report.adopted_model;
    m.law = options.law;
    m.structure = *ks;
    for (double lk : current.log_k) m.k.push_back(std::exp(lk));
    m.terms = report.terms;
    std::vector<double> e;
    for (size_t i = 0; i < train.size(); ++i) e.push_back(td.obs[train[i]].measured_um - pt[i]);
    FitNoiseModel(pt, e, &m);
  }
  for (int o : all) {
    const TermObservation& ob = td.obs[o];
    DiagnosisPoint p;
    p.campaign_id = data.campaigns[ob.campaign].id;
    p.stand = SlotStand(ob.slot);
    p.position = SlotPosition(ob.slot);
    p.validation = !train_campaigns.count(ob.campaign);
    p.measured_um = ob.measured_um;
    p.before_um = before_all[o];
    p.after_um = after_all[o];
    for (const Finding& f : report.findings) {
      const int k = td.CovariateIndex(f.covariate);
      if (k >= 0) p.covariates[f.covariate] = td.obs_z[k][o];
    }
    report.points.push_back(std::move(p));
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace rollwear
