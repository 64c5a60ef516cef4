// Internal to core/diagnosis: the stages of Diagnose() (diagnosis.h), in
// the order diagnosis.cc runs them: the baseline calibration, the term data
// and observation sets, the cross-validation folds, the rounds of
// hypothesise-test-adopt (screen, refit, likelihood-ratio test,
// cross-validation, winner, adoption) and the summary of the final model.
// Include only from core/diagnosis/diagnosis*.cc.
//
// Thread-safety: a DiagnosisState and a PhaseClock belong to one Diagnose()
// call and one thread; the stage functions share no state between calls
// (ParallelFor inside a stage writes only per-index slots).
#ifndef ROLLWEAR_CORE_DIAGNOSIS_DIAGNOSIS_STAGES_INTERNAL_H_
#define ROLLWEAR_CORE_DIAGNOSIS_DIAGNOSIS_STAGES_INTERNAL_H_

#include <chrono>
#include <set>
#include <string>
#include <unordered_set>
#include <vector>

#include "core/base/status.h"
#include "core/diagnosis/diagnosis.h"
#include "core/diagnosis/diagnosis_internal.h"
#include "core/fit/study.h"
#include "core/fit/term_fit.h"

namespace rollwear::diag {

// Adds the wall time since the last Mark (or construction) to
// report->phase_seconds[name].
class PhaseClock {
 public:
  explicit PhaseClock(DiagnosisReport* report)
      : report_(report), mark_(std::chrono::steady_clock::now()) {}
  void Mark(const char* name) {
    const auto now = std::chrono::steady_clock::now();
    report_->phase_seconds[name] +=
        std::chrono::duration<double>(now - mark_).count();
    mark_ = now;
  }

 private:
  DiagnosisReport* report_;
  std::chrono::steady_clock::time_point mark_;
};

// A fit of option-1 log coefficients plus terms (usable = false when the
// fit failed).
struct Fitted {
  std::vector<double> log_k;
  std::vector<TermSpec> terms;
  double rss = 0;
  bool usable = false;
};

// Stage 1's result: the campaign split and the baseline calibration on it.
struct Baseline {
  CampaignSplit split;
  SplitCalibration calibration;
};

// What the stages share: the term data, the observation sets (indices into
// td.obs), the cross-validation folds over the training observations, the
// baseline predictions and the current model.
struct DiagnosisState {
  TermData td;
  std::unordered_set<int> train_campaigns;
  std::vector<int> train, val, all;
  std::vector<std::vector<int>> fit_sets, held_out;  // per fold
  std::vector<double> before_all;  // baseline prediction of `all`
  // Robust noise sd of the baseline at each of `all` (robust.h): Locate
  // clips residuals to +-kHuberK of it.
  std::vector<double> locate_sd;
  Fitted current;
  // UnscopedCandidates on `train`, built in the first round (the same for
  // every round: `train` does not change).
  std::vector<std::vector<Candidate>> unscoped;
  // options.thresholds (diagnosis_thresholds.h), for the stages that are
  // given the state but not the options.
  DiagnosisThresholds thresholds;
  // The findings joint forward selection named (JointWinner): the round
  // that adopted it, the structure it was judged with, and its refusal
  // alone (reason and place), for WithdrawUnpairedJoint.
  struct JointPair {
    int round = 0;  // the finding's adoption round
    std::string partner, reason;
    ModelTerm partner_term;  // a cell partner is known by its place
    Unexplained place;
  };
  std::vector<JointPair> joint;
};

// Stage 1 (diagnosis_baseline.cc). Aggregates, splits the campaigns 2:1 and
// calibrates option 1 on the training part, its grade factors free where
// the data identify them and shrunk (core/fit/calibration.h) where not;
// fills the baseline gaps and baseline_grades of `report`.
StatusOr<Baseline> RunBaseline(const Dataset& data,
                               const DiagnosisOptions& options,
                               DiagnosisReport* report);

// The term data, the train/validation/all observation sets and the current
// model (the baseline's coefficients, no terms) with its predictions; fills
// n_train and n_val of `report`.
StatusOr<DiagnosisState> BuildState(const Dataset& data,
                                    const DiagnosisOptions& options,
                                    const Baseline& base,
                                    DiagnosisReport* report);

// Assigns the training campaigns (shuffled by the split seed) to
// options.cv_folds folds and fills state->fit_sets and state->held_out.
void MakeFolds(const DiagnosisOptions& options, const CampaignSplit& split,
               DiagnosisState* state);

// Steps 3-4, one round (step 5 repeats it): refits the current model, screens
// and tests every candidate over covariates not in `used`, cross-validates the
// significant ones and adopts the winner (into state->current, report->findings
// and `used`). Round 0 also fills report->first_round. Returns false when the
// round adopted nothing, which ends the search.
bool RunRound(int round, const Dataset& data, const DiagnosisOptions& options,
              std::set<int>* used, PhaseClock* phase, DiagnosisState* state,
              DiagnosisReport* report);

// After the rounds: withdraws each set of adopted stand cells of one factor
// whose complementary description (ComplementCells) has no more cells: its
// findings become runners-up, its terms leave state->current (refitted),
// and the mismatch is listed as located with both descriptions
// (diagnosis_complement.cc). Then withdraws, one at a time, each adopted
// cell that other cells of its kind join significantly in the final model
// (the strongest alone, Bonferroni over the siblings, or all at once; 1 %
// over the two tests), or that a pair of them describes about as well
// (LR within 5), located with them. Returns the round each remaining
// finding was adopted in (aligned with report->findings).
std::vector<int> WithdrawTiedCellSets(const DiagnosisOptions& options,
                                      DiagnosisState* state,
                                      DiagnosisReport* report);

// Withdraws finding i after the rounds (diagnosis_complement.cc): a
// runner-up of its adoption round with `reason`, `kind` and `guard`, its
// place `located` listed as unexplained, the model replaced by `refit`
// (without its term); `rounds` (aligned with report->findings) loses it
// too.
void WithdrawFinding(size_t i, const std::string& reason, RefusalKind kind,
                     const std::string& guard, const Unexplained& located,
                     const Fitted& refit, DiagnosisState* state,
                     DiagnosisReport* report, std::vector<int>* rounds);

// The siblings guard (LookAtSiblings) again on the final model, for each
// scoped finding but the cells: one whose siblings join it significantly
// once the later rounds' effects are in the model is withdrawn (a
// runner-up, refusal proxy_guard, guard "siblings"), its term leaves
// state->current (refitted) and the siblings' place is listed as located
// (diagnosis_final_scope.cc). `rounds`: the round each finding was adopted
// in (WithdrawTiedCellSets), erased along with them.
void WithdrawUnconfinedScopes(const DiagnosisOptions& options,
                              DiagnosisState* state, DiagnosisReport* report,
                              std::vector<int>* rounds);

// Fits `terms` (their params are the start) with the baseline coefficients
// `log_k` on `subset` (term_fit.h FitTerms); unusable when the fit fails.
// With `errors`, the terms' standard errors go to *term_se.
Fitted Fit(const TermData& td, const std::vector<int>& subset,
           const std::vector<double>& sd, const std::vector<double>& log_k,
           std::vector<TermSpec> terms, bool errors = false,
           std::vector<double>* term_se = nullptr);

// The model (`log_k`, `terms`) refitted on the training readings with its
// own noise model (TermNoiseSd at those values, options.robust); the sd
// goes to *sd when not null, for the tests that compare with it.
Fitted FitWithOwnNoise(const DiagnosisState& st,
                       const DiagnosisOptions& options,
                       const std::vector<double>& log_k,
                       const std::vector<TermSpec>& terms,
                       std::vector<double>* sd = nullptr);

// Mean |measured - pred| over `obs` (pred aligned with obs).
double Gap(const TermData& td, const std::vector<int>& obs,
           const std::vector<double>& pred);

// A model's K-fold cross-validation error on the training campaigns:
// weighted MSE (residual / sd) and mean |residual| in µm.
struct CvResult {
  double mse = 0, gap = 0;
};

// K-fold cross-validation on training campaigns of each model of `models`
// (refitted on each fold; the model itself where a fold's fit fails). The
// models x folds fits run in parallel; each result is summed in fold and
// observation order, so it does not depend on the threads.
std::vector<CvResult> CrossValidate(const DiagnosisState& st,
                                    const std::vector<double>& sd,
                                    const std::vector<const Fitted*>& models,
                                    int num_threads);

// After the rounds, the per-roll family (diagnosis_roll_family.cc): when
// the current model's training readings, roll by roll, scatter more than
// their noise allows (Cochran's Q over the rolls' own multipliers, level
// options.alpha), a roll-effect term (model_terms.h) with the between-roll
// spread tau estimated from that scatter (DerSimonian & Laird 1986) is
// fitted; it is adopted only when it lowers the cross-validated error by
// options.min_cv_improvement beside the current model and beside each
// calendar rival (a drift by campaign start, a roll's service), which a
// roll scatter could otherwise stand for. Adopts into state->current and
// report->findings; returns whether it did; a refusal with heterogeneity
// goes to report->runners_up with why.
bool RunRollFamily(const DiagnosisOptions& options, DiagnosisState* st,
                   DiagnosisReport* report);

// The per-roll term (diagnosis_roll_family.cc) for the rolls' scatter under
// `model` with the noise sd `sd` (not refitted): its spread tau by
// DerSimonian & Laird from Cochran's Q over the rolls with at least
// thresholds.min_readings_per_roll training readings, as RunRollFamily
// estimates it, but without its significance and held-out tests (the look
// again beside the rolls, diagnosis_look_again.h, uses it as the rival
// "the rolls' own scatter"). False when the data hold no roll_id, fewer
// than 3 such rolls, or no scatter beyond the noise (tau 0).
bool RollScatterTerm(const DiagnosisState& st, const DiagnosisOptions& options,
                     const std::vector<double>& sd, const Fitted& model,
                     TermSpec* term);

// The proxy guard's answer on a round's winner (diagnosis_guard.cc).
struct GuardResult {
  bool pass = true;
  std::string reason;   // why not, e.g. "inconsistent across stand"
  Unexplained located;  // for an inconsistent effect: where it lives
  // The proxy guard that refused (kProxyGuards, diagnosis_guard.cc), e.g.
  // "group_consistency"; "" when passed or refused elsewhere.
  std::string guard;
};

// Whether fitted candidate i is gated while a gated copy of the same term
// is among `chosen`, and appends to `chosen` the significant (p adjusted <
// alpha) ungated twin of each gated candidate in it (diagnosis_gates.cc):
// the round cross-validates one gate per term, with its twin.
bool GatedCopyIn(const std::vector<Fitted>& fits, int i,
                 const std::vector<int>& chosen);
// The usable fit whose term is gated fit `gated`'s ungated twin (the same
// covariate, form and place, no gate), or -1 (none, or `gated` is not
// gated).
int UngatedTwinOf(const std::vector<Fitted>& fits, int gated);
void AddFittedTwins(const std::vector<Fitted>& fits,
                    const std::vector<CandidateResult>& results, double alpha,
                    std::vector<int>* chosen);

// The proxy guard's look at a gated last term of `with_term`
// (diagnosis_gates.cc): refused when the gate is not required, i.e. the
// gated term adds nothing significant to its ungated twin; passes any
// other term.
GuardResult GateRequired(const DiagnosisState& st,
                         const DiagnosisOptions& options,
                         const std::vector<double>& sd,
                         const Fitted& with_term);

// The proxy guard (diagnosis_guard.cc): the chain kProxyGuards run in
// order on the last term of `with_term`, the first refusal returned with its
// guard's name (docs/diagnosis.md lists the twelve): is its effect consistent
// across pass-level factors, stands, positions, roll types and covariate
// quartiles (Wald, Cochran's Q), its gate required, inside its cell, scope
// and siblings, along time and the grade order, is the strongest breakdown
// of `located_before` (Locate of the training residuals before the term,
// clipped at the round's `sd`) materially reduced by it, is it consistent
// across the pass-level covariates of `refused` (the round's candidates the
// guards refused before it), and constant inside its gate?
// `num_tests`: the round's Bonferroni count, the level a candidate must
// clear again where it is judged beside the rolls' own scatter.
GuardResult GuardAgainstProxy(const Dataset& data, const DiagnosisState& st,
                              const DiagnosisOptions& options,
                              const std::vector<double>& sd,
                              const std::vector<Breakdown>& located_before,
                              const Fitted& with_term, double num_tests,
                              const std::vector<std::string>& refused = {});

// The guard's consistency test across the levels of one pass-level factor
// (grade, lubrication, a text column of coils.csv; diagnosis_split.cc):
// the Wald statistic of equal scales b_l of the term's contribution on each
// level's passes, its p, the largest |b_l - b_bar|, and the level with the
// largest |b_l| (where the effect lives) with its scale and the rms of the
// effect on its readings (signed by its mean, µm).
struct SplitHeterogeneity {
  std::string factor;
  int levels = 0;
  double wald = 0, p = 1, max_dev = 0;
  std::string level;
  double scale = 0, level_size_um = 0;
  // A split by the quartiles of a numeric covariate of a term that is not
  // one multiplier on a set of passes: the guard weighs it after the
  // stands, positions and roll types, which it may stand in for (contact
  // length differs between stands).
  bool deferred = false;
  // The halves of a gated term's passes inside its gate (by the gate
  // covariate): tested on its own (ConstantInsideGate), not among the
  // dimensions of the consistency guards.
  bool inside_gate = false;
};
// One entry per pass-level factor the last term of `with_term` is not
// about and whose levels can be told apart (>= 2 levels with enough of the
// term's contribution); `e` the training readings' residuals without the
// term, `w` their weights 1/sd^2 and `phi` the adopted model's weighted
// mean square (all aligned with state.train).
std::vector<SplitHeterogeneity> SplitByPassFactors(const DiagnosisState& st,
                                                   const Fitted& with_term,
                                                   const std::vector<double>& e,
                                                   const std::vector<double>& w,
                                                   double phi);
// The proxy guard's look inside a cell (diagnosis_inside_cell.cc): fails
// when the last term of `with_term` is a cell whose effect, on its place or
// its twin's, varies with a numeric wear-rate covariate (of the pass, roll
// or campaign): a log-linear term there, added on top, is significant over
// places x covariates (1 %) and still adds (1 %) given each other offered
// cell the model does not hold; the place is then located along that
// covariate.
GuardResult LookInsideCell(const DiagnosisState& st,
                           const DiagnosisOptions& options,
                           const std::vector<double>& sd,
                           const Fitted& with_term);
// The proxy guard's look within a single-factor scope
// (diagnosis_siblings.cc): fails when the last term of `with_term`, scoped
// to a roll type or grade (a stand), added again on one of the stands it
// runs at (one of the stand's roll types or grades), is significant there:
// the effect is not uniform inside the scope, so a place of two factors,
// which no covariate term can be scoped to, holds it. Also fails when the
// scope has two parts that split its readings and the effect on one of
// them is not required (PartNotRequired): then located with p_adjusted NaN,
// for the caller to fill in with the candidate's.
GuardResult LookWithinScope(const DiagnosisState& st,
                            const DiagnosisOptions& options,
                            const std::vector<double>& sd,
                            const Fitted& with_term);
// `base`'s terms plus `extra`, fitted from base's coefficients on the
// training readings (diagnosis_siblings.cc).
Fitted FitWith(const DiagnosisState& st, const std::vector<double>& sd,
               const Fitted& base, const TermSpec& extra);
// The training readings' mean residual inside `scope` under `fitted`
// (diagnosis_siblings.cc).
double MeanResidualIn(const DiagnosisState& st, const Fitted& fitted,
                      const TermScope& scope);
// The nested likelihood-ratio statistic of model b extending model a,
// LR = n ln(RSS_a / RSS_b) ~ chi2(extra params) (Wilks 1938, Ann. Math.
// Stat. 9:60), floored at 0 (diagnosis_alternatives.cc, the encompassing
// test's statistic).
double NestedLr(double n, double rss_a, double rss_b);
// The proxy guard's look at the siblings of a single-factor scope
// (diagnosis_siblings.cc): fails when the last term of `with_term`, added
// again at another level of its scope's factor, is significant there too.
GuardResult LookAtSiblings(const DiagnosisState& st,
                           const DiagnosisOptions& options,
                           const std::vector<double>& sd,
                           const Fitted& with_term);

// The levels of the scope's factor (labelled as in a breakdown: "API-X65",
// "F6", "F7/top") for which the data cannot tell whether the last term of
// `with_term` holds there too, into f->scope_undetermined, with a sentence
// for f->explanation: the guard found the term not significant there
// (LookAtSiblings), and a copy there tied to its own parameters is not
// rejected against a free copy at 1 % (diagnosis_siblings.cc). None for
// unscoped and cell terms.
void NoteUndeterminedSiblings(const DiagnosisState& st,
                              const std::vector<double>& sd,
                              const Fitted& with_term, Finding* f);

// The size of what a model adds to another: the rms of the difference of
// their training predictions over the readings inside any of `scopes` (an
// empty scope holds every reading); 0 when none is inside
// (diagnosis_rivals.cc).
double ContributionRmsUm(const DiagnosisState& st, const Fitted& with,
                         const Fitted& without,
                         const std::vector<TermScope>& scopes);

// A candidate over a locate-only covariate (CovariateSpec::locate_only:
// roll_campaigns_before, after_stop): always fails, with where it lives and its
// LR as `located` (diagnosis_rivals.cc). Passes every other candidate.
GuardResult NotNameable(const DiagnosisState& st,
                        const std::vector<Fitted>& fits,
                        const std::vector<CandidateResult>& results,
                        int candidate);

// A candidate whose fit stops at a bracket of its box (a parameter within
// 1e-4 of the box's width (the solver stops a few 1e-6 short of a bound) from a
// bound that its family does not call a limit, TermFamily::BoundIsALimit): the
// fit wants to go on, so the form stands in for structure it does not describe
// (an offset of 1000 µm on every reading, a multiplier of e^3): fails, located
// at its covariate with its LR (diagnosis_rivals.cc). Passes every other
// candidate.
GuardResult AtBoxBound(const DiagnosisState& st,
                       const std::vector<Fitted>& fits,
                       const std::vector<CandidateResult>& results,
                       int candidate);

// The proxy guard's comparison with the round's rivals
// (diagnosis_rivals.cc): fails when the term of accepted candidate `winner`
// adds nothing significant to the model of an accepted candidate over
// another covariate (not a cell): the data do not say which of the two
// drives the wear. A rival over the same scope that carries the winner's
// mechanism (SameCarriedMechanism) and adds nothing to the winner either
// does not fail it (CarriersOf lists it).
GuardResult DistinctFromRivals(const DiagnosisState& st,
                               const std::vector<double>& sd,
                               const std::vector<int>& accepted,
                               const std::vector<Fitted>& fits,
                               const std::vector<CandidateResult>& results,
                               int winner);
// The same comparison for a gated winner against the same term behind a
// gate on another covariate (refitted by AddRivalGates; diagnosis_rivals.cc):
// fails when the winner adds nothing significant to one of them, since the
// data then do not say which quantity gates the effect.
GuardResult DistinctFromOtherGates(const DiagnosisState& st,
                                   const std::vector<double>& sd,
                                   const std::vector<Fitted>& fits,
                                   const std::vector<CandidateResult>& results,
                                   int winner);

// The guard's look at the grade x campaign-order check (diagnosis_order.cc):
// refused, with where the structure lives after the term as `located`, when
// the check is significant at alpha with the training predictions `before`
// and still with `after` (both aligned with state.train).
GuardResult LookAtGradeOrder(const DiagnosisState& st,
                             const DiagnosisOptions& options,
                             const std::vector<double>& sd,
                             const std::vector<double>& before,
                             const std::vector<double>& after);

// Whether `t` is a calendar-time term (its covariate is started_at or
// measured_at).
bool IsCalendarTerm(const TermData& td, const ModelTerm& t);

// The guard's look along time for a calendar-time term
// (diagnosis_along_time.cc): refused, with the lag-1 structure as `located`,
// when the lag-1 autocovariance of the time-ordered campaign means of the
// training residuals is significant with the predictions `before` (aligned
// with state.train) and more than half of it remains with `after`.
GuardResult LookAlongTime(const Dataset& data, const DiagnosisState& st,
                          const DiagnosisOptions& options,
                          const std::vector<double>& sd,
                          const std::vector<double>& before,
                          const std::vector<double>& after,
                          const std::string& covariate);

// What the guards refused in a round (GuardedWinner): the places the
// refusals located (RunRound lists them as unexplained when the round names
// nothing), the candidates refused as proxies of a structure and their
// covariates (FitsWorseThanRefused, interacts_with_refused), and, aligned,
// every candidate tried with its refusal (kind, guard, reason, place) and
// its row in report->runners_up.
struct RoundRefusals {
  std::vector<Unexplained> located;
  std::vector<int> refused;
  std::vector<std::string> refused_covariates;
  std::vector<int> tried;
  std::vector<RefusalKind> kinds;
  std::vector<std::string> guards;
  std::vector<std::string> reasons;
  std::vector<Unexplained> places;
  std::vector<size_t> rows;
};

// The first accepted candidate of a round (`accepted`, best first) that
// passes every guard of the ordered table kWinnerGuards
// (diagnosis_winner.cc): not locate-only (NotNameable), its fit inside its
// box (AtBoxBound), distinct from the round's cells (NoBetterThanCell),
// GuardAgainstProxy, distinct from its rivals (DistinctFromRivals) and no
// worse a fit than what the guards refused (FitsWorseThanRefused); or -1.
// The others tried become runners-up with the refusing guard's
// RefusalKind; `refusals` gets what was refused and where it lives.
int GuardedWinner(int round, const Dataset& data,
                  const DiagnosisOptions& options, const DiagnosisState& st,
                  const std::vector<double>& sd,
                  const std::vector<int>& accepted,
                  const std::vector<Fitted>& fits,
                  const std::vector<CandidateResult>& results, double num_tests,
                  DiagnosisReport* report, RoundRefusals* refusals);

// Every guard of kWinnerGuards on `candidate` over the model st.current
// (diagnosis_winner.cc), nothing refused before it but the covariates
// `refused_covariates`: the first refusal, or a pass.
GuardResult WinnerGuardsOn(
    const Dataset& data, const DiagnosisOptions& options,
    const DiagnosisState& st, const std::vector<double>& sd,
    const std::vector<int>& accepted, const std::vector<Fitted>& fits,
    const std::vector<CandidateResult>& results, double num_tests,
    const std::vector<std::string>& refused_covariates, int candidate);

// Joint forward selection (diagnosis_joint.cc, docs/diagnosis.md "Two
// effects together"): when the guards refused every accepted candidate of
// a round judged on the round's model, each refused candidate A (best
// first, one per covariate, at most thresholds.max_joint_candidates) is
// judged again on the model that also carries another significant
// structure B of the round (of the max_joint_contexts + 1 strongest
// covariates by `score_p` over `screened` and the covariates the round's
// structural refusals located the left structure along, fitted where the round
// did not refit them, those other than A's mechanism adding significantly to
// the round's model and not at their box's edge: the located one's best fit,
// then best fit first, at most thresholds.max_joint_contexts beside it; a gated
// A that B makes unnecessary gives way to its ungated twin). A
// is the winner when, given B, it still adds significantly (Bonferroni over
// the round's tests times the pairs that may be tried) and passes every
// guard but shadow_of_refused, and B, given A, does the same: the pair is
// one consistent
// description, and a second effect no longer vetoes the first. Not run in
// a round with no round after it (B would never be judged). Returns A or
// its ungated twin (whose runner-up row of this round it removes, recording the
// pair in st->joint) and sets `note` to the sentence saying so; or -1.
// st->current is restored before it returns.
int JointWinner(int round, const Dataset& data, const DiagnosisOptions& options,
                const std::vector<double>& sd, const std::vector<int>& accepted,
                const std::vector<Fitted>& fits,
                const std::vector<CandidateResult>& results, double num_tests,
                const std::vector<double>& score_p,
                const std::vector<Candidate>& screened,
                const RoundRefusals& refusals, DiagnosisState* st,
                DiagnosisReport* report, std::string* note);

// After the rounds (diagnosis_joint.cc): a finding joint selection named
// whose partner structure the final model does not hold (no term over its
// covariate, or for a cell at its place, and no finding carrying its
// mechanism) was named on a model that does not exist: withdrawn
// (WithdrawFinding, RefusalKind::kJointPartnerMissing), its refusal alone
// restored and its place listed as unexplained.
void WithdrawUnpairedJoint(const DiagnosisOptions& options,
                           DiagnosisState* state, DiagnosisReport* report,
                           std::vector<int>* rounds);

// The index in `terms` of the term finding `f` adopted, or -1
// (diagnosis_final_scope.cc).
int AdoptedTermIndex(const std::vector<TermSpec>& terms, const Finding& f);

// The covariates the round's fitted candidates carry the winner's
// mechanism through (SameCarriedMechanism), over its scope, that the data
// cannot tell from it either way: neither term adds significantly to the
// other's model (DistinctFromRivals' encompassing test, at alternative_alpha).
// The winner's covariate first, then theirs; empty when there is none
// (diagnosis_rivals.cc). A carrier need not have been cross-validated: the
// strongest candidates of a round may all be forms of one covariate.
std::vector<std::string> CarriersOf(const DiagnosisState& st,
                                    const std::vector<double>& sd,
                                    const std::vector<Fitted>& fits,
                                    const std::vector<CandidateResult>& results,
                                    int winner);

// A winning cell with a twin (TwinCell) stated as the place that wears more;
// `note` gets the sentence naming the twin (diagnosis_inside_cell.cc).
Fitted OrientTwinCell(const DiagnosisState& st, const std::vector<double>& sd,
                      const Fitted& winner, std::string* note);

// Which level of an offset-per-level winner reads true
// (diagnosis_reference.cc): the reference with the least RSS, its label,
// and the other levels the data cannot reject as reading true (with their
// likelihood-ratio difference to the best, under `critical`; a level whose
// refit failed is kept as possible).
struct ReferenceChoice {
  struct Possible {
    std::string level;
    double delta = 0;  // LR difference to the best; NaN if its refit failed
  };
  std::string reference;
  std::vector<Possible> possible;  // levels possibly reading true
  double critical = 0;
};

// For an offset-per-level winner, refits it with each level that has
// training readings in its scope as the reference and returns the fit with
// the least RSS, filling *choice; any other winner is returned as is.
Fitted ChooseOffsetReference(const DiagnosisState& st,
                             const std::vector<double>& sd,
                             const Fitted& winner, ReferenceChoice* choice);

// When a level the finding names as reading off is one the data cannot
// reject as reading true, states the offset between the levels instead:
// shape "offset_between_levels", no level named, the reason appended to
// the explanation.
void StateReferenceIdentification(const ReferenceChoice& choice, Finding* f);

// The verdict, final gaps, coefficients, terms, adopted model and the
// per-observation points of the final model.
void Summarise(const Dataset& data, const DiagnosisOptions& options,
               const DiagnosisState& state, DiagnosisReport* report);

}  // namespace rollwear::diag

#endif  // ROLLWEAR_CORE_DIAGNOSIS_DIAGNOSIS_STAGES_INTERNAL_H_
