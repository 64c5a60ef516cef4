// The summary of a diagnosis (step 7 and the report's closing figures,
// see diagnosis_stages_internal.h): the final model's gaps, coefficients
// and served noise, its suspected outliers, what remains located, the
// verdict, and one point per reading.
// Thread-safety: reentrant (writes only the report it is given).
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/diagnosis/diagnosis.h"
#include "core/diagnosis/diagnosis_stages_internal.h"
#include "core/fit/robust.h"
#include "core/model/k_structure.h"

namespace rollwear::diag {
namespace {

// One DiagnosisPoint per observation of `all`, with the final prediction.
void AddPoints(const Dataset& data, const DiagnosisState& st,
               const std::vector<double>& after_all, DiagnosisReport* report) {
  const TermData& td = st.td;
  for (int o : st.all) {
    const TermObservation& ob = td.obs[o];
    DiagnosisPoint p;
    p.campaign_id = data.campaigns[ob.campaign].id;
    p.stand = SlotStand(ob.slot);
    p.position = SlotPosition(ob.slot);
    p.validation = !st.train_campaigns.count(ob.campaign);
    p.measured_um = ob.measured_um;
    p.before_um = st.before_all[o];
    p.after_um = after_all[o];
    for (const Finding& f : report->findings) {
      const int k = td.CovariateIndex(f.covariate);
      if (k >= 0) p.covariates[f.covariate] = td.obs_z[k][o];
    }
    report->points.push_back(std::move(p));
  }
}

// The readings of `all` more than kOutlierSigmas sd's of `noise` off the
// final prediction, largest first.
void ListOutliers(const Dataset& data, const DiagnosisState& st,
                  const std::vector<double>& after_all,
                  const RobustNoise& noise, DiagnosisReport* report) {
  for (int o : st.all) {
    const TermObservation& ob = st.td.obs[o];
    const double u = (ob.measured_um - after_all[o]) / noise.SdAt(after_all[o]);
    if (!(std::abs(u) > kOutlierSigmas)) continue;
    SuspectedOutlier out;
    out.campaign = ob.campaign;
    out.slot = ob.slot;
    out.training = st.train_campaigns.count(ob.campaign) > 0;
    out.measured_um = ob.measured_um;
    out.predicted_um = after_all[o];
    out.standardized_residual = u;
    report->suspected_outliers.push_back(out);
  }
  NameOutliers(data, &report->suspected_outliers);
}

// Step 7 (look again). The final model's residual breakdowns (Locate) and noise
// checks (NoiseChecks), clipped to +-kHuberK sd's of `noise`: what remains
// significant at the family-wise level and of material size.
std::vector<Unexplained> LocateUnexplained(const Dataset& data,
                                           const DiagnosisOptions& options,
                                           const DiagnosisState& st,
                                           const std::vector<double>& after_all,
                                           const RobustNoise& noise) {
  std::vector<double> pred, sd;
  for (int o : st.all) {
    pred.push_back(after_all[o]);
    sd.push_back(noise.SdAt(after_all[o]));
  }
  std::vector<Breakdown> checks =
      Locate(st.td, data, st.all, pred, options.thresholds, &sd);
  for (Breakdown& b :
       NoiseChecks(st.td, data, st.all, pred, sd, options.thresholds)) {
    checks.push_back(std::move(b));
  }
  return UnexplainedStructure(checks, options.alpha,
                              MaterialResidualUm(sd, options.thresholds),
                              options.thresholds);
}

}  // namespace

void Summarise(const Dataset& data, const DiagnosisOptions& options,
               const DiagnosisState& st, DiagnosisReport* report) {
  const TermData& td = st.td;
  const Fitted& current = st.current;
  const std::vector<double> after_all =
      PredictTerms(td, st.all, current.log_k, current.terms);
  std::vector<double> pt, pv;
  for (int o : st.train) pt.push_back(after_all[o]);
  for (int o : st.val) pv.push_back(after_all[o]);
  report->final_gap_train_um = Gap(td, st.train, pt);
  report->final_gap_val_um = Gap(td, st.val, pv);
  if (report->findings.empty()) {
    // Nothing adopted: the final model is the baseline. (The robust term
    // refit and the robust calibration stop after the same two reweighting
    // steps from different starts, so their gaps may differ by a fraction
    // of a micron; the report must not show a change it did not make.)
    report->final_gap_train_um = report->baseline_gap_train_um;
    report->final_gap_val_um = report->baseline_gap_val_um;
  }
  const StatusOr<KStructure> ks =
      KStructure::ForOption(1, td.positions, td.roll_types, td.grades);
  if (ks.ok()) {
    for (int i = 0; i < ks->num_coefficients(); ++i) {
      report->coefficients.emplace_back(ks->CoefficientName(i),
                                        std::exp(current.log_k[i]));
    }
  }
  for (const TermSpec& t : current.terms) report->terms.push_back(t.term);
  if (ks.ok()) {
    WearModel& m = report->adopted_model;
    m.law = options.law;
    m.structure = *ks;
    for (double lk : current.log_k) m.k.push_back(std::exp(lk));
    m.terms = report->terms;
    std::vector<double> e;
    for (size_t i = 0; i < st.train.size(); ++i) {
      e.push_back(td.obs[st.train[i]].measured_um - pt[i]);
    }
    const RobustNoise noise = FitRobustNoise(pt, e);
    // Served widened to cover the training tails, as calibrate's (robust.h);
    // outliers and the locate below judge against the robust noise itself.
    const double c = TailCoverageScale(noise.u);
    m.noise_sd_um = c * noise.noise_sd_um;
    m.noise_rel = c * noise.noise_rel;
    ListOutliers(data, st, after_all, noise, report);
    // Appended to what the proxy guard located in the last round.
    for (Unexplained& u :
         LocateUnexplained(data, options, st, after_all, noise)) {
      report->unexplained.push_back(std::move(u));
    }
    std::stable_sort(report->unexplained.begin(), report->unexplained.end(),
                     [](const Unexplained& a, const Unexplained& b) {
                       return a.p_value < b.p_value;
                     });
    // The lag-1 structure describes the whole series: the strongest entry
    // only (the guard's, naming the time term that failed to take it away,
    // and the final model's look again can both list it).
    bool lag1_seen = false;
    std::erase_if(report->unexplained, [&](const Unexplained& u) {
      if (u.dimension != "lag1_along_time") return false;
      const bool drop = lag1_seen;
      lag1_seen = true;
      return drop;
    });
  }
  report->verdict = !report->findings.empty() ? "missing_physics_found"
                    : !report->unexplained.empty()
                        ? "mismatch_located_unexplained"
                        : "no_significant_mismatch";
  AddPoints(data, st, after_all, report);
}

}  // namespace rollwear::diag
