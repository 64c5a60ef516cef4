// Model terms: physics the baseline wear law leaves out, as nested
// extensions that reduce to the baseline when their parameters are zero.
//
// Each form is a term family (term_family.h): its file
// core/model/term_family_<name>.cc holds the formula below, its
// derivatives, its refit box and its stored rules.
//
// Wear-rate terms multiply the wear of every pass i of a roll:
//   w_i = K * Load_i * prod_t m_t(z_t,i)
//   log-linear   m = exp(b * (z - c) / s)          c, s: training mean, sd
//   power        m = (z / c)^b                     z > 0
//   saturating   m = 1 + b * (1 - exp(-z / lam))   growth that levels off;
//                                                  lam = exp(q); linear growth
//                                                  is the lam >> z limit
//   decaying     m = 1 + b * exp(-z / lam)         run-in: extra wear early on
//   hinge        m = exp(b * max(0, (z - k) / s))  a knee k (fitted): the
//                                                  rate changes above it
//                                                  (s > 0) or below it
//                                                  (s < 0), |s| the sd
//   flag         m = exp(b * z)                    z in {0, 1}
//   binned       m = exp(b_k) for z in bin k >= 1  (bin 0: m = 1); bins are
//                                                  training quantiles: any
//                                                  shape
//   per-level    m = exp(b_l) for factor level l >= 1
//   cell         m = exp(b) on the passes of its scope, a (stand or roll
//                position) x (roll type or grade) cell the K structure
//                cannot express (covariate "cell", always 1)
//   roll-effect  m = exp(b_r) for the physical roll r (covariate "roll_id",
//                levels = roll ids, one parameter per roll, no reference):
//                the roll's own wear resistance, a random effect with the
//                normal prior b_r ~ N(0, s^2), s = `scale` estimated from
//                the data (core/fit/roll_effects.h: DerSimonian & Laird
//                1986); a roll the fit never saw counts as 1, its type's
//                value
// Additive terms add wear on every pass they cover, beside the law's:
//   w_i = K * Load_i * prod_t m_t(z_t,i) + r * sum_a a
// (r: the roll's own factor, the roll-effect term's exp(b_r), 1 without
// one: a roll's wear resistance acts on all its wear)
//   per-coil     a (µm) per pass, whatever its length and load: the wear
//                each coil's bite adds (covariate campaign_coils_before,
//                whose value it does not use; a >= 0)
// Measurement terms add to what the grinder reads, not to the wear:
//   offset-decay   y = d + A * exp(-z / tau)       tau = exp(q)
//   offset-linear  y = d + A * (z - c) / s
//   offset-per-level  y = d + d_l for level l != r of a measurement-side text
//                  column (r = reference_level, chosen by the fit: the
//                  diagnosis offers every level as reference; params in
//                  level order without r): a second grinder, a gauge, a
//                  shift crew reading differently
//   offset-binned  y = d + A_k in quantile bin k >= 1 of z (bin 0 reads as
//                  is; edges as the binned form): a gauge that steps or
//                  drifts unevenly over calendar time (measured_at)
// A missing covariate value (NaN) leaves the prediction unchanged.
//
// Scope (TermScope): a term may be restricted to one stand, one roll
// position (top/bottom), one roll type and/or one grade. A scoped wear-rate
// term multiplies only the passes inside its scope (m = 1 outside); a scoped
// measurement term offsets only the readings of rolls inside it. The
// parameter count is that of the unscoped form.
//
// Cell terms are fitted with a normal prior b ~ N(0, tau^2) (TermSpec::
// prior_sd, term_fit.h) so that rare cells stay sane; roll-effect terms
// with b_r ~ N(0, scale^2), their own estimated spread.
//
// Thread-safety: pure functions and plain values.
#ifndef ROLLWEAR_CORE_MODEL_MODEL_TERMS_H_
#define ROLLWEAR_CORE_MODEL_MODEL_TERMS_H_

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace rollwear {

enum class TermForm {
  kLogLinear,
  kPower,
  kSaturating,
  kDecaying,
  kFlag,
  kBinned,
  kPerLevel,
  kCell,
  kOffsetDecay,
  kOffsetLinear,
  kOffsetPerLevel,
  kOffsetBinned,
  kRollEffect,
  kPerCoil,
  kHinge,
};
// The functions below that depend on the form ask the term's family
// (term_family.h, whose registry term_family.cc defines them).
const char* TermFormName(TermForm f);  // "log_linear", "power", ...
bool ParseTermForm(const std::string& name, TermForm* out);

// Where a term applies; the default (all zero / empty) is everywhere.
// A gate restricts a term to the passes on one side of a threshold of a
// second, pass-level numeric covariate (a lubrication flag that acts only
// above some speed): the term applies where gate >= gate_at (gate_above) or
// gate < gate_at, and is 1 (or adds nothing) on the other passes.
struct TermScope {
  TermScope() = default;
  // A place and a grade, no gate ({7, -1, "", "HSLA420"}).
  TermScope(int stand_in, int position_in, std::string roll_type_in,
            std::string grade_in)
      : stand(stand_in),
        position(position_in),
        roll_type(std::move(roll_type_in)),
        grade(std::move(grade_in)) {}

  int stand = 0;          // 1..7, 0 = every stand
  int position = -1;      // static_cast<int>(Position), -1 = both
  std::string roll_type;  // empty = every roll type
  std::string grade;      // empty = every grade
  std::string gate;       // empty = no gate; else a pass-level covariate
  double gate_at = 0;     // the gate's threshold, in the covariate's unit
  bool gate_above = true;

  bool IsAll() const {
    return stand == 0 && position < 0 && roll_type.empty() && grade.empty() &&
           gate.empty();
  }
  // Whether a pass whose gate covariate is `value` is inside the gate (a
  // pass without a value is outside; with no gate, every pass is inside).
  bool CoversGateValue(double value) const {
    if (gate.empty()) return true;
    if (std::isnan(value)) return false;
    return gate_above ? value >= gate_at : value < gate_at;
  }
  // Whether a roll at (stand, position) of `roll_type` is inside (the grade
  // and the gate are checked per pass: CoversGrade, CoversGateValue).
  bool CoversRoll(int roll_stand, int roll_position, const std::string& type) const {
    return (stand == 0 || stand == roll_stand) &&
           (position < 0 || position == roll_position) &&
           (roll_type.empty() || roll_type == type);
  }
  bool CoversGrade(const std::string& g) const { return grade.empty() || grade == g; }
  // Readable: "F7", "top rolls", "roll type ICDP", "grade HSLA",
  // "passes with speed_mps >= 12.1", joined by ", "; "" when everywhere.
  std::string Label() const;
  // The contract's finding scope: {"stand":"F7","position":"top",...}; a
  // gate as "gate" (the covariate), "gate_side" ("above" or "below") and
  // "gate_at" (the threshold, %.4g).
  std::vector<std::pair<std::string, std::string>> Fields() const;
  // The gate's threshold as Label and Fields write it ("12.1").
  std::string GateAtText() const;
  bool operator==(const TermScope&) const = default;
};

// The covariate name of cell terms (covariates.h: the constant 1).
inline constexpr const char* kCellCovariateName = "cell";
// Prior sd tau of a cell term's log-multiplier b ~ N(0, tau^2): a cell 20 %
// off the K structure is one prior sd, so a cell with few observations
// shrinks towards 1 while a well-measured cell is fitted by its data.
inline constexpr double kCellPriorSd = 0.2;

struct ModelTerm {
  std::string covariate;  // name in the covariate catalog (covariates.h)
  TermForm form = TermForm::kLogLinear;
  std::vector<double> params;  // see the table above
  double center = 0;           // c
  double scale = 1;            // s (roll-effect: the prior sd of b_r)
  std::vector<double> edges;   // binned: upper edges of bins 0..B-2
  int num_levels = 0;          // per-level: number of factor levels
  // per-level: the factor's level labels, level l = levels[l] (the first
  // num_levels of the fitted data's levels). The daemon matches a record's
  // label to them (core/model/predictor.h); empty for a term stored before
  // labels were kept, which then counts as 1 coil by coil.
  std::vector<std::string> levels;
  TermScope scope;  // where the term applies (default: everywhere)
  int reference_level = 0;  // offset-per-level: the level read as is
  // roll-effect: per level, the posterior sd of b_r and the training
  // readings it rests on (the fit's, for the roll's interval; empty when
  // not computed).
  std::vector<double> level_sd;
  std::vector<int> level_readings;

  // Both from the term's family (term_family.h).
  bool IsMeasurementTerm() const;
  bool IsAdditiveTerm() const;  // adds wear per pass (TermAddend)
  int NumParams() const;
};

// Wear-rate multiplier m(z) and, if grad != nullptr, dm/dparams
// (size NumParams()).
double TermMultiplier(const ModelTerm& t, double z, double* grad);
// Measurement offset (µm) and, if grad != nullptr, d/dparams.
double TermOffset(const ModelTerm& t, double z, double* grad);
// Wear added to a pass (µm) by an additive term and, if grad != nullptr,
// d/dparams; 0 for any other term. TermMultiplier of an additive term is 1
// and TermOffset 0.
double TermAddend(const ModelTerm& t, double z, double* grad);

// Index of the bin of z (binned form).
int TermBin(const ModelTerm& t, double z);

// A physical roll's own wear factor under a model's roll-effect term:
// exp(b_r) with the 95 % interval exp(b_r +- 1.96 sd_r) and the training
// readings behind it; a roll the term does not know is at its type's value
// 1 with the prior's interval exp(+-1.96 scale) and 0 readings.
struct RollWearFactor {
  double value = 1, lo = 1, hi = 1;
  double log_sd = 0;  // sd_r (or the prior's scale): the sd of log factor
  int readings = 0;
  bool known = false;  // the roll had training readings
};
// The index of roll `roll_id` among a roll-effect term's levels, or -1
// (the one lookup of a roll's level: the predictor, the served factor, its
// re-estimate).
int RollLevelOf(const ModelTerm& t, const std::string& roll_id);

// nullopt when `terms` has no roll-effect term.
std::optional<RollWearFactor> RollWearFactorOf(const std::vector<ModelTerm>& terms,
                                               const std::string& roll_id);

// The half-width of a 95 % interval of predicted wear `wear` on roll
// `roll_id`, widened for the uncertainty of the roll's own factor (a
// roll-effect term): sqrt(half^2 + (1.96 wear sd_r)^2), the delta method
// on wear = exp(b_r) x (d wear / d b_r = wear), as roll_effects.h's
// intervals; `half` unchanged without such a term.
double WidenForRollFactor(const std::vector<ModelTerm>& terms,
                          const std::string& roll_id, double wear, double half);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_MODEL_TERMS_H_
