// The diagnosis engine; see diagnosis.h for the procedure. Diagnose() runs
// the stages of diagnosis_stages_internal.h in order.
#include "core/diagnosis/diagnosis.h"

#include <algorithm>
#include <chrono>
#include <set>
#include <string>
#include <vector>

#include "core/diagnosis/diagnosis_internal.h"
#include "core/diagnosis/diagnosis_stages_internal.h"
#include "core/diagnosis/profile_locate.h"

namespace rollwear {

const char* RefusalKindName(RefusalKind kind) {
  switch (kind) {
    case RefusalKind::kNotNameable:
      return "not_nameable";
    case RefusalKind::kAtBoxBound:
      return "at_box_bound";
    case RefusalKind::kNoBetterThanCell:
      return "no_better_than_cell";
    case RefusalKind::kProxyGuard:
      return "proxy_guard";
    case RefusalKind::kNotDistinguishable:
      return "not_distinguishable";
    case RefusalKind::kShadowOfRefused:
      return "shadow_of_refused";
    case RefusalKind::kTwinStands:
      return "twin_stands";
    case RefusalKind::kCellPair:
      return "cell_pair";
    case RefusalKind::kRollFamily:
      return "roll_family";
    case RefusalKind::kJointPartnerMissing:
      return "joint_partner_missing";
    case RefusalKind::kUnspecified:
      return "unspecified";
  }
  return "unspecified";
}

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
  // A guard's question about an alternative is never stricter than the
  // round (diagnosis_alternatives.h).
  if (!(thresholds.alternative_alpha >= alpha)) {
    return fail("thresholds.alternative_alpha must be >= alpha");
  }
  return thresholds.IsValid(error);
}

StatusOr<DiagnosisReport> Diagnose(const Dataset& data,
                                   const DiagnosisOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  std::string error;
  if (!options.IsValid(&error)) return Status::InvalidArgument("diagnosis options: " + error);
  DiagnosisReport report;
  report.law = WearLawName(options.law);
  diag::PhaseClock phase(&report);

  // 1. Baseline.
  ROLLWEAR_ASSIGN_OR_RETURN(const diag::Baseline base,
                            diag::RunBaseline(data, options, &report));
  phase.Mark("baseline");
  ROLLWEAR_ASSIGN_OR_RETURN(diag::DiagnosisState state,
                            diag::BuildState(data, options, base, &report));
  phase.Mark("data");

  // 2. Locate.
  report.locate = diag::Locate(state.td, data, state.all, state.before_all,
                               options.thresholds,
                               options.robust ? &state.locate_sd : nullptr);
  phase.Mark("locate");

  // 3-5. Hypothesise, test and repeat: round after round.
  diag::MakeFolds(options, base.split, &state);
  std::set<int> used;
  for (int round = 0; round < options.max_findings; ++round) {
    if (!diag::RunRound(round, data, options, &used, &phase, &state, &report)) break;
  }
  std::vector<int> rounds =
      diag::WithdrawTiedCellSets(options, &state, &report);
  diag::WithdrawUnconfinedScopes(options, &state, &report, &rounds);
  diag::WithdrawUnpairedJoint(options, &state, &report, &rounds);
  // The per-roll family on what the rounds leave (diagnosis_roll_family.cc).
  if (diag::RunRollFamily(options, &state, &report)) phase.Mark("roll_family");

  diag::Summarise(data, options, state, &report);
  // Along the barrel, when the grinder measured profiles: what the final
  // model's profiles leave at the edges or on one side is located, never
  // named (profile_locate.h).
  if (!data.profile_points.empty() && !report.adopted_model.k.empty()) {
    StatusOr<BarrelLocate> barrel =
        LocateAlongBarrel(report.adopted_model, data, DatasetIndex(data),
                          base.split, options.alpha, options.thresholds);
    if (barrel.ok()) {
      const double tests = static_cast<double>(barrel->contrasts.size());
      for (const BarrelContrast& c : barrel->contrasts) {
        if (!c.significant) continue;
        report.unexplained.push_back(
            {c.dimension, c.where, "paired_t_across_rolls", c.t, c.mean_um,
             c.p_value, std::min(1.0, c.p_value * tests)});
      }
      std::stable_sort(report.unexplained.begin(), report.unexplained.end(),
                       [](const Unexplained& a, const Unexplained& b) {
                         return a.p_value < b.p_value;
                       });
      if (report.findings.empty() && !report.unexplained.empty()) {
        report.verdict = "mismatch_located_unexplained";
      }
    }
    phase.Mark("barrel");
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace rollwear
