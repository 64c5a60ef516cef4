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
     "Wear rate rises with hours in service, not with the rolled length: the "
     "roll heats up and thermal fatigue accumulates with time in the stand "
     "(stoppages included).",
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

std::string Format(const char* fmt, double a, double b = 0, double c = 0,
                   double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof(buf), fmt, a, b, c, d);
  return buf;
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
  if (EndsWith(name, "_kn_per_mm")) return Format("%.2f kN/mm", v);
  if (EndsWith(name, "_mm")) return Format("%.4g mm", v);
  if (EndsWith(name, "_m")) {
    return std::abs(v) >= 1000 ? Format("%.1f km", v / 1000)
                               : Format("%.0f m", v);
  }
  if (EndsWith(name, "_c")) return Format("%.0f °C", v);
  if (EndsWith(name, "_h") || name == "hours_since_mount")
    return Format("%.1f h", v);
  if (EndsWith(name, "_kn")) return Format("%.0f kN", v);
  if (EndsWith(name, "_mps")) return Format("%.2f m/s", v);
  if (EndsWith(name, "_hb")) return Format("%.0f HB", v);
  if (name == "campaign_coils_before") return Format("%.0f coils", v);
  return Format("%.4g", v);
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

// The bin j whose jump from bin j - 1 carries at least 3/4 of a binned
// profile's total change, every other jump at most 1/4 of it (the rule of
// the offset-binned form: a step seen through quantile bins, such as a
// wear rate 1.21 times higher from the third regrind on: bins 1.000,
// 1.208, 1.198, 1.212); 0 when there is none.
int SingleJump(const std::vector<double>& m) {
  const double total = std::abs(m.back() - m.front());
  size_t j = 0;
  double largest = 0;
  for (size_t i = 1; i < m.size(); ++i) {
    if (std::abs(m[i] - m[i - 1]) > largest) {
      largest = std::abs(m[i] - m[i - 1]);
      j = i;
    }
  }
  if (!(total > 0) || largest < 0.75 * total) return 0;
  for (size_t i = 1; i < m.size(); ++i) {
    if (i != j && std::abs(m[i] - m[i - 1]) > 0.25 * largest) return 0;
  }
  return static_cast<int>(j);
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
  return " It applies only to " + t.scope.Label() + kElsewhereTheLawHolds + ".";
}

// Offset-per-level parameters, the levels whose offset is significant
// (|d| > 2 s.e., or every non-reference level without standard errors) and
// the sentence "the reading of grinder=B is offset by -15.2 µm".
void OffsetLevels(const ModelTerm& t, Finding* f, std::string* fitted) {
  f->shape = "offset_per_level";
  f->levels.clear();
  const std::string ref = t.reference_level < static_cast<int>(t.levels.size())
                              ? t.levels[t.reference_level]
                              : "";
  for (size_t j = 0; j < t.params.size(); ++j) {
    const size_t l = static_cast<int>(j) < t.reference_level ? j : j + 1;
    const std::string label =
        l < t.levels.size() ? t.levels[l] : std::to_string(l);
    f->parameters["offset_um[" + label + "]"] = t.params[j];
    auto se = f->parameter_std_errors.find("param" + std::to_string(j));
    const bool significant = se == f->parameter_std_errors.end() ||
                             !std::isfinite(se->second) ||
                             std::abs(t.params[j]) > 2 * se->second;
    if (!significant) continue;
    f->levels.push_back(label);
    if (!fitted->empty()) *fitted += "; ";
    *fitted += "the reading of " + t.covariate + "=" + label +
               Format(" is offset by %+.1f µm", t.params[j]);
  }
  if (fitted->empty()) *fitted = "no level's offset is significant";
  *fitted += " (reference " + t.covariate + "=" + ref + ")";
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
           Format("%.2f", std::exp(t.params[0])) +
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

}  // namespace

void NameFinding(const TermData& td, const std::vector<int>& train,
                 const TermSpec& spec, Finding* f) {
  const ModelTerm& t = spec.term;
  const CovariateSpec& c = td.catalog[spec.covariate];
  const WeightedValues w = Collect(td, train, spec.covariate);
  const double lo = Quantile(w, 0.05), hi = Quantile(w, 0.95);
  f->covariate = c.name;
  f->form = TermFormName(t.form);
  switch (c.level) {
    case CovariateLevel::kPass:
      f->level = "pass";
      break;
    case CovariateLevel::kRoll:
      f->level = "roll";
      break;
    case CovariateLevel::kCampaign:
      f->level = "campaign";
      break;
    case CovariateLevel::kMeasurement:
      f->level = "measurement";
      break;
  }
  const double* p = t.params.data();
  bool up = true;
  std::string fitted;
  // Shape of a wear-rate multiplier from its profile over the covariate's
  // 5th..95th percentiles: monotone (with or without most of the change in
  // the first half: saturating growth / decay) or with an interior extreme.
  auto profile_shape = [&]() {
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
        auto se = f->parameter_std_errors.find("param" + std::to_string(j));
        if (se != f->parameter_std_errors.end() && std::isfinite(se->second)) {
          tol = std::max(tol, 2 * std::exp(t.params[j]) * se->second);
        }
      }
    }
    bool inc = true, dec = true;
    for (size_t i = 1; i < v.size(); ++i) {
      inc = inc && v[i] >= v[i - 1] - tol;
      dec = dec && v[i] <= v[i - 1] + tol;
    }
    up = v.back() > v.front();
    if (inc && dec) {  // flat within the tolerance: monotone in its direction
      inc = up;
      dec = !up;
    }
    if (inc && !dec) {
      if (t.form == TermForm::kBinned && ThresholdShape(v) != nullptr) {
        return std::string(ThresholdShape(v));
      }
      return std::string((v[2] - v[0]) > 0.75 * (v[4] - v[0])
                             ? "saturating_growth"
                             : "increasing");
    }
    if (dec && !inc) {
      return std::string((v[0] - v[2]) > 0.75 * (v[0] - v[4]) ? "decaying"
                                                              : "decreasing");
    }
    if (t.form == TermForm::kBinned) {
      if (const char* th = ThresholdShape(v)) return std::string(th);
    }
    const size_t imax = std::max_element(v.begin(), v.end()) - v.begin();
    const size_t imin = std::min_element(v.begin(), v.end()) - v.begin();
    if (imax > 0 && imax + 1 < v.size()) return std::string("peaked");
    if (imin > 0 && imin + 1 < v.size()) return std::string("valley");
    return std::string(up ? "increasing" : "decreasing");
  };
  const std::string range_text =
      Format("wear-rate multiplier %.3f at the 5th percentile (",
             TermMultiplier(t, lo, nullptr)) +
      Readable(c.name, lo) +
      Format(") and %.3f at the 95th (", TermMultiplier(t, hi, nullptr)) +
      Readable(c.name, hi) + ")";
  switch (t.form) {
    case TermForm::kLogLinear:
    case TermForm::kPower: {
      f->shape = profile_shape();
      if (t.form == TermForm::kLogLinear) {
        f->parameters = {
            {"beta", p[0]}, {"center", t.center}, {"scale", t.scale}};
      } else {
        f->parameters = {{"exponent", p[0]}, {"reference", t.center}};
      }
      fitted = range_text;
      break;
    }
    case TermForm::kSaturating:
    case TermForm::kDecaying: {
      const double lam = std::exp(p[1]);
      f->shape = profile_shape();
      f->parameters = {{"beta", p[0]}, {"lambda", lam}};
      fitted = range_text + ", length scale " + Readable(c.name, lam);
      break;
    }
    case TermForm::kFlag:
      up = p[0] > 0;
      f->shape = up ? "higher_when_on" : "lower_when_on";
      f->parameters = {{"beta", p[0]}, {"multiplier_on", std::exp(p[0])}};
      fitted = Format("wear-rate multiplier %.3f when on", std::exp(p[0]));
      break;
    case TermForm::kBinned: {
      f->shape = profile_shape();
      std::vector<double> m = {1.0};
      for (double b : t.params) m.push_back(std::exp(b));
      for (size_t i = 0; i < m.size(); ++i) {
        f->parameters["bin" + std::to_string(i) + "_multiplier"] = m[i];
      }
      for (size_t i = 0; i < t.edges.size(); ++i) {
        f->parameters["edge" + std::to_string(i)] = t.edges[i];
      }
      if (t.edges.size() == 1) {  // a change point (AddSteps)
        f->shape = m[1] >= 1 ? "step_up" : "step_down";
        fitted = Format("a step: wear-rate multiplier %.3f from ", m[1]) +
                 Readable(c.name, t.edges[0]) + " on, relative to before";
        break;
      }
      fitted = "wear-rate multipliers by quantile bin of the covariate:";
      for (size_t i = 0; i < m.size(); ++i) {
        fitted += Format(" %.3f", m[i]);
        if (i < t.edges.size())
          fitted += " | " + Readable(c.name, t.edges[i]) + " |";
      }
      if (const int j = SingleJump(m);
          j > 0 && f->shape.rfind("threshold", 0) != 0) {
        f->shape = m[j] > m[j - 1] ? "step_up" : "step_down";
        fitted +=
            Format("; a step: %.3f times the rate below ", m[j] / m[j - 1]) +
            Readable(c.name, t.edges[j - 1]) + " from there on";
      }
      break;
    }
    case TermForm::kPerLevel:
      f->shape = "per_level";
      for (size_t i = 0; i < t.params.size(); ++i) {
        f->parameters["level" + std::to_string(i + 1) + "_multiplier"] =
            std::exp(t.params[i]);
      }
      fitted = "wear-rate multipliers";
      f->levels.clear();
      for (size_t i = 0; i < t.params.size(); ++i) {
        const std::string label =
            i + 1 < t.levels.size() ? t.levels[i + 1] : std::to_string(i + 1);
        fitted += Format(" %.3f", std::exp(t.params[i])) + " (" + label + ")";
        // The affected levels (the contract's levels): those whose
        // multiplier is more than 2 standard errors from the reference's 1.
        auto se = f->parameter_std_errors.find("param" + std::to_string(i));
        if (se == f->parameter_std_errors.end() || !std::isfinite(se->second) ||
            std::abs(t.params[i]) > 2 * se->second) {
          f->levels.push_back(label);
        }
      }
      break;
    case TermForm::kCell:
      up = p[0] > 0;
      f->shape = up ? "higher_in_cell" : "lower_in_cell";
      f->parameters = {{"beta", p[0]}, {"multiplier", std::exp(p[0])}};
      fitted = Format("wear-rate multiplier %.3f in the cell", std::exp(p[0]));
      break;
    case TermForm::kRollEffect: break;  // named by diagnosis_roll_family.cc
    case TermForm::kOffsetPerLevel:
      OffsetLevels(t, f, &fitted);
      up = false;
      break;
    case TermForm::kOffsetDecay:
      up = p[0] > 0;
      f->shape = p[0] < 0 ? "reads_low_when_measured_early"
                          : "reads_high_when_measured_early";
      f->parameters = {{"amplitude_um", p[0]}, {"tau", std::exp(p[1])}};
      fitted = Format(
          "measured wear offset %.1f µm right after the campaign, fading with "
          "time constant %.3g",
          p[0], std::exp(p[1]));
      break;
    case TermForm::kOffsetBinned: {
      // Offsets by quantile bin (bin 0 reads as is): a step when one jump
      // between neighbouring bins carries at least 3/4 of the total change.
      std::vector<double> o = {0.0};
      for (double b : t.params) o.push_back(b);
      up = o.back() > o.front();
      double largest = 0;
      bool monotone = true;
      for (size_t i = 1; i < o.size(); ++i) {
        const double jump = o[i] - o[i - 1];
        largest = std::max(largest, std::abs(jump));
        monotone = monotone && (up ? jump >= -1.0 : jump <= 1.0);  // 1 µm slack
      }
      const double total = std::abs(o.back() - o.front());
      f->shape = !monotone                 ? "uneven"
                 : largest >= 0.75 * total ? (up ? "step_up" : "step_down")
                                           : (up ? "increasing" : "decreasing");
      for (size_t i = 0; i < o.size(); ++i) {
        f->parameters["bin" + std::to_string(i) + "_offset_um"] = o[i];
      }
      for (size_t i = 0; i < t.edges.size(); ++i) {
        f->parameters["edge" + std::to_string(i)] = t.edges[i];
      }
      if (t.edges.size() == 1) {  // a change point (AddSteps)
        fitted = Format("a step: measured wear offset %+.1f µm from ", o[1]) +
                 Readable(c.name, t.edges[0]) + " on, relative to before";
        break;
      }
      fitted = "measured wear offsets by quantile bin of the covariate (µm):";
      for (size_t i = 0; i < o.size(); ++i) {
        fitted += Format(" %+.1f", o[i]);
        if (i < t.edges.size())
          fitted += " | " + Readable(c.name, t.edges[i]) + " |";
      }
      break;
    }
    case TermForm::kOffsetLinear:
      up = p[0] > 0;
      f->shape = up ? "increasing" : "decreasing";
      f->parameters = {
          {"slope_um_per_sd", p[0]}, {"center", t.center}, {"scale", t.scale}};
      fitted = Format(
          "measured wear offset of %.1f µm per standard deviation (%.4g)", p[0],
          t.scale);
      break;
  }
  const std::string text = MechanismOf(t, c, up, f);
  f->explanation = text + DescribeScope(t, f) + " Fitted: " + fitted + ".";
}

}  // namespace rollwear::diag
