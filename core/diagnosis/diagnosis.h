// Diagnosis: when predictions and grinder measurements disagree in a
// structured way, find where, name the physics the model leaves out, fit a
// term for it and show on held-out campaigns that the fit improved.
//
// One code path and one default configuration for every dataset; the
// engine is never told which effect (if any) is present. Every fit and test
// uses Huber's robust loss (robust.h; docs/diagnosis.md): a few gross
// grinder errors neither create nor hide findings, and are listed.
//  1. Baseline: calibrate Wang option 1 (calibration.h) on the training
//     campaigns of the seeded 2/3-1/3 split.
//  2. Locate: break the baseline residuals down by roll position, roll type,
//     dominant grade, campaign length, wear amplitude, time, time of day,
//     the physical roll, and against every catalogued covariate aggregated
//     as the model aggregates it (ANOVA F or Pearson t tests), with effect
//     sizes.
//  3. Hypothesise: candidate terms that equal the model when their
//     amplitude is 0, over every covariate of the catalog (covariates.h),
//     each proposed by its term family (core/model/term_family.h, one file
//     per family): wear-rate forms (log-linear, power, quantile bins,
//     saturating, decaying, a knee (hinge), flag, one multiplier per
//     factor level), wear
//     added per coil, offsets of what the grinder reads, and steps on one
//     day of a calendar covariate; the log-linear, flag and per-coil forms
//     also at each single scope (a stand, a position top or bottom, a roll
//     position, a roll type, a grade), the flag also behind a gate (the
//     passes above or below a 5 % quantile of another numeric pass
//     covariate; diagnosis_gates.cc), and a cell of two factors
//     (diagnosis_scoped.cc).
//  4. Test: a score test screens every candidate at the current model; the
//     strongest are refitted jointly with the baseline (term_fit.h),
//     LR = n ln(RSS0/RSS1) ~ chi2(df) with a Bonferroni correction over
//     every test of the round, then cross-validated on the training
//     campaigns; a candidate is accepted only when both agree (p_adj <
//     alpha and the CV error reduced by min_cv_improvement). The accepted
//     ones are tried in order of their cross-validated error (penalised
//     per parameter), and the first to pass every guard of kWinnerGuards
//     (diagnosis_winner.cc) is named: over a quantity the format names, a
//     fit inside its box, no better described by a cell, the proxy chain
//     (kProxyGuards, diagnosis_guard.cc: consistent across pass-level
//     factors, stands, positions, roll types and quartiles, a gate
//     required, inside its cell, scope and siblings, along time and the
//     grade order, the located structure reduced, consistent across the
//     covariates of candidates refused before it, constant inside its
//     gate), distinct from rivals of another
//     mechanism, and not a worse fit than a candidate refused as not
//     nameable, by the proxy chain or as such a shadow. The guards that
//     weigh an alternative description (a cell, a sibling or part of the
//     scope, a slope inside a cell, a rival, another gate) share one
//     encompassing test and one multiplicity policy at
//     thresholds.alternative_alpha (diagnosis_alternatives.h). Each refusal is
//     a runner-up with its RefusalKind and sentence; what a refusal located is
//     kept for the verdict. When every accepted candidate is refused, joint
//     forward selection (diagnosis_joint.cc) judges a refused one again on the
//     model that carries another significant structure of the round, and names
//     it when each of the two passes given the other.
//  5. Repeat on the improved model, up to max_findings findings. After the
//     rounds, findings the final model does not support are withdrawn
//     (cell sets a twin stand predicts alike, a cell two other cells
//     describe as well, a cell or scope no longer confined, a jointly
//     named finding whose partner the final model does not hold;
//     diagnosis_complement.cc, diagnosis_final_scope.cc,
//     diagnosis_joint.cc), and the per-roll family runs on what is left
//     (diagnosis_roll_family.cc).
//  6. Report: the adopted terms with parameters and standard errors, the
//     validation gap before and after each.
//  7. Look again: the final model's residuals located as in step 2 plus
//     the noise checks (diagnosis_noise.cc) and, with profiles.csv, along
//     the barrel (profile_locate.h); what is significant at the
//     family-wise level and of material size is `unexplained`. Verdict:
//     missing_physics_found (a finding), mismatch_located_unexplained (no
//     finding, something unexplained; no physics named) or
//     no_significant_mismatch (no finding, residuals behave like noise).
// docs/diagnosis.md is the reference (its Procedure numbers the steps the
// same way): pipeline, families, guards, thresholds (DiagnosisThresholds),
// verdicts and limits.
//
// Thread-safety: Diagnose is reentrant; it uses up to options.num_threads
// worker threads internally.
#ifndef ROLLWEAR_CORE_DIAGNOSIS_DIAGNOSIS_H_
#define ROLLWEAR_CORE_DIAGNOSIS_DIAGNOSIS_H_

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/dataset/dataset.h"
#include "core/diagnosis/diagnosis_thresholds.h"
#include "core/fit/robust.h"
#include "core/model/metrics.h"
#include "core/model/model_terms.h"
#include "core/model/wear_law.h"
#include "core/model/wear_model.h"

namespace rollwear {

struct DiagnosisOptions {
  WearLaw law = WearLaw::kWang;
  uint64_t split_seed = 1;
  // A split file's split (core/model/given_split.h); replaces the seeded one.
  std::optional<CampaignSplit> given_split;
  int cv_folds = 5;
  // Family-wise level per round; at most thresholds.alternative_alpha.
  double alpha = 0.001;
  double min_cv_improvement = 0.03;  // relative CV weighted-MSE reduction
  // Parsimony: a candidate must beat one with fewer parameters by this much
  // CV-error ratio per extra parameter to be preferred.
  double cv_penalty_per_parameter = 0.005;
  int max_findings = 3;
  int num_bins = 4;  // quantile bins of the binned form
  int max_factor_levels = 12;
  int num_threads = 2;
  // Huber's robust loss everywhere (robust.h; docs/diagnosis.md). false:
  // least squares, for comparison only.
  bool robust = true;
  // The guards' levels, material sizes, minimum counts and grids
  // (diagnosis_thresholds.h; docs/diagnosis.md, "Thresholds").
  DiagnosisThresholds thresholds;

  bool IsValid(std::string* error) const;
};

// One dimension of the residual breakdown.
struct Breakdown {
  std::string dimension;  // "roll_position", "wear_amplitude", a covariate...
  std::string test;       // "anova" or "pearson"
  double statistic = 0;   // F or t
  double p_value = 1;
  double effect_size =
      0;  // largest |mean relative residual| of a group, or |r|
  struct Group {
    std::string label;
    int n = 0;
    double mean_residual_um = 0;  // measured - predicted
    double mean_relative = 0;     // mean of (measured - predicted) / predicted
    // ANOVA only: the group mean over its standard error from the pooled
    // within-group sd, mean / (s_w / sqrt(n)) ~ t(N - k) under "mean 0".
    double t = 0;
  };
  std::vector<Group> groups;
};

struct CandidateResult {
  std::string covariate;
  std::string form;
  int df = 0;
  double lr = 0;
  double p_value = 1;
  double p_adjusted = 1;
  double cv_mse_ratio = 1;  // CV weighted MSE with / without; NaN if not run
  bool accepted = false;
};

struct Finding {
  std::string covariate;
  std::string level;  // "pass", "roll", "campaign", "measurement"
  std::string
      mechanism;      // physical name, e.g. "wear_rate_growth_along_campaign"
  std::string shape;  // "increasing", "decreasing", "saturating_growth",
                      // "decaying", "on_off", "per_level", "peaked"...
  std::string form;   // TermFormName
  std::string explanation;
  std::map<std::string, double> parameters;
  std::map<std::string, double> parameter_std_errors;
  double lr = 0;
  int df = 0;
  double p_value = 1;
  double p_adjusted = 1;
  double cv_gap_before_um = 0, cv_gap_after_um = 0;
  double cv_mse_ratio = 1;
  double gap_val_before_um = 0, gap_val_after_um = 0;
  std::vector<std::string> alternatives;  // covariates that fit almost as well
  // When the data cannot tell the covariate from others that carry the
  // same mechanism (diagnosis_carriers.cc: the campaign's rolled length,
  // coils and hours; force and specific force; entry and exit thickness):
  // all of them, the fitted term's covariate first, and `mechanism` is the
  // carried one. Empty otherwise.
  std::vector<std::string> carriers;
  // Where the finding applies ({"stand":"F7","position":"top"}; empty =
  // everywhere) and the affected levels of a factor ("B" of a grinder
  // column, "HSLA" of grade), as the contract's findings[].scope / levels.
  std::map<std::string, std::string> scope;
  std::vector<std::string> levels;
  // The other levels of a one-level scope's factor for which the data
  // cannot tell whether the finding holds there too ("API-X65"; the
  // contract's findings[].scope_undetermined, docs/diagnosis.md).
  std::vector<std::string> scope_undetermined;
  ModelTerm term;  // the adopted term
};

// Which check kept a significant candidate from being adopted, or withdrew
// a finding after its round (docs/diagnosis.md, "The proxy guard"): the
// typed part of RunnerUp::reason, for clients that sort refusals without
// reading sentences (JSON runners_up[].refusal, RefusalKindName).
enum class RefusalKind {
  kNotNameable,          // over a quantity the format does not name
  kAtBoxBound,           // its fit stops at a bracket of its box
  kNoBetterThanCell,     // a cell of the round describes the data as well
  kProxyGuard,           // one of the proxy guard's rows (RunnerUp::guard)
  kNotDistinguishable,   // a rival of another mechanism fits as well
  kShadowOfRefused,      // fits worse than a candidate the guard refused
  kTwinStands,           // withdrawn: the twin stand's levels predict alike
  kCellPair,             // withdrawn: two other cells describe it as well
  kRollFamily,           // the per-roll family's own checks
  kJointPartnerMissing,  // withdrawn: named jointly with a structure the
                         // final model does not hold
  kUnspecified,          // not set (a bug: every refusal sets its kind)
};
// "not_nameable", "at_box_bound", "no_better_than_cell", "proxy_guard",
// "not_distinguishable", "shadow_of_refused", "twin_stands", "cell_pair",
// "roll_family", "joint_partner_missing", "unspecified".
const char* RefusalKindName(RefusalKind kind);

// A significant candidate of a round that was not adopted, with why
// (the proxy guard of docs/diagnosis.md): "inconsistent across stand",
// "located structure remains (roll_position)", ...
struct RunnerUp {
  int round = 0;
  std::string covariate;
  std::string form;
  double p_adjusted = 1;
  double cv_mse_ratio = 1;
  std::string reason;
  RefusalKind refusal = RefusalKind::kUnspecified;
  // For kProxyGuard: the row of kProxyGuards that refused
  // ("group_consistency", "look_again", ...); "" otherwise.
  std::string guard;
};

// Structure of the final model's residuals that is significant at the
// family-wise level (Bonferroni over every dimension tested) and of
// material size, and that no adopted term explains.
struct Unexplained {
  std::string
      dimension;  // "roll_position", "time_scale_8", "runs_along_time"...
  std::string
      where;  // "roll_position=F7/bottom", "calendar time, block 3 of 4"...
  std::string test;  // "anova", "pearson", "lag1_autocorrelation", "runs",
                     // "brown_forsythe"
  double statistic = 0;
  double mean_residual_um = 0;  // mean measured - predicted where it lives
  double p_value = 1;           // unadjusted
  double p_adjusted = 1;        // Bonferroni over the dimensions tested
};

// Per validation observation, for plots.
struct DiagnosisPoint {
  std::string campaign_id;
  int stand = 0;
  Position position = Position::kTop;
  bool validation = false;
  double measured_um = 0;
  double before_um = 0;  // baseline prediction
  double after_um = 0;   // prediction with the adopted terms
  std::map<std::string, double> covariates;  // of the findings, aggregated
};

struct DiagnosisReport {
  std::string law;
  int n_train = 0, n_val = 0;
  double baseline_gap_train_um = 0, baseline_gap_val_um = 0;
  // The baseline's grade factors, in one sentence: "grades fitted freely",
  // or shrunk (calibration.h) because the free fit is not identified.
  std::string baseline_grades;
  double final_gap_train_um = 0, final_gap_val_um = 0;
  std::vector<Breakdown> locate;  // strongest evidence first
  std::vector<Finding> findings;  // order of adoption = strongest first
  std::vector<CandidateResult> first_round;  // by p-value, top 15
  // Significant candidates the proxy guard did not adopt, round by round.
  std::vector<RunnerUp> runners_up;
  // Residual structure of the final model left unexplained (strongest
  // first); the noise checks of diagnosis_noise.cc included.
  std::vector<Unexplained> unexplained;
  // "missing_physics_found" (a finding adopted; `unexplained` may still
  // list structure), "mismatch_located_unexplained" (no finding, but
  // `unexplained` is not empty: no physics is named) or
  // "no_significant_mismatch" (no finding and the residuals behave like
  // measurement noise).
  std::string verdict;
  std::vector<DiagnosisPoint> points;
  // The adopted model: option-1 coefficients (names and values) and terms.
  std::vector<std::pair<std::string, double>> coefficients;
  std::vector<ModelTerm> terms;
  // The same as a servable model version (option 1 + terms, noise model
  // fitted on the training residuals): what calibrate, the daemon and the
  // reports use once the finding is adopted.
  WearModel adopted_model;
  // Readings (training and validation) whose residual under the final
  // model exceeds kOutlierSigmas sd's of its robust noise model (robust.h),
  // largest first: suspected gross grinder errors, kept at Huber weight.
  std::vector<SuspectedOutlier> suspected_outliers;
  double seconds = 0;
  // Wall seconds per phase ("baseline", "data", "locate", "screen",
  // "refit", "cross_validation", "guard"), summed over rounds.
  std::map<std::string, double> phase_seconds;
};

StatusOr<DiagnosisReport> Diagnose(const Dataset& data,
                                   const DiagnosisOptions& options);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_DIAGNOSIS_DIAGNOSIS_H_
