// The concealed effects of the mill simulator: physics that Wang's law
// (wear = K * F/w * L) leaves out, each acting through one quantity that the
// dataset records. Adding an effect is adding one entry to kEffects.
//
// Wear-rate effects multiply the wear increment of every pass of the roll:
//   dW = K * (F/w) * L * prod_e m_e(pass, roll, campaign state).
// Measurement effects add to what the grinder reads, not to the true wear.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/sim/sim_internal.h"

namespace rollwear::sim {
namespace {

// campaign_growth: the roll surface degrades along the campaign (fire
// cracks, banding, loss of the oxide layer), so each km of strip wears more
// than the one before:  m = 1 + beta * L_before / L_ref.
// This is the mechanism the study gives for under-prediction above ~300 um.
double CampaignGrowth(const EffectContext& c, const double* p) {
  return 1 + p[0] * c.campaign_length_before_m / p[1];
}

// run_in: a freshly ground surface carries grinding roughness peaks that
// wear off quickly:  m = 1 + beta * exp(-L_before / lambda).
double RunIn(const EffectContext& c, const double* p) {
  return 1 + p[0] * std::exp(-c.campaign_length_before_m / p[1]);
}

// warm_measurement: a roll measured before it has cooled down still carries
// thermal expansion (largest at the barrel centre, where the thermal crown
// sits), so the gauge reads less wear. Newton cooling with time constant tau:
//   measured -= A * exp(-cooling_h / tau).
double WarmMeasurement(const EffectContext& c, const double* p) {
  return -p[0] * std::exp(-c.cooling_h / p[1]);
}

// temperature: colder strip carries a harder, more abrasive tertiary scale
// (and a harder surface layer), so wear rises as entry temperature falls:
//   m = exp(beta * (T_ref - T) / 100 K).
double Temperature(const EffectContext& c, const double* p) {
  return std::exp(p[0] * (p[1] - c.pass->temperature_c) / 100.0);
}

// cold_knee: below a knee temperature the strip's scale turns hard and
// abrasive quickly; above it the wear law holds (a threshold, not a trend):
//   m = exp(beta * max(0, t_knee_c - temperature_c) / 10 K).
double ColdKnee(const EffectContext& c, const double* p) {
  return std::exp(p[0] * std::max(0.0, p[1] - c.pass->temperature_c) / 10.0);
}

// lubrication: roll-gap lubrication lowers friction and slip in the bite,
// and with it the abrasive wear beyond what the lower force already gives:
//   m = 1 - gamma * lubrication.
double Lubrication(const EffectContext& c, const double* p) {
  return c.pass->lubrication ? 1 - p[0] : 1;
}

// hardness: Archard's law scales wear with 1/hardness; Wang's law has no
// hardness term, so softer rolls (and rolls ground down into their softer
// inner shell) wear faster:  m = (H_ref / HB)^n.
double Hardness(const EffectContext& c, const double* p) {
  return std::pow(p[0] / c.mount->hardness_hb, p[1]);
}

// speed: higher peripheral speed means more sliding distance per revolution
// in the slip zones and a hotter roll surface:  m = (v / v_ref)^beta.
double Speed(const EffectContext& c, const double* p) {
  return std::pow(c.pass->speed_mps / p[0], p[1]);
}

// supplier_change: from a given day on, the rolls bought come from a new
// supplier (or a new casting batch) whose shell wears faster; the roll-type
// labels stay the same, so only the calendar shows it:
//   m = 1 + gamma  for campaigns started at or after day_step.
double SupplierChange(const EffectContext& c, const double* p) {
  return c.days_since_first_campaign >= p[1] ? 1 + p[0] : 1;
}

// reduction: heavier reductions mean a longer bite with more forward slip,
// so more sliding per metre than F/w alone says:  m = (r / r_ref)^beta,
// r = 1 - h_exit / h_entry.
double ReductionSlip(const EffectContext& c, const double* p) {
  const double r = 1 - c.pass->exit_thickness_mm / c.pass->entry_thickness_mm;
  return std::pow(r / p[0], p[1]);
}

// diameter: a roll ground down to a smaller diameter runs more revolutions
// per km of strip and carries a higher contact pressure, so it wears more
// per unit of Wang's load (which has no diameter):  m = (D_ref / D)^n.
double Diameter(const EffectContext& c, const double* p) {
  return std::pow(p[0] / c.mount->diameter_mm, p[1]);
}

}  // namespace

// gross_errors: a grinder that now and then reads a plausible-looking but
// grossly wrong value (a mis-set zero, a reading taken off the centre, a
// digit typed wrong): a fraction p[0] of the readings is off by a magnitude
// of two forms, half each: uniform on [min_um, max_um], and heavy-tailed
// Pareto (tail index 1.2, scale min_um, capped at 3 max_um: median ~1.8
// min_um, 1 in 10 beyond ~7 min_um), with either sign; a large negative
// error on a lightly worn roll reads negative.
double GrossError(Random* rng, const double* p) {
  if (!(rng->Uniform() < p[0])) return 0;
  const double sign = rng->Uniform() < 0.5 ? -1.0 : 1.0;
  double magnitude;
  if (rng->Uniform() < 0.5) {
    magnitude = rng->Uniform(p[1], p[2]);
  } else {
    const double v = std::max(rng->Uniform(), 1e-12);
    magnitude = std::min(p[1] * std::pow(v, -1 / 1.2), 3 * p[2]);
  }
  return sign * magnitude;
}

namespace {

const std::vector<EffectSpec>& BuildTable() {
  static const std::vector<EffectSpec> kEffects = {
      {"campaign_growth",
       "campaign_length_before_m",
       "wear rate grows along the campaign as the roll surface degrades: "
       "multiplier 1 + beta * campaign_length_before_m / l_ref_m",
       EffectKind::kWearRate,
       2,
       {{{"beta", 0.5}, {"l_ref_m", 100000}, {"", 0}}},
       &CampaignGrowth},
      {"run_in",
       "campaign_length_before_m",
       "a freshly ground surface wears faster until its grinding roughness is "
       "gone: multiplier 1 + beta * exp(-campaign_length_before_m / lambda_m)",
       EffectKind::kWearRate,
       2,
       {{{"beta", 1.5}, {"lambda_m", 10000}, {"", 0}}},
       &RunIn},
      {"warm_measurement",
       "cooling_h",
       "rolls measured while still warm read less wear (thermal expansion "
       "not yet gone): measured -= amplitude_um * exp(-cooling_h / tau_h)",
       EffectKind::kMeasurement,
       2,
       {{{"amplitude_um", 60}, {"tau_h", 6}, {"", 0}}},
       &WarmMeasurement},
      {"temperature",
       "temperature_c",
       "colder strip carries harder, more abrasive scale: multiplier "
       "exp(beta * (t_ref_c - temperature_c) / 100)",
       EffectKind::kWearRate,
       2,
       {{{"beta", 0.5}, {"t_ref_c", 900}, {"", 0}}},
       &Temperature},
      {"cold_knee",
       "temperature_c",
       "below a knee temperature the scale turns abrasive; above it the law "
       "holds: multiplier exp(beta * max(0, t_knee_c - temperature_c) / 10)",
       EffectKind::kWearRate,
       2,
       {{{"beta", 0.15}, {"t_knee_c", 895}, {"", 0}}},
       &ColdKnee},
      {"lubrication",
       "lubrication",
       "roll-gap lubrication reduces abrasive wear: multiplier "
       "1 - gamma * lubrication",
       EffectKind::kWearRate,
       1,
       {{{"gamma", 0.2}, {"", 0}, {"", 0}}},
       &Lubrication},
      {"hardness",
       "hardness_hb",
       "softer rolls wear faster than Wang's law (which ignores hardness) "
       "says: multiplier (h_ref_hb / hardness_hb)^n",
       EffectKind::kWearRate,
       2,
       {{{"h_ref_hb", 560}, {"n", 2}, {"", 0}}},
       &Hardness},
      {"speed",
       "speed_mps",
       "faster rolls slide more and run hotter: multiplier "
       "(speed_mps / v_ref_mps)^beta",
       EffectKind::kWearRate,
       2,
       {{{"v_ref_mps", 10}, {"beta", 0.5}, {"", 0}}},
       &Speed},
      {"supplier_change",
       "started_at",
       "rolls bought from a new supplier from day day_step on wear faster, "
       "with unchanged roll-type labels: multiplier 1 + gamma for campaigns "
       "started on or after day_step (days since the first campaign)",
       EffectKind::kWearRate,
       2,
       {{{"gamma", 0.25}, {"day_step", 45}, {"", 0}}},
       &SupplierChange},
      {"reduction",
       "reduction",
       "heavier reductions slip more in a longer bite: multiplier "
       "(reduction / r_ref)^beta, reduction = 1 - exit / entry thickness",
       EffectKind::kWearRate,
       2,
       {{{"r_ref", 0.2}, {"beta", 0.8}, {"", 0}}},
       &ReductionSlip},
      {"diameter",
       "diameter_mm",
       "reground (smaller) rolls wear more per unit load: multiplier "
       "(d_ref_mm / diameter_mm)^n",
       EffectKind::kWearRate,
       2,
       {{{"d_ref_mm", 700}, {"n", 3}, {"", 0}}},
       &Diameter},
      {"gross_errors",
       "",
       "the grinder reads a fraction of the rolls grossly wrong, either sign: "
       "half off by uniform [min_um, max_um], half by a heavy-tailed Pareto "
       "(index 1.2, scale min_um, capped at 3 max_um); acts through no "
       "recorded quantity",
       EffectKind::kGrossError,
       3,
       {{{"fraction", 0.03}, {"min_um", 30}, {"max_um", 300}}},
       nullptr},
  };
  return kEffects;
}

}  // namespace

const std::vector<EffectSpec>& EffectTable() { return BuildTable(); }

const EffectSpec* FindEffect(const std::string& name) {
  for (const EffectSpec& e : EffectTable()) {
    if (name == e.name) return &e;
  }
  return nullptr;
}

}  // namespace rollwear::sim
