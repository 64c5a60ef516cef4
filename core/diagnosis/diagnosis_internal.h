// Internal pieces of the diagnosis engine (diagnosis.h): the candidate
// library, the naming of mechanisms, and the residual breakdowns. Include
// only from diagnosis*.cc.
//
// Thread-safety: pure functions.
#ifndef ROLLWEAR_CORE_DIAGNOSIS_DIAGNOSIS_INTERNAL_H_
#define ROLLWEAR_CORE_DIAGNOSIS_DIAGNOSIS_INTERNAL_H_

#include <array>
#include <cmath>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/diagnosis/diagnosis.h"
#include "core/fit/term_fit.h"

namespace rollwear::diag {

struct Candidate {
  TermSpec spec;
  // Alternative starting parameter vectors (non-linear parameters such as
  // a length scale are tried on a small grid; the best fit is kept).
  std::vector<std::vector<double>> starts;
};

// A covariate's training values with their weights (the load of each pass
// for a pass-level covariate, 1 per observation otherwise), sorted.
struct WeightedValues {
  std::vector<std::pair<double, double>> v;  // (value, weight), sorted
  double total = 0;
};
WeightedValues Collect(const TermData& td, const std::vector<int>& obs, int k);
// The weighted q-quantile of `w` (NaN when empty).
double Quantile(const WeightedValues& w, double q);

// The quartile bin (0..3) of x among three ascending edges: 0 below
// edges[0], 1 below edges[1], 2 below edges[2], else 3.
inline int QuartileOf(double x, const std::array<double, 3>& edges) {
  return x < edges[0] ? 0 : x < edges[1] ? 1 : x < edges[2] ? 2 : 3;
}
// A bin's label: "Q1 (< e0)", "Q2 (e0 - e1)", "Q3 (e1 - e2)" or
// "Q4 (>= e2)", edges as %.4g (diagnosis_locate.cc).
std::string QuartileLabel(int q, const std::array<double, 3>& edges);
// The weighted mean and standard deviation of `w` (w.total > 0).
void MeanSd(const WeightedValues& w, double* mean, double* sd);

// Every candidate term over covariates not in `used`; cells at every
// place but those of `adopted_cells` (and their twins).
std::vector<Candidate> MakeCandidates(
    const TermData& td, const std::vector<int>& train,
    const std::set<int>& used, const DiagnosisOptions& options,
    const std::vector<TermScope>& adopted_cells = {});

// The unscoped candidates of each covariate on `train`, by catalogue index
// (built on options.num_threads threads): the part of MakeCandidates that
// does not depend on `used`, so a diagnosis builds it once for its rounds.
std::vector<std::vector<Candidate>> UnscopedCandidates(
    const TermData& td, const std::vector<int>& train,
    const DiagnosisOptions& options);

// MakeCandidates from UnscopedCandidates(td, train, options).
std::vector<Candidate> MakeCandidates(
    const TermData& td, const std::vector<int>& train,
    const std::set<int>& used,
    const std::vector<std::vector<Candidate>>& unscoped,
    const DiagnosisThresholds& thresholds,
    const std::vector<TermScope>& adopted_cells = {});

// Appends the scoped variants of the simple candidates already in `out`
// and the cell candidates but those of `adopted_cells` and their twins
// (diagnosis_scoped.cc).
void AddScopedCandidates(const TermData& td, const std::vector<int>& train,
                         const DiagnosisThresholds& thresholds,
                         const std::set<int>& used,
                         const std::vector<TermScope>& adopted_cells,
                         std::vector<Candidate>* out);

// A cell term over `scope` as the candidates offer it: m = exp(b), b from
// 0 within [-3, 3], prior sd kCellPriorSd (diagnosis_scoped.cc).
TermSpec CellTermSpec(const TermData& td, const TermScope& scope);
// Whether two cells are of one kind: the same place factor (stand, roll
// position or position) and the same level factor (roll type or grade).
bool SameCellKind(const TermScope& a, const TermScope& b);

// `cells` followed by the twin (TwinCell) of each that has one: the places
// a set of cells describes (diagnosis_scoped.cc).
std::vector<TermScope> WithTwins(const TermData& td,
                                 const std::vector<int>& train,
                                 const DiagnosisThresholds& thresholds,
                                 const std::vector<TermScope>& cells);
// The scopes of the cell terms among `terms`.
std::vector<TermScope> ModelCells(const std::vector<TermSpec>& terms);

// The cells with enough training data, as the candidates offer them (one
// of two twin cells; diagnosis_scoped.cc).
std::vector<TermScope> OfferedCellScopes(const TermData& td,
                                         const std::vector<int>& train,
                                         const DiagnosisThresholds& thresholds);

// The twin of a cell: when the cell's roll type or grade runs (in the
// training data) in exactly two places of the cell's kind (two stands, top
// and bottom, or two roll positions such as F7/top and F7/bottom), the
// other place's cell, which describes the same data
// (x m at one place = x 1/m at the other, the level's own K factor taking
// up the rest). False when there is no twin (diagnosis_scoped.cc).
bool TwinCell(const TermData& td, const std::vector<int>& train,
              const DiagnosisThresholds& thresholds, const TermScope& cell,
              TermScope* twin);

// The complementary description of a set of stand cells of one factor
// (roll types, or grades, all at one stand s) in a mill whose training
// readings come from exactly two stands s and t: the factor's other levels
// that run at both stands, as cells at t. Multiplying stand s's K by m and
// those levels' K by 1/m, the set at s x m is those cells at t x m: the
// same predictions (the interaction of a two-row table is identified only
// up to a constant). False (and empty) when `cells` is not such a set or
// the mill has not two stands (diagnosis_scoped.cc).
bool ComplementCells(const TermData& td, const std::vector<int>& train,
                     const DiagnosisThresholds& thresholds,
                     const std::vector<TermScope>& cells,
                     std::vector<TermScope>* complement);

// The level of a factor covariate's value (TermData::z holds the level
// index as a double; NaN, an empty cell, and anything that cannot be a
// level index are -1).
inline int LevelIndex(double z) {
  if (!(z > -0.5 && z < 1e9)) return -1;
  return static_cast<int>(std::lround(z));
}

// The end of a scoped finding's sentence "It applies only to F7; elsewhere
// the wear law holds." (diagnosis_naming.cc), which the note on
// undetermined siblings qualifies (diagnosis_siblings.cc).
inline constexpr const char* kElsewhereTheLawHolds =
    "; elsewhere the wear law holds";

// The single-factor scopes with enough training data (at least
// thresholds.min_scope_observations inside, and not all of them): each stand,
// position (top, bottom), roll position (stand and position, "F7/top"), roll
// type and grade (diagnosis_scoped.cc). With `keep_everywhere`, also a scope
// that holds every training reading (a grade rolled in every campaign still
// restricts passes: the sibling test must see it).
std::vector<TermScope> SingleScopes(const TermData& td,
                                    const std::vector<int>& train,
                                    const DiagnosisThresholds& thresholds,
                                    bool keep_everywhere = false);

// The gates a gated family's candidate over covariate index `covariate` is
// offered behind (term_family.h, offered_gated): above and below each
// distinct load-weighted inner 1/thresholds.gate_grid quantile of every
// other numeric pass-level covariate of the training passes that neither
// grows within a campaign (that is the growth families' physics) nor is
// locate-only.
std::vector<TermScope> GateScopes(const TermData& td,
                                  const std::vector<int>& train,
                                  const DiagnosisThresholds& thresholds,
                                  int covariate);

// Whether candidate i is behind a gate while a gated copy of the same term
// (covariate, form and place) is among `chosen` (diagnosis_gates.cc): the
// round refits one gate per term.
bool GateOfATermIn(const std::vector<Candidate>& candidates, int i,
                   const std::vector<int>& chosen);
// Appends to `chosen` the ungated twin of each gated candidate in it (the
// same term on every pass), when offered and not chosen yet: the gate must
// be required (GateRequired), and the round must have the twin to name
// when it is not (the plain lubrication flag was not refitted behind six of
// its gated copies).
void AddUngatedTwins(const std::vector<Candidate>& candidates,
                     std::vector<int>* chosen);

// Appends to `chosen`, for each gated candidate in it, the strongest gate
// of the same term on each other gate covariate whose score p-value is at
// most `max_score_p` (diagnosis_gates.cc): the gate covariates a term's
// effect may follow (speed and the gauge move together through the
// stands), which the winner must be told apart from
// (DistinctFromOtherGates, diagnosis_rivals.cc).
void AddRivalGates(const std::vector<Candidate>& candidates,
                   const std::vector<double>& score_p, double max_score_p,
                   std::vector<int>* chosen);

// Whether observation `ob` is inside `s` (a grade scope, or a gate, holds an
// observation when any of its passes rolled the grade, or is inside the
// gate).
bool InScope(const TermData& td, const TermObservation& ob, const TermScope& s);

// A mechanism several recorded quantities carry (diagnosis_carriers.cc):
// its covariates (nullptr pads the list) and its name and sentence when the
// wear rate rises (up) or falls (down) along them.
struct CarrierGroup {
  const char* name;
  std::array<const char*, 3> covariates;
  const char* up;
  const char* up_text;
  const char* down;
  const char* down_text;
};
// The group `covariate` carries, or nullptr.
const CarrierGroup* CarrierGroupOf(const std::string& covariate);
// Whether two different covariates carry one mechanism.
bool SameCarriedMechanism(const std::string& a, const std::string& b);
// " Carried by a, b or c: ... (the fitted term is on a)." for a finding's
// carriers (the named covariate first).
std::string CarriersSentence(const std::vector<std::string>& carriers);

// Fills mechanism, shape and explanation of a finding from its fitted term
// and the covariate's training range (reads f->parameter_std_errors when
// set, to tell a noisy binned step from a peak). With f->carriers (more
// than the term's covariate), the carried mechanism is named with them.
void NameFinding(const TermData& td, const std::vector<int>& train,
                 const TermSpec& spec, Finding* finding);

// Residual breakdowns of `pred` (aligned with `obs`), strongest first;
// with `clip_sd` (aligned with `obs`) each residual is clipped to
// +-kHuberK * clip_sd first (robust.h).
std::vector<Breakdown> Locate(const TermData& td, const Dataset& data,
                              const std::vector<int>& obs,
                              const std::vector<double>& pred,
                              const DiagnosisThresholds& thresholds,
                              const std::vector<double>* clip_sd = nullptr);

// Whether `spec` is a calendar step candidate (a binned or offset-binned
// term with a single edge).
inline bool IsStep(const TermSpec& spec) {
  return (spec.term.form == TermForm::kBinned ||
          spec.term.form == TermForm::kOffsetBinned) &&
         spec.term.edges.size() == 1;
}

// Load-weighted quantile q in [0, 1] of covariate k over the passes of
// `obs` (or of the aggregated values for non-pass covariates).
double CovariateQuantile(const TermData& td, const std::vector<int>& obs, int k,
                         double q);

// One-way ANOVA F test (F = MSB / MSW, Fisher 1925) of `resid` over the
// groups named by `label` (in the order of `order`, else by label), with
// each group's mean residual and mean relative residual `rel`.
Breakdown AnovaBreakdown(const std::string& dimension,
                         const std::vector<std::string>& label,
                         const std::vector<double>& resid,
                         const std::vector<double>& rel,
                         const std::vector<std::string>& order = {});

// The grade with the largest share of the observation's load ("?" if none).
std::string DominantGrade(const TermData& td, const TermObservation& o);

// The noise checks of the final model's residuals (diagnosis_noise.cc):
// dyadic time blocks, lag-1 autocorrelation and runs of campaign means in
// time order, roll position x time half, and Brown-Forsythe spread by
// position and by time quarter. `sd` (aligned with `obs`) is the robust
// noise sd of each prediction; residuals are standardised and clipped to
// +-kHuberK.
std::vector<Breakdown> NoiseChecks(const TermData& td, const Dataset& data,
                                   const std::vector<int>& obs,
                                   const std::vector<double>& pred,
                                   const std::vector<double>& sd,
                                   const DiagnosisThresholds& thresholds);

// The group of a breakdown that carries its structure (diagnosis_noise.cc):
// the largest |mean residual| (for a spread check, the largest relative
// spread), groups labelled "missing" left out; nullptr when there is none.
const Breakdown::Group* Carrier(const Breakdown& b);

// The grade x campaign-order check (diagnosis_order.cc): whether a grade's
// coils in the campaign's opening window wear otherwise than its other
// coils, from the standardised residuals `u` (and their µm `um`, for the
// size), both aligned with `obs`; appends one breakdown
// "grade_by_campaign_order" (test "partial_correlation", p-value
// Bonferroni-adjusted over the grades and windows tried).
void GradeByCampaignOrder(const TermData& td, const std::vector<int>& obs,
                          const std::vector<double>& u,
                          const std::vector<double>& um,
                          const DiagnosisThresholds& thresholds,
                          std::vector<Breakdown>* out);

// Per campaign of `obs`, in time order (started_at): the mean of `u` and of
// `um` (aligned with `obs`) over the campaign's observations.
struct CampaignSeries {
  std::vector<double> u, um;
};
CampaignSeries ByCampaignInTime(const TermData& td, const Dataset& data,
                                const std::vector<int>& obs,
                                const std::vector<double>& u,
                                const std::vector<double>& um);

// The checks significant at family-wise level `alpha` (Bonferroni over all
// of `checks`) and of material size (a location group mean of at least
// `material_um`; see diagnosis_noise.cc for the others), strongest first.
std::vector<Unexplained> UnexplainedStructure(
    const std::vector<Breakdown>& checks, double alpha, double material_um,
    const DiagnosisThresholds& thresholds);

// The material size of a located mean residual: a quarter
// (thresholds.material_noise_share) of the median noise sd.
double MaterialResidualUm(const std::vector<double>& sd,
                          const DiagnosisThresholds& thresholds);

}  // namespace rollwear::diag

#endif  // ROLLWEAR_CORE_DIAGNOSIS_DIAGNOSIS_INTERNAL_H_
