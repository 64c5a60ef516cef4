// The naming of the diagnosis engine's findings: mechanism names, shapes,
// readable values and the explanation a mill engineer reads; see
// diagnosis.h and docs/diagnosis.md ("Shapes and mechanism names").
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <limits>
#include <string>
#include <utility>

#include "core/diagnosis/diagnosis_internal.h"
#include "core/model/term_family.h"

namespace rollwear::diag {
namespace {

struct Mechanism {
  const char* covariate;
  const char* up;  // mechanism when the multiplier rises with the covariate
  const char* up_text;
  const char* down;
  const char* down_text;
};

// Physical reading of a dependence on each canonical covariate.
constexpr Mechanism kMechanisms[] = {
    {"campaign_length_before_m", "wear_rate_growth_along_campaign",
     "Each km of strip wears the roll more than the one before: the roll "
     "surface degrades along the campaign (fire cracks, banding, loss of the "
     "protective oxide layer), which the wear law, summing independent strips, "
     "leaves out.",
     "run_in_of_fresh_surface",
     "A freshly ground roll wears faster at first (grinding roughness peaks "
     "are worn off) and then settles; the wear law treats every strip alike."},
    {"campaign_coils_before", "wear_rate_growth_along_campaign",
     "Wear per coil rises with the number of coils already rolled: the roll "
     "surface degrades along the campaign.",
     "run_in_of_fresh_surface",
     "The first coils after a roll change wear the roll more: run-in of a "
     "freshly ground surface."},
    {"hours_since_mount", "thermal_growth_with_time_in_service",
     "Wear rate rises with hours in service, not with the rolled length: it "
     "follows the time the roll spends in the stand, idle time after "
     "stoppages included (thermal fatigue, oxide growth on the idle hot "
     "roll). Readings taken once per campaign tell this only in part from "
     "extra wear on the first coils after each restart (a cold roll, a lost "
     "oxide film), since both follow the stops; where the data hold enough "
     "coils after stops the diagnosis compares the two (after_stop).",
     "run_in_of_fresh_surface",
     "Wear is highest in the first hours after mounting: run-in and the "
     "thermal transient of a cold roll."},
    {"temperature_c", "hot_strip_oxide_abrasion",
     "Hotter strip wears the roll more: thicker, abrasive oxide scale and a "
     "hotter roll surface at higher entry temperature.",
     "cold_strip_hardness_and_scale",
     "Colder strip wears the roll more: it is harder and carries a harder, "
     "more abrasive tertiary scale."},
    {"lubrication", "lubrication_increases_wear",
     "Passes with roll-gap lubrication on wear more than the law predicts.",
     "roll_gap_lubrication",
     "Roll-gap lubrication lowers friction and slip in the bite and with them "
     "the abrasive wear, beyond what the lower force already accounts for."},
    {"hardness_hb", "hardness_increases_wear",
     "Harder rolls wear more than the law predicts (e.g. a harder but more "
     "brittle roll grade).",
     "roll_hardness",
     "Softer rolls wear faster: Archard wear scales with 1/hardness, which "
     "Wang's law does not contain (and rolls get softer as they are ground "
     "down)."},
    {"speed_mps", "rolling_speed",
     "Faster rolling wears the roll more per km: more sliding and a higher "
     "thermal load of the roll surface.",
     "rolling_speed_decrease",
     "Slower rolling wears the roll more per km: longer contact time and "
     "hotter contact per revolution."},
    {"force_kn", "superlinear_load_dependence",
     "Wear grows faster than linearly with rolling force (pressure exponent "
     "above one in the Archard law).",
     "sublinear_load_dependence",
     "Wear grows slower than linearly with rolling force."},
    {"specific_force_kn_per_mm", "superlinear_load_dependence",
     "Wear grows faster than linearly with specific force (pressure exponent "
     "above one).",
     "sublinear_load_dependence",
     "Wear grows slower than linearly with specific force."},
    {"width_mm", "strip_width",
     "Wider strips wear the barrel centre more per unit load.",
     "narrow_strip_concentration",
     "Narrow strips concentrate the contact at the barrel centre, wearing it "
     "more per unit load."},
    {"shift_mm", "axial_shift_position",
     "Centre wear depends on the axial shift position: shifting moves the "
     "contact zone along the barrel.",
     "axial_shift_position",
     "Centre wear depends on the axial shift position: shifting moves the "
     "contact zone along the barrel."},
    {"reduction", "roll_gap_slip",
     "Heavier reductions wear the roll more: more forward slip and sliding in "
     "a longer bite.",
     "roll_gap_slip_decrease",
     "Lighter reductions wear the roll more per unit load."},
    {"contact_length_mm", "roll_gap_slip",
     "Longer contact arcs wear the roll more: more sliding per revolution.",
     "roll_gap_slip_decrease",
     "Shorter contact arcs wear the roll more per unit load."},
    {"entry_thickness_mm", "strip_thickness",
     "Thicker entry strip wears the roll more.", "thin_strip",
     "Thinner entry strip wears the roll more per unit load."},
    {"exit_thickness_mm", "strip_thickness",
     "Thicker exit strip wears the roll more.", "thin_strip",
     "Thinner strip wears the roll more per unit load."},
    {"length_m", "coil_length",
     "Longer coils wear more per metre than short ones.", "coil_length",
     "Short coils wear more per metre (threading and tail-out)."},
    {"diameter_mm", "roll_diameter",
     "Larger rolls wear more per unit load than the law predicts.",
     "roll_diameter",
     "Smaller (more reground) rolls wear more per unit load: higher contact "
     "pressure and more revolutions per km."},
    {"started_at", "drift_over_time",
     "Wear rates drift upward over the months (e.g. a new roll supplier or "
     "batch, a changed cooling practice).",
     "drift_over_time", "Wear rates drift downward over the months."},
    {"measured_at", "measurement_drift_over_time",
     "What the grinder reads drifts upward over the months: a gauge or grinder "
     "calibration drift on the measured value, not wear physics.",
     "measurement_drift_over_time",
     "What the grinder reads drifts downward over the months: a gauge or "
     "grinder calibration drift on the measured value, not wear physics."},
    {"cooling_h", "thermal_expansion_at_measurement",
     "Rolls measured soon after the campaign read a different wear: the roll "
     "still carries thermal expansion at the barrel centre when gauged warm.",
     "thermal_expansion_at_measurement",
     "Rolls measured soon after the campaign read less wear: a warm roll is "
     "still expanded at the barrel centre, which hides part of the wear until "
     "it cools."},
};

const Mechanism* FindMechanism(const std::string& covariate) {
  for (const Mechanism& m : kMechanisms) {
    if (covariate == m.covariate) return &m;
  }
  return nullptr;
}

bool EndsWith(const std::string& s, const char* suffix) {
  const std::string x(suffix);
  return s.size() >= x.size() &&
         s.compare(s.size() - x.size(), x.size(), x) == 0;
}

// A covariate value with its unit and a readable magnitude: "96.7 km",
// "912 °C", "14.5 h", a calendar date for day counts.
std::string Readable(const std::string& name, double v) {
  if (!std::isfinite(v)) return "n/a";
  if (name == "started_at" || name == "measured_at") {
    const std::time_t t = static_cast<std::time_t>(v * 86400.0);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof(buf), "%Y-%m-%d", &tm);
    return buf;
  }
  if (EndsWith(name, "_kn_per_mm")) return WordFormat("%.2f kN/mm", v);
  if (EndsWith(name, "_mm")) return WordFormat("%.4g mm", v);
  if (EndsWith(name, "_m")) {
    return std::abs(v) >= 1000 ? WordFormat("%.1f km", v / 1000)
                               : WordFormat("%.0f m", v);
  }
  if (EndsWith(name, "_c")) return WordFormat("%.0f °C", v);
  if (EndsWith(name, "_h") || name == "hours_since_mount")
    return WordFormat("%.1f h", v);
  if (EndsWith(name, "_kn")) return WordFormat("%.0f kN", v);
  if (EndsWith(name, "_mps")) return WordFormat("%.2f m/s", v);
  if (EndsWith(name, "_hb")) return WordFormat("%.0f HB", v);
  if (name == "campaign_coils_before") return WordFormat("%.0f coils", v);
  return WordFormat("%.4g", v);
}

// A rise (or drop) concentrated above the upper quantiles of a binned
// profile: the first four points flat within a quarter of the total change,
// most of it in the last step.
const char* ThresholdShape(const std::vector<double>& v) {
  const double total = v.back() - v.front();
  double lo = v[0], hi = v[0];
  for (size_t i = 1; i + 1 < v.size(); ++i) {
    lo = std::min(lo, v[i]);
    hi = std::max(hi, v[i]);
  }
  const double last = v.back() - v[v.size() - 2];
  if (std::abs(last) > 0.75 * std::abs(total) &&
      hi - lo < 0.25 * std::abs(last)) {
    return last > 0 ? "threshold_rise" : "threshold_drop";
  }
  return nullptr;
}

// The finding's scope and levels (contract fields) and the sentence saying
// where it applies. A cell term is reported on its factor (roll_type or
// grade) with the level in `levels` and the stand or position as scope.
std::string DescribeScope(const ModelTerm& t, Finding* f) {
  f->scope.clear();
  for (const auto& [k, v] : t.scope.Fields()) f->scope[k] = v;
  if (t.form == TermForm::kCell) {
    const bool by_type = !t.scope.roll_type.empty();
    f->covariate = by_type ? "roll_type" : "grade";
    f->levels = {by_type ? t.scope.roll_type : t.scope.grade};
    f->scope.erase(f->covariate);
  }
  if (t.scope.IsAll()) return "";
  // A gate's threshold is a step of the grid it was chosen on
  // (thresholds.gate_grid), not a fitted value.
  const std::string grid = t.scope.gate.empty()
                               ? ""
                               : " (its threshold one of a grid of the passes' "
                                 "quantiles, not fitted)";
  return " It applies only to " + t.scope.Label() + grid +
         kElsewhereTheLawHolds + ".";
}

// The mechanism name of finding `f` (its term `t` over covariate `c`,
// rising when `up`) into f->mechanism, and the sentence of physics that
// opens its explanation: a cell's interaction, a reading's offset, a
// mechanism carried by several quantities (f->carriers), one covariate's
// (kMechanisms), or a plain dependence.
std::string MechanismOf(const ModelTerm& t, const CovariateSpec& c, bool up,
                        Finding* f) {
  const Mechanism* m = FindMechanism(c.name);
  std::string text;
  if (t.form == TermForm::kCell) {
    f->mechanism =
        std::string(t.scope.roll_type.empty() ? "grade" : "roll_type") +
        "_by_" + (t.scope.stand > 0 ? "stand" : "position") + "_interaction";
    text = "Rolls of " + t.scope.Label() + " wear " +
           WordFormat("%.2f", std::exp(t.params[0])) +
           " times what the K structure (position x roll type x grade factors, "
           "which multiply independently) predicts: an interaction no single "
           "factor expresses.";
  } else if (t.form == TermForm::kOffsetPerLevel) {
    f->mechanism = "measurement_offset_by_" + c.name;
    text =
        "The grinder's reading depends on " + c.name +
        ": an instrument, gauge or crew offset on the measured value, not wear "
        "physics.";
  } else if (const CarrierGroup* g = CarrierGroupOf(c.name);
             g != nullptr && f->carriers.size() > 1) {
    f->mechanism = up ? g->up : g->down;
    text = std::string(up ? g->up_text : g->down_text) +
           CarriersSentence(f->carriers);
  } else if (m != nullptr && (f->shape == "peaked" || f->shape == "valley")) {
    // Its sentences read a monotone dependence ("drift upward"): a profile
    // with an interior extreme is stated as such, not given one of them.
    f->mechanism = c.name + "_nonmonotone";
    text = "The wear rate " +
           std::string(f->shape == "peaked" ? "rises, then falls,"
                                            : "falls, then rises,") +
           " along " + c.name + ", which no monotone reading of it (" +
           (std::string(m->up) == m->down
                ? std::string(m->up)
                : std::string(m->up) + " or " + m->down) +
           ") describes as a whole.";
  } else if (m != nullptr) {
    f->mechanism = up ? m->up : m->down;
    text = up ? m->up_text : m->down_text;
  } else if (t.IsMeasurementTerm()) {
    f->mechanism = "measurement_bias_" + c.name;
    text = "What the grinder reads depends on " + c.name +
           ", a measurement-side effect the wear model does not contain.";
  } else {
    f->mechanism = c.name + "_dependence";
    text = "The wear rate depends on " + c.name +
           ", a quantity the wear law does not contain.";
  }
  return text;
}

// Shape of a wear-rate multiplier from its profile over the covariate's
// 5th..95th percentiles (`w`), and whether it rises: monotone (with or
// without most of the change in the first half: saturating growth /
// decay) or with an interior extreme.
std::pair<std::string, bool> ProfileShape(const ModelTerm& t,
                                          const WeightedValues& w,
                                          const TermWordingInput& in) {
  std::vector<double> v;
  for (double q : {0.05, 0.275, 0.5, 0.725, 0.95}) {
    v.push_back(TermMultiplier(t, Quantile(w, q), nullptr));
  }
  // A departure from monotone counts only beyond 1 % of the change, and
  // for the binned form beyond 2 standard errors of a bin's multiplier
  // (exp(b) * se(b)): a step seen through noisy bins is still a step.
  double tol = 0.01 * std::max(1e-12, std::abs(v.back() - v.front()));
  if (t.form == TermForm::kBinned) {
    for (size_t j = 0; j < t.params.size(); ++j) {
      const double se = StdErrorOf(in, j);
      if (std::isfinite(se))
        tol = std::max(tol, 2 * std::exp(t.params[j]) * se);
    }
  }
  bool inc = true, dec = true;
  for (size_t i = 1; i < v.size(); ++i) {
    inc = inc && v[i] >= v[i - 1] - tol;
    dec = dec && v[i] <= v[i - 1] + tol;
  }
  const bool up = v.back() > v.front();
  if (inc && dec) {  // flat within the tolerance: monotone in its direction
    inc = up;
    dec = !up;
  }
  if (inc && !dec) {
    if (t.form == TermForm::kBinned && ThresholdShape(v) != nullptr) {
      return {ThresholdShape(v), up};
    }
    return {(v[2] - v[0]) > 0.75 * (v[4] - v[0]) ? "saturating_growth"
                                                 : "increasing",
            up};
  }
  if (dec && !inc) {
    return {(v[0] - v[2]) > 0.75 * (v[0] - v[4]) ? "decaying" : "decreasing",
            up};
  }
  if (t.form == TermForm::kBinned) {
    if (const char* th = ThresholdShape(v)) return {th, up};
  }
  const size_t imax = std::max_element(v.begin(), v.end()) - v.begin();
  const size_t imin = std::min_element(v.begin(), v.end()) - v.begin();
  if (imax > 0 && imax + 1 < v.size()) return {"peaked", up};
  if (imin > 0 && imin + 1 < v.size()) return {"valley", up};
  return {up ? "increasing" : "decreasing", up};
}

// "pass", "roll", "campaign" or "measurement".
const char* LevelName(CovariateLevel level) {
  switch (level) {
    case CovariateLevel::kPass:
      return "pass";
    case CovariateLevel::kRoll:
      return "roll";
    case CovariateLevel::kCampaign:
      return "campaign";
    case CovariateLevel::kMeasurement:
      return "measurement";
  }
  return "";
}

}  // namespace

void NameFinding(const TermData& td, const std::vector<int>& train,
                 const TermSpec& spec, Finding* f) {
  const ModelTerm& t = spec.term;
  const CovariateSpec& c = td.catalog[spec.covariate];
  const WeightedValues w = Collect(td, train, spec.covariate);
  const double lo = Quantile(w, 0.05), hi = Quantile(w, 0.95);
  f->covariate = c.name;
  f->form = TermFormName(t.form);
  f->level = LevelName(c.level);
  TermWordingInput in;
  in.std_errors = &f->parameter_std_errors;
  in.profile_shape = [&t, &w, &in] { return ProfileShape(t, w, in); };
  in.range_text =
      WordFormat("wear-rate multiplier %.3f at the 5th percentile (",
                 TermMultiplier(t, lo, nullptr)) +
      Readable(c.name, lo) +
      WordFormat(") and %.3f at the 95th (", TermMultiplier(t, hi, nullptr)) +
      Readable(c.name, hi) + ")";
  in.readable = [&c](double v) { return Readable(c.name, v); };
  // The family words its term (core/model/term_family_<name>.cc).
  TermWording words;
  FamilyOf(t.form).Word(t, in, &words);
  if (!words.shape.empty()) f->shape = words.shape;
  for (const auto& [name, value] : words.parameters)
    f->parameters[name] = value;
  if (words.levels) f->levels = *words.levels;
  const bool up = words.up;
  const std::string& fitted = words.fitted;
  std::string text;
  if (words.mechanism.empty()) {
    text = MechanismOf(t, c, up, f);
  } else {  // the family's own physics (term_family.h: names_mechanism)
    f->mechanism = words.mechanism;
    text = words.mechanism_text;
  }
  f->explanation = text + DescribeScope(t, f) + " Fitted: " + fitted + ".";
}

}  // namespace rollwear::diag
