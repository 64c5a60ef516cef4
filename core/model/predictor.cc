#include "core/model/predictor.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string_view>
#include <utility>

#include "core/model/covariates.h"
#include "core/model/term_family.h"

namespace rollwear {

RollWearState MountRoll(const WearModel& model, const std::string& position_label,
                        const std::string& roll_type, double diameter_mm,
                        double hardness_hb, UnixSeconds campaign_started_at,
                        ExtraFields mount_extra, ExtraFields campaign_extra,
                        std::string roll_id) {
  RollWearState s;
  s.roll_id = std::move(roll_id);
  s.position = model.structure.PositionLevel(position_label);
  s.roll_type = model.structure.RollTypeLevel(roll_type);
  s.diameter_mm = diameter_mm;
  s.hardness_hb = hardness_hb;
  s.gradient.assign(model.num_parameters(), 0.0);
  s.campaign_started_at = campaign_started_at;
  const size_t slash = position_label.find('/');
  if (slash != std::string::npos) {
    s.stand = ParseStand(position_label.substr(0, slash));
    Position p;
    if (ParsePosition(position_label.substr(slash + 1), &p)) {
      s.roll_position = static_cast<int>(p);
    }
  }
  s.roll_type_label = roll_type;
  s.mount_extra = std::move(mount_extra);
  s.campaign_extra = std::move(campaign_extra);
  s.top_roll = position_label.size() < 4 ||
               position_label.compare(position_label.size() - 4, 4, "/top") == 0;
  if (model.is_ann()) {
    s.ann = MountRoll(*model.ann, position_label, roll_type, diameter_mm, hardness_hb);
  }
  return s;
}

void TrackProfile(RollWearState* state, const ProfileGrid& grid) {
  state->profile.emplace(grid);
}

namespace {

// Adds a pass's wear to the tracked profile (profile_fit.cc's SumRoll).
void AddPassToProfile(const PassInput& pass, double wear, RollWearState* state) {
  if (!state->profile.has_value()) return;
  state->profile->AddPass(wear, StripCentreMm(state->top_roll, pass.shift_mm),
                          pass.width_mm / 2);
}

// The value of a term on an extra column (a name outside the built-in
// catalog) for this pass: the numeric field, or for a per-level term the
// index of the factor field's label in the term's levels; NaN (multiplier
// 1) when there is none.
double ExtraTermValue(const ModelTerm& t, const PassInput& pass,
                      const RollWearState& state) {
  const ExtraFields* records[] = {&pass.extra, &state.mount_extra,
                                  &state.campaign_extra};
  if (t.form != TermForm::kPerLevel) {
    for (const ExtraFields* r : records) {
      if (const double* v = r->Numeric(t.covariate)) return *v;
    }
    return std::numeric_limits<double>::quiet_NaN();
  }
  std::string_view label;  // no field: the empty cell's level, ""
  for (const ExtraFields* r : records) {
    if (const std::string* l = r->Factor(t.covariate)) {
      label = *l;
      break;
    }
  }
  for (size_t l = 0; l < t.levels.size(); ++l) {
    if (t.levels[l] == label) return static_cast<double>(l);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

double PassTermMultiplier(const WearModel& model, const PassInput& pass,
                          const RollWearState& state) {
  return PassTermEffects(model, pass, state).multiplier;
}

PassTermEffect PassTermEffects(const WearModel& model, const PassInput& pass,
                               const RollWearState& state) {
  PassTermEffect effect;
  if (model.terms.empty()) return effect;
  static const Dataset kNoExtras;
  static const std::vector<CovariateSpec> kCatalog = CovariateCatalog(kNoExtras);
  Pass p;
  p.rolled_at = pass.rolled_at;
  p.force_kn = pass.force_kn;
  p.width_mm = pass.width_mm;
  p.length_m = pass.length_m;
  p.entry_thickness_mm = pass.entry_thickness_mm;
  p.exit_thickness_mm = pass.exit_thickness_mm;
  p.temperature_c = pass.temperature_c;
  p.speed_mps = pass.speed_mps;
  p.lubrication = pass.lubrication;
  p.shift_mm = pass.shift_mm;
  Mount m;
  m.diameter_mm = state.diameter_mm;
  m.hardness_hb = state.hardness_hb;
  Campaign c;
  c.started_at = state.campaign_started_at;
  PassContext ctx;
  ctx.pass = &p;
  ctx.mount = &m;
  ctx.campaign = &c;
  ctx.length_before_m = state.rolled_length_m;
  ctx.coils_before = state.coils;
  double& multiplier = effect.multiplier;
  double roll_factor = 1.0;  // the roll's own factor scales the added wear
  for (const ModelTerm& t : model.terms) {
    if (t.IsMeasurementTerm()) continue;
    if (!t.scope.CoversRoll(state.stand, state.roll_position, state.roll_type_label) ||
        !t.scope.CoversGrade(pass.grade)) {
      continue;  // outside its scope: m = 1
    }
    if (t.form == TermForm::kRollEffect) {
      const int l = RollLevelOf(t, state.roll_id);
      const double level = l < 0 ? std::numeric_limits<double>::quiet_NaN()
                                 : static_cast<double>(l);
      const double m = TermMultiplier(t, level, nullptr);
      multiplier *= m;
      if (FamilyOf(t.form).scales_added_wear()) roll_factor *= m;
      continue;
    }
    // z of a covariate: the catalog's, or an extra column's by the term's
    // own reading (a level index for per_level).
    const auto value_of = [&](const ModelTerm& reading) {
      for (const CovariateSpec& spec : kCatalog) {
        if (spec.name == reading.covariate &&
            spec.level != CovariateLevel::kMeasurement) {
          return CovariateValue(spec, kNoExtras, ctx, 0);
        }
      }
      return ExtraTermValue(reading, pass, state);
    };
    if (!t.scope.gate.empty()) {
      ModelTerm gate;  // the gate covariate read as a number
      gate.covariate = t.scope.gate;
      if (!t.scope.CoversGateValue(value_of(gate))) continue;  // m = 1
    }
    const double z = value_of(t);
    if (t.IsAdditiveTerm()) {
      effect.added_um += TermAddend(t, z, nullptr);
    } else {
      multiplier *= TermMultiplier(t, z, nullptr);
    }
  }
  effect.added_um *= roll_factor;
  return effect;
}

double AddPass(const WearModel& model, const PassInput& pass, RollWearState* state) {
  if (model.is_ann()) {
    // The roll must have been mounted under this model (MountRoll sets the
    // network state); a state of another model gives NaN, never a guess.
    if (!state->ann.has_value()) {
      state->wear_um = std::numeric_limits<double>::quiet_NaN();
      return state->wear_um;
    }
    const double wear = AddPass(*model.ann, pass, &*state->ann);
    state->wear_um = state->ann->wear_um;
    state->coils = state->ann->coils;
    state->rolled_length_m = state->ann->rolled_length_m;
    AddPassToProfile(pass, wear, state);
    return wear;
  }
  const PassLoadInput in{pass.force_kn,           pass.width_mm,
                         pass.length_m,           pass.entry_thickness_mm,
                         pass.exit_thickness_mm,  state->diameter_mm,
                         state->hardness_hb};
  const int grade = model.structure.GradeLevel(pass.grade);
  const auto [multiplier, added_um] = PassTermEffects(model, pass, *state);
  // The additive terms' wear does not depend on K: the gradient (in K's
  // parameters) is the law's part alone.
  const double wear =
      model.PassWear(in, state->position, state->roll_type, grade) *
          multiplier +
      added_um;
  if (static_cast<int>(state->gradient.size()) != model.num_parameters()) {
    state->gradient.assign(model.num_parameters(), 0.0);
  }
  model.AddPassGradient(in, state->position, state->roll_type, grade,
                        state->gradient.data(), multiplier);
  state->wear_um += wear;
  state->coils += 1;
  state->rolled_length_m += pass.length_m;
  AddPassToProfile(pass, wear, state);
  return wear;
}

std::pair<double, double> WearInterval(const WearModel& model,
                                       const RollWearState& state) {
  if (model.is_ann() && state.ann.has_value()) {
    // var = s_members^2 + sigma0^2 + (rho d)^2: the ensemble members'
    // sample variance stands for the network's own uncertainty (a
    // deep-ensemble estimate, Lakshminarayanan et al., NIPS 2017).
    const std::vector<double>& w = state.ann->member_wear_um;
    double var = 0;
    if (w.size() > 1) {
      double mean = 0;
      for (double x : w) mean += x;
      mean /= static_cast<double>(w.size());
      for (double x : w) var += (x - mean) * (x - mean);
      var /= static_cast<double>(w.size() - 1);
    }
    const double d = state.wear_um;
    var += model.noise_sd_um * model.noise_sd_um +
           (model.noise_rel * d) * (model.noise_rel * d);
    const double half = 1.959963984540054 * std::sqrt(var);
    return {d - half, d + half};
  }
  const auto [lo, hi] = model.Interval(state.wear_um, state.gradient.data());
  const double half = WidenForRollFactor(model.terms, state.roll_id,
                                         state.wear_um, (hi - lo) / 2);
  return {state.wear_um - half, state.wear_um + half};
}

}  // namespace rollwear
