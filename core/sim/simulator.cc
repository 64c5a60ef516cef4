// The mill simulator's campaign loop: roll inventory and rotation, passes,
// true wear (Wang's law with option-1 coefficients and the selected
// concealed effects), grinder measurements with noise, regrinding and
// scrapping. Process details live in sim_process.cc, effects in
// sim_effects.cc.
#include "core/sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/sim/sim_internal.h"
#include "core/model/barrel_profile.h"
#include "core/model/wear_law.h"

namespace rollwear {
namespace {

using sim::EffectContext;
using sim::EffectKind;
using sim::EffectSpec;
using sim::MakeRandom;
using sim::RoundTo;
using sim::Stream;

// Noise model of the measured wear:
//   measured = S * W + offsets + e,  S ~ lognormal(mean 1, kRollScatterSigma)
// per physical roll and campaign (roll-to-roll material scatter), e ~ N(0,
// kGrinderNoiseSd) (gauge repeatability on the grinder).
constexpr double kRollScatterSigma = 0.09;
constexpr double kGrinderNoiseSd = 8.0;
// Share of the measured rolls that also get a grinder profile.
constexpr double kProfileShare = 0.85;
// 2025-01-06T06:00:00Z, start of the first campaign.
constexpr UnixSeconds kStartTime = 1736143200;
constexpr int kStands[2] = {6, 7};

struct Roll {
  std::string id;
  int type = 0;
  double new_diameter_mm = 0;
  double diameter_mm = 0;
  double new_hardness_hb = 0;
  UnixSeconds available_at = 0;
  int campaigns = 0;  // campaigns served so far (in this simulation)
  double wear_factor = 1;  // SimulatorOptions::roll_wear_factor_sd
};

std::string Serial(char prefix, int n, int width) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%c%0*d", prefix, width, n);
  return buf;
}

Roll NewRoll(int serial, int type, Random* rng) {
  Roll r;
  r.id = Serial('R', serial, 4);
  r.type = type;
  r.new_diameter_mm =
      RoundTo(rng->Uniform(sim::kNewDiameterMinMm, sim::kNewDiameterMaxMm), 2);
  r.diameter_mm = r.new_diameter_mm;
  r.new_hardness_hb =
      sim::RollTypes()[type].hardness_new_hb + rng->Normal(0, 12);
  return r;
}

// Surface hardness falls as the roll is ground into its working layer.
double HardnessAt(const Roll& r) {
  const double depth_mm = (r.new_diameter_mm - r.diameter_mm) / 2;
  return RoundTo(
      r.new_hardness_hb - sim::RollTypes()[r.type].hardness_slope * depth_mm,
      1);
}

double Preference(int type, int stand) {
  const auto& t = sim::RollTypes()[type];
  return stand == 6 ? t.preference_f6 : t.preference_f7;
}

// The roll shop's choice of a work roll for `stand`: a roll type drawn with
// weight preference * (rolls of that type ready), and of that type the roll
// that has waited longest. With `same_type` >= 0 that type is kept when a
// roll of it is ready (matched pairs). If nothing is ready the roll ready
// first is taken and the campaign start is delayed until then.
int ChooseRoll(const std::vector<Roll>& rolls, const std::vector<bool>& taken,
               int stand, int same_type, UnixSeconds* start, Random* rng) {
  std::array<int, sim::kNumRollTypes> best{};
  std::array<double, sim::kNumRollTypes> weight{};
  best.fill(-1);
  int earliest = -1;
  for (int i = 0; i < static_cast<int>(rolls.size()); ++i) {
    const Roll& r = rolls[i];
    if (taken[i] || Preference(r.type, stand) <= 0) continue;
    if (earliest < 0 || r.available_at < rolls[earliest].available_at) {
      earliest = i;
    }
    if (r.available_at > *start) continue;
    weight[r.type] += Preference(r.type, stand);
    if (best[r.type] < 0 || r.available_at < rolls[best[r.type]].available_at) {
      best[r.type] = i;
    }
  }
  if (same_type >= 0 && best[same_type] >= 0) return best[same_type];
  double total = 0;
  for (double w : weight) total += w;
  if (total <= 0) {
    *start = std::max(*start, rolls[earliest].available_at);
    return earliest;
  }
  return best[sim::Categorical(rng, weight.data(), sim::kNumRollTypes)];
}

// An effect switched on, with its parameter values as the array its Apply
// function reads.
struct ActiveEffect {
  const EffectSpec* spec;
  std::array<double, sim::kMaxEffectParameters> parameters{};
};

// One simulation in progress: the roll shop's inventory, the dataset being
// written and the truth. Run() simulates the campaigns in order; every
// campaign draws from its own random streams (sim::Stream).
class MillRun {
 public:
  MillRun(const SimulatorOptions& options, Simulation* out)
      : options_(options), data_(out->data), truth_(out->truth) {
    grade_index_.fill(-1);
    type_index_.fill(-1);
  }

  void Run();

 private:
  void InitTruthAndEffects();
  void InitFamilies();
  // Switches on an effect of the old table (its first parameter replaced
  // by *first_parameter when given).
  void Activate(const EffectSpec& e, const double* first_parameter);
  // With a stoppages family: idle hours after some coils of campaign c.
  void AddStoppages(int c, std::vector<sim::CoilPlan>* coils) const;
  void BuildInventory();
  // Draws the roll's lifelong wear factor from its own stream (options'
  // roll_wear_factor_sd; 1 when 0) and records it in the truth.
  void AssignWearFactor(int serial, Roll* roll);
  // Chooses the four work rolls (mounted_); may delay *start until enough
  // rolls are ready.
  void ChooseRolls(UnixSeconds* start, Random* rng);
  void AddMounts(int campaign);
  // Appends the passes of `coils`, the first rolled at *t, and returns the
  // noise-free wear per sim slot (before measurement effects); *t ends as
  // the time the last tail leaves F7.
  std::array<double, 4> RollCoils(int campaign, UnixSeconds start,
                                  const std::vector<sim::CoilPlan>& coils,
                                  UnixSeconds* t);
  Pass MakePass(int campaign, int coil_index, int seq, UnixSeconds t,
                const sim::CoilPlan& coil, int stand) const;
  void MeasureAndRegrind(int campaign, const std::array<double, 4>& wear_um);
  // The grinder's profile of the roll in `slot`, measured with the centre
  // reading (same roll scatter and measurement offset, its own noise per
  // point).
  void AddProfile(int campaign, int slot, UnixSeconds measured_at,
                  double scatter, double offset_um, Random* rng);

  const Mount& MountOf(int slot) const {
    return data_.mounts[first_mount_ + slot];
  }
  const sim::RollTypeSpec& TypeOf(int slot) const {
    return sim::RollTypes()[rolls_[mounted_[slot]].type];
  }

  const SimulatorOptions& options_;
  Dataset& data_;
  SimulationTruth& truth_;
  std::vector<ActiveEffect> rate_effects_;
  std::vector<ActiveEffect> measurement_effects_;
  std::vector<ActiveEffect> gross_effects_;
  // Effect families (sim_families.cc), applied after the effects above.
  std::vector<sim::FamilyEffect> families_;
  // Stoppages inside campaigns (the family that asks for them, or null).
  const sim::FamilyEffect* stoppages_ = nullptr;
  // Per family: its text column's index in measurement_extra (-1: none).
  std::vector<int> column_of_;
  std::vector<Roll> rolls_;
  int next_serial_ = 1;
  std::array<int, sim::kNumGrades> grade_index_{};    // -> Dataset::grades
  std::array<int, sim::kNumRollTypes> type_index_{};  // -> Dataset::roll_types
  // The current campaign: roll index per sim slot, first mount row.
  std::array<int, 4> mounted_{};
  size_t first_mount_ = 0;
  double abs_noise_sum_ = 0;
  // With profiles: this campaign's strips on each sim slot, and the sums
  // of the profile noise floor.
  std::array<std::vector<sim::StripTrace>, 4> traces_;
  double profile_abs_noise_sum_ = 0;
  size_t profile_points_ = 0;
};

void MillRun::InitTruthAndEffects() {
  truth_.seed = options_.seed;
  truth_.law = WearLawName(WearLaw::kWang);
  truth_.grinder_noise_sd_um = kGrinderNoiseSd;
  truth_.roll_scatter_sd = kRollScatterSigma;
  if (options_.profiles) {
    truth_.has_profiles = true;
    truth_.profile_shape = sim::DrawProfileShape(options_.seed);
  }
  for (int stand : kStands) {
    for (Position p : {Position::kTop, Position::kBottom}) {
      truth_.k_position[RollPositionName(stand, p)] =
          sim::kPositionFactor[sim::SimSlot(stand, p)];
    }
  }
  for (const auto& t : sim::RollTypes()) {
    truth_.k_roll_type[t.label] = t.k_roll_type;
  }
  for (const auto& g : sim::Grades()) truth_.k_grade[g.label] = g.k_grade;

  InitFamilies();
  for (const std::string& name : options_.effects) {
    const EffectSpec* e = sim::FindEffect(name);
    if (e != nullptr) Activate(*e, nullptr);  // else a family
  }
  if (options_.gross_error_fraction > 0) {
    Activate(*sim::FindEffect("gross_errors"), &options_.gross_error_fraction);
  }
  // Families after the old effects in the truth, in the order given.
  for (const sim::FamilyEffect& f : families_) truth_.effects.push_back(f.truth);
}

void MillRun::Activate(const EffectSpec& e, const double* first_parameter) {
  ActiveEffect active{&e, {}};
  SimulatedEffect out;
  out.name = e.name;
  out.covariate = e.covariate;
  out.description = e.description;
  for (int i = 0; i < e.num_parameters; ++i) {
    active.parameters[i] = i == 0 && first_parameter != nullptr
                               ? *first_parameter
                               : e.parameters[i].value;
    out.parameters[e.parameters[i].name] = active.parameters[i];
  }
  (e.kind == EffectKind::kWearRate      ? rate_effects_
   : e.kind == EffectKind::kMeasurement ? measurement_effects_
                                        : gross_effects_)
      .push_back(active);
  truth_.effects.push_back(std::move(out));
}

void MillRun::InitFamilies() {
  for (const std::string& name : options_.effects) {
    if (sim::FindEffect(name) != nullptr) continue;
    families_.push_back(
        sim::DrawFamily(name, options_.seed, options_.num_campaigns));
  }
  for (const sim::FamilyEffect& f : families_) {
    if (f.stoppage_probability > 0 && stoppages_ == nullptr) stoppages_ = &f;
    column_of_.push_back(-1);
    if (f.column.empty()) continue;
    ExtraColumns& x = data_.measurement_extra;
    std::string name = f.column;  // a second family's column gets "_2"
    while (std::find(x.factor_names.begin(), x.factor_names.end(), name) !=
           x.factor_names.end()) {
      name += "_2";
    }
    column_of_.back() = static_cast<int>(x.factor_names.size());
    x.factor_names.push_back(name);
    x.factor_levels.push_back(f.column_levels);
    x.factor.emplace_back();
  }
}

void MillRun::AssignWearFactor(int serial, Roll* roll) {
  if (!(options_.roll_wear_factor_sd > 0)) return;
  Random rng = MakeRandom(options_.seed, Stream::kRollWearFactor,
                          static_cast<uint64_t>(serial));
  roll->wear_factor = sim::LogNormalMeanOne(&rng, options_.roll_wear_factor_sd);
  truth_.roll_wear_factor[roll->id] = roll->wear_factor;
}

// Roll inventory: 12..16 rolls per type, at diameters spread over their
// working layer (a shop in steady state).
void MillRun::BuildInventory() {
  Random rng = MakeRandom(options_.seed, Stream::kInventory, 0);
  for (int t = 0; t < sim::kNumRollTypes; ++t) {
    const int n = 12 + static_cast<int>(rng.Below(5));
    for (int i = 0; i < n; ++i) {
      const int serial = next_serial_++;
      Roll r = NewRoll(serial, t, &rng);
      AssignWearFactor(serial, &r);
      r.diameter_mm =
          RoundTo(rng.Uniform(sim::kScrapDiameterMm + 4, r.new_diameter_mm), 2);
      rolls_.push_back(std::move(r));
    }
  }
}

// F7 (premium rolls) first, then F6; the bottom roll is of the top roll's
// type in 85% of the changes (matched pairs).
void MillRun::ChooseRolls(UnixSeconds* start, Random* rng) {
  std::vector<bool> taken(rolls_.size(), false);
  for (int stand : {7, 6}) {
    const int top = ChooseRoll(rolls_, taken, stand, -1, start, rng);
    taken[top] = true;
    const int pair_type = rng->Uniform() < 0.85 ? rolls_[top].type : -1;
    const int bottom = ChooseRoll(rolls_, taken, stand, pair_type, start, rng);
    taken[bottom] = true;
    mounted_[sim::SimSlot(stand, Position::kTop)] = top;
    mounted_[sim::SimSlot(stand, Position::kBottom)] = bottom;
  }
}

// Mount rows in sim-slot order (F6 top, F6 bottom, F7 top, F7 bottom).
void MillRun::AddMounts(int campaign) {
  first_mount_ = data_.mounts.size();
  for (int stand : kStands) {
    for (Position p : {Position::kTop, Position::kBottom}) {
      const Roll& r = rolls_[mounted_[sim::SimSlot(stand, p)]];
      Mount m;
      m.campaign = campaign;
      m.stand = stand;
      m.position = p;
      m.roll_id = r.id;
      if (type_index_[r.type] < 0) {
        type_index_[r.type] =
            Dataset::Intern(&data_.roll_types, sim::RollTypes()[r.type].label);
      }
      m.roll_type = type_index_[r.type];
      m.diameter_mm = r.diameter_mm;
      m.hardness_hb = HardnessAt(r);
      data_.mounts.push_back(std::move(m));
    }
  }
}

Pass MillRun::MakePass(int campaign, int coil_index, int seq, UnixSeconds t,
                       const sim::CoilPlan& coil, int stand) const {
  const bool f7 = stand == 7;
  Pass pass;
  pass.campaign = campaign;
  pass.coil = coil_index;
  pass.seq = seq;
  pass.rolled_at = t;
  pass.grade = grade_index_[coil.grade];
  pass.stand = stand;
  pass.width_mm = coil.width_mm;
  pass.entry_thickness_mm = f7 ? coil.h6_mm : coil.h5_mm;
  pass.exit_thickness_mm = f7 ? coil.h7_mm : coil.h6_mm;
  // L = m / (rho * w * h_exit).
  pass.length_m = RoundTo(coil.mass_t * 1000 /
                              (sim::kSteelDensity * coil.width_mm * 1e-3 *
                               pass.exit_thickness_mm * 1e-3),
                          1);
  pass.temperature_c = f7 ? coil.t7_c : coil.t6_c;
  pass.speed_mps = f7 ? coil.v7_mps : coil.v6_mps;
  pass.lubrication = coil.lubrication;
  pass.shift_mm = f7 ? coil.shift7_mm : coil.shift6_mm;
  // The force model sees the mean diameter and modulus of the roll pair.
  const int top = sim::SimSlot(stand, Position::kTop);
  const int bottom = sim::SimSlot(stand, Position::kBottom);
  const double young = 0.5 * (TypeOf(top).young_gpa + TypeOf(bottom).young_gpa);
  const double diameter =
      0.5 * (MountOf(top).diameter_mm + MountOf(bottom).diameter_mm);
  pass.force_kn =
      RoundTo(sim::RollForceKn(sim::Grades()[coil.grade], pass.width_mm,
                               pass.entry_thickness_mm, pass.exit_thickness_mm,
                               pass.temperature_c, pass.speed_mps, diameter,
                               young, pass.lubrication),
              1);
  return pass;
}

// Each pass adds K * Load * prod(effect multipliers) to the two rolls of its
// stand, K = kF[position] * kR[roll type] * kS[grade] (option 1), Load from
// Wang's law on the recorded (rounded) row.
std::array<double, 4> MillRun::RollCoils(
    int campaign, UnixSeconds start, const std::vector<sim::CoilPlan>& coils,
    UnixSeconds* t) {
  std::array<double, 4> wear_um{};
  std::array<double, 2> length_before_m{};  // per stand
  for (std::vector<sim::StripTrace>& t : traces_) t.clear();
  for (int i = 0; i < static_cast<int>(coils.size()); ++i) {
    const sim::CoilPlan& coil = coils[i];
    const sim::GradeSpec& grade = sim::Grades()[coil.grade];
    if (grade_index_[coil.grade] < 0) {
      grade_index_[coil.grade] = Dataset::Intern(&data_.grades, grade.label);
    }
    const int coil_index = static_cast<int>(data_.coil_ids.size());
    data_.coil_ids.push_back(Serial('H', coil_index + 1, 7));
    for (int s = 0; s < 2; ++s) {
      const int stand = kStands[s];
      const Pass pass = MakePass(campaign, coil_index, i + 1, *t, coil, stand);
      for (Position p : {Position::kTop, Position::kBottom}) {
        const int slot = sim::SimSlot(stand, p);
        const Mount& m = MountOf(slot);
        const PassLoadInput in{pass.force_kn,          pass.width_mm,
                               pass.length_m,          pass.entry_thickness_mm,
                               pass.exit_thickness_mm, m.diameter_mm,
                               m.hardness_hb};
        double k = sim::kPositionFactor[slot] * TypeOf(slot).k_roll_type *
                   grade.k_grade;
        EffectContext ctx;
        ctx.pass = &pass;
        ctx.mount = &m;
        ctx.campaign_length_before_m = length_before_m[s];
        ctx.coils_before = i;
        ctx.coils_since_stop = coil.coils_since_stop;
        ctx.hours_since_mount = (*t - start) / 3600.0;
        ctx.days_since_first_campaign = (start - kStartTime) / 86400.0;
        for (const ActiveEffect& e : rate_effects_) {
          k *= e.spec->apply(ctx, e.parameters.data());
        }
        double added_um = 0;  // the families' wear per pass (kWearAdded)
        if (!families_.empty()) {
          ctx.campaign = campaign;
          ctx.num_campaigns = options_.num_campaigns;
          ctx.slot = slot;
          ctx.grade = coil.grade;
          ctx.roll_type = rolls_[mounted_[slot]].type;
          ctx.roll_campaigns_before = rolls_[mounted_[slot]].campaigns;
          for (const sim::FamilyEffect& f : families_) {
            if (f.kind == EffectKind::kWearRate && f.apply) k *= f.apply(ctx);
            if (f.kind == EffectKind::kWearAdded && f.apply)
              added_um += f.apply(ctx);
          }
        }
        const double pass_wear_um = k * BaseLoad(WearLaw::kWang, in) + added_um;
        wear_um[slot] += pass_wear_um;
        if (options_.profiles) {
          traces_[slot].push_back(
              {pass_wear_um, StripCentreMm(p == Position::kTop, pass.shift_mm),
               pass.width_mm / 2});
        }
      }
      length_before_m[s] += pass.length_m;
      data_.passes.push_back(pass);
    }
    // Next head in after this tail leaves F7 (strip speed v (1 + f)).
    const double tail_s =
        data_.passes.back().length_m / (coil.v7_mps * (1 + coil.slip7));
    const bool last = i + 1 == static_cast<int>(coils.size());
    *t +=
        static_cast<UnixSeconds>(std::lround(tail_s + (last ? 0 : coil.gap_s)));
  }
  return wear_um;
}

// Grinder measurements, regrind and scrapping after the campaign. Cooling
// time before the measurement: a campaign-level backlog (lognormal, median
// 7 h) times a per-roll factor, kept within 1..48 h.
void MillRun::AddProfile(int campaign, int slot, UnixSeconds measured_at,
                         double scatter, double offset_um, Random* rng) {
  const Mount& m = MountOf(slot);
  const SimulatedProfileShape& shape = truth_.profile_shape;
  for (const auto& [x_mm, wear_um] :
       sim::TrueProfile(shape, traces_[slot])) {
    ProfilePoint p;
    p.campaign = campaign;
    p.stand = m.stand;
    p.position = m.position;
    p.roll_id = m.roll_id;
    p.measured_at = measured_at;
    p.x_mm = x_mm;
    p.wear_um = RoundTo(scatter * wear_um + offset_um +
                            rng->Normal(0, shape.point_noise_sd_um),
                        1);
    profile_abs_noise_sum_ += std::fabs(p.wear_um - (wear_um + offset_um));
    ++profile_points_;
    data_.profile_points.push_back(std::move(p));
  }
}

void MillRun::MeasureAndRegrind(int campaign,
                                const std::array<double, 4>& wear_um) {
  const uint64_t seed = options_.seed;
  const Campaign& cp = data_.campaigns[campaign];
  Random cooling_rng = MakeRandom(seed, Stream::kCooling, campaign);
  Random scatter_rng = MakeRandom(seed, Stream::kScatter, campaign);
  Random grinder_rng = MakeRandom(seed, Stream::kGrinder, campaign);
  Random missing_rng = MakeRandom(seed, Stream::kMissing, campaign);
  Random regrind_rng = MakeRandom(seed, Stream::kRegrind, campaign);
  Random gross_rng = MakeRandom(seed, Stream::kGross, campaign);
  Random profile_rng = MakeRandom(seed, Stream::kProfile, campaign + 1);
  Random column_rng = MakeRandom(seed, Stream::kColumn, campaign);
  const double backlog_h = 7 * std::exp(cooling_rng.Normal(0, 0.8));
  for (int slot = 0; slot < 4; ++slot) {
    const Mount& m = MountOf(slot);
    Roll& roll = rolls_[mounted_[slot]];
    const double cooling_h = std::clamp(
        backlog_h * std::exp(cooling_rng.Normal(0, 0.25)), 1.0, 48.0);
    const UnixSeconds measured_at =
        cp.ended_at + static_cast<UnixSeconds>(std::lround(cooling_h * 3600));
    const double scatter =
        sim::LogNormalMeanOne(&scatter_rng, kRollScatterSigma);
    const double grinder = grinder_rng.Normal(0, kGrinderNoiseSd);
    const bool missing =
        missing_rng.Uniform() < options_.missing_measurement_fraction;

    // Measurement-side effects see the recorded cooling time.
    EffectContext ctx;
    ctx.mount = &m;
    ctx.cooling_h = (measured_at - cp.ended_at) / 3600.0;
    double offset_um = 0;
    for (const ActiveEffect& e : measurement_effects_) {
      offset_um += e.spec->apply(ctx, e.parameters.data());
    }
    ctx.campaign = campaign;
    ctx.num_campaigns = options_.num_campaigns;
    ctx.slot = slot;
    std::vector<int> levels(data_.measurement_extra.factor.size(), -1);
    for (size_t i = 0; i < families_.size(); ++i) {
      const sim::FamilyEffect& f = families_[i];
      ctx.column_level = -1;
      if (column_of_[i] >= 0) {
        ctx.column_level = levels[column_of_[i]] =
            sim::Categorical(&column_rng, f.column_shares.data(),
                             static_cast<int>(f.column_shares.size()));
      }
      if (f.kind == EffectKind::kMeasurement && f.apply) {
        offset_um += f.apply(ctx);
      }
    }
    const double true_wear_um = scatter * roll.wear_factor * wear_um[slot];
    double gross_um = 0;
    for (const ActiveEffect& e : gross_effects_) {
      gross_um += sim::GrossError(&gross_rng, e.parameters.data());
    }
    if (!missing) {
      Measurement meas;
      meas.campaign = campaign;
      meas.stand = m.stand;
      meas.position = m.position;
      meas.roll_id = m.roll_id;
      meas.measured_at = measured_at;
      meas.wear_center_um =
          RoundTo(std::max(1.0, true_wear_um + offset_um + grinder) + gross_um,
                  1);
      const double noise_free = roll.wear_factor * wear_um[slot] + offset_um;
      abs_noise_sum_ += std::fabs(meas.wear_center_um - noise_free);
      truth_.noise_free_wear_um.push_back(noise_free);
      truth_.noise_free_keys.push_back({cp.id, m.stand, m.position});
      truth_.gross_error_um.push_back(gross_um);
      data_.measurements.push_back(std::move(meas));
      for (size_t i = 0; i < levels.size(); ++i) {
        data_.measurement_extra.factor[i].push_back(levels[i]);
      }
      if (options_.profiles && profile_rng.Uniform() < kProfileShare) {
        AddProfile(campaign, slot, measured_at, scatter * roll.wear_factor, offset_um,
                   &profile_rng);
      }
    }

    // Regrind: remove the wear plus a safety stock of 0.2..0.6 mm on the
    // radius; a roll below its scrap diameter is replaced by a new one.
    const double safety_mm = regrind_rng.Uniform(0.2, 0.6);
    roll.diameter_mm =
        RoundTo(roll.diameter_mm - 2 * (true_wear_um * 1e-3 + safety_mm), 2);
    roll.available_at = measured_at + static_cast<UnixSeconds>(
                                          regrind_rng.Uniform(3600, 3 * 3600));
    roll.campaigns += 1;
    if (roll.diameter_mm < sim::kScrapDiameterMm) {
      const UnixSeconds ready = roll.available_at;
      const int serial = next_serial_++;
      roll = NewRoll(serial, roll.type, &regrind_rng);
      AssignWearFactor(serial, &roll);
      roll.available_at = ready;
    }
  }
}

void MillRun::AddStoppages(int c, std::vector<sim::CoilPlan>* coils) const {
  if (stoppages_ == nullptr) return;
  Random rng = MakeRandom(options_.seed, Stream::kStoppage, c);
  for (size_t i = 0; i + 1 < coils->size(); ++i) {
    if (rng.Uniform() < stoppages_->stoppage_probability) {
      (*coils)[i].gap_s += 3600 * rng.Uniform(stoppages_->stoppage_min_h,
                                              stoppages_->stoppage_max_h);
    }
  }
}

void MillRun::Run() {
  InitTruthAndEffects();
  BuildInventory();
  const size_t expected_passes = static_cast<size_t>(
      options_.num_campaigns * options_.coils_per_campaign * 2 * 1.1);
  data_.passes.reserve(expected_passes);
  data_.coil_ids.reserve(expected_passes / 2);
  data_.campaigns.reserve(options_.num_campaigns);

  UnixSeconds start = kStartTime;
  for (int c = 0; c < options_.num_campaigns; ++c) {
    Random schedule_rng = MakeRandom(options_.seed, Stream::kSchedule, c);
    Random choice_rng = MakeRandom(options_.seed, Stream::kRollChoice, c);
    Random timing_rng = MakeRandom(options_.seed, Stream::kTiming, c);
    const sim::CampaignPlan plan =
        sim::PlanCampaign(options_.coils_per_campaign, &schedule_rng);
    std::vector<sim::CoilPlan> coils = sim::PlanCoils(plan, &schedule_rng);
    if (!options_.shifting) {
      for (sim::CoilPlan& coil : coils) coil.shift6_mm = coil.shift7_mm = 0;
    }
    AddStoppages(c, &coils);
    sim::CountCoilsSinceStop(&coils);
    ChooseRolls(&start, &choice_rng);
    AddMounts(c);

    Campaign campaign;
    campaign.id = Serial('C', c + 1, 4);
    campaign.started_at = start;
    // First head in 5..15 min after the change; rolls out 2..8 min after
    // the last tail.
    UnixSeconds t =
        start + static_cast<UnixSeconds>(timing_rng.Uniform(300, 900));
    const std::array<double, 4> wear_um = RollCoils(c, start, coils, &t);
    campaign.ended_at =
        t + static_cast<UnixSeconds>(timing_rng.Uniform(120, 480));
    data_.campaigns.push_back(campaign);
    MeasureAndRegrind(c, wear_um);
    // Roll change: 20..40 min.
    start = campaign.ended_at +
            static_cast<UnixSeconds>(timing_rng.Uniform(20 * 60, 40 * 60));
  }
  truth_.noise_floor_um = data_.measurements.empty()
                              ? 0
                              : abs_noise_sum_ / data_.measurements.size();
  if (profile_points_ > 0) {
    truth_.profile_noise_floor_um = profile_abs_noise_sum_ / profile_points_;
  }
}

}  // namespace

StatusOr<Simulation> Simulate(const SimulatorOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) return Status::InvalidArgument(error);
  Simulation result;
  MillRun(options, &result).Run();
  return result;
}

}  // namespace rollwear
