// Mill simulator: writes a synthetic hot-strip-mill dataset shaped like the
// rollwear study (F6/F7 finishing stands, top and bottom work rolls, 395
// campaigns, about 51,700 coils, 8 roll types/suppliers, 9 grades), with
// forces from a flow-stress model, regrinds and replacements of physical
// rolls, grinder noise and roll-to-roll scatter. The true wear is Wang's law
// with option-1 coefficients kF[position]*kR[roll type]*kS[grade], optionally
// modified by concealed effects that the baseline model lacks.
//
// Thread-safety: Simulate is a pure function of its options (seeded RNG).
#ifndef ROLLWEAR_CORE_SIM_SIMULATOR_H_
#define ROLLWEAR_CORE_SIM_SIMULATOR_H_

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/dataset/dataset.h"
#include "core/base/status.h"

namespace rollwear {

// The truth of the simulated wear profiles (SimulatorOptions::profiles).
struct SimulatedProfileShape {
  double body_beta2 = 0;         // (u/b)^2 coefficient of the body
  double edge_amplitude = 0;     // A: relative rise at the strip edge
  double edge_decay_mm = 0;      // lambda: width of the edge rise
  double point_noise_sd_um = 0;  // the grinder's noise per profile point
};
struct SimulatorOptions {
  uint64_t seed = 1;
  int num_campaigns = 395;
  // Mean coils per campaign (campaign lengths vary around it).
  double coils_per_campaign = 131;
  // Names from SimulatorEffects(); empty = no concealed effect. A family
  // (sim_families.cc) is NAME (form and strength drawn from the seed) or
  // NAME:K (variant K of its forms/scopes; strength still from the seed).
  std::vector<std::string> effects;
  // Fraction of (campaign, position) measurements missing (gauge faults,
  // not yet ground).
  double missing_measurement_fraction = 0.0;
  // Write profiles.csv: a grinder profile across the barrel for most
  // measured rolls (kProfileShare of them).
  bool profiles = false;
  // Cyclic work-roll shifting (false: every pass at shift 0, same schedule
  // otherwise).
  bool shifting = true;
  // > 0: gross grinder errors on this fraction of the readings, on top of
  // any effect (the gross_errors effect with fraction = this; not with
  // --effect gross_errors as well).
  double gross_error_fraction = 0;
  // > 0: every physical roll wears by its own factor for life (material,
  // supplier batch, heat treatment), lognormal with mean 1 and this sd of
  // its log, drawn from its serial (truth: roll_wear_factor). 0 leaves
  // every other draw of the simulation as it was.
  double roll_wear_factor_sd = 0;

  bool IsValid(std::string* error) const;
};

// A concealed effect and its true parameters.
struct SimulatedEffect {
  std::string name;         // e.g. "campaign_growth"
  std::string covariate;    // canonical column/derived name it acts through
                            // ("" for gross_errors: no recorded quantity)
  std::string description;  // one sentence of physics
  std::map<std::string, double> parameters;
  // Effect families (older effects: form "", strength 0, no scope or
  // levels, expressible): the variant drawn, its size (a multiplier such
  // as 1.3, a beta, or an offset in um; 0 for a null variant), where it
  // applies ({"stand":"F7"}, {"stand":"F7","position":"top"}; empty =
  // everywhere) and the affected levels of a factor (grade, roll type,
  // grinder...).
  std::string form;
  double strength = 0;
  std::map<std::string, std::string> scope;
  std::vector<std::string> levels;
  // false: no candidate term of one recorded quantity can describe it;
  // `mismatch` then says where the residual structure lives ("campaign
  // order", "time", "temperature_c x speed_mps").
  bool expressible = true;
  std::string mismatch;
  // A null variant: data-side change only (a column, stoppages), no
  // change of wear or reading; the diagnosis should stay quiet.
  bool null_effect = false;
};

// Key of one SimulationTruth::noise_free_wear_um entry: the measurement row
// it belongs to.
struct SimulatedMeasurementKey {
  std::string campaign_id;
  int stand = 0;
  Position position = Position::kTop;
};

struct SimulationTruth {
  uint64_t seed = 0;
  std::string law = "wang";
  // True option-1 factors, by label (position "F6/top", roll type, grade).
  std::map<std::string, double> k_position;
  std::map<std::string, double> k_roll_type;
  std::map<std::string, double> k_grade;
  std::vector<SimulatedEffect> effects;
  // Noise-free centre wear for each row of Dataset::measurements (the wear
  // a perfect model of baseline + effects would predict), and the noise
  // floor: mean |measured - noise-free| over all measurements.
  std::vector<double> noise_free_wear_um;
  std::vector<SimulatedMeasurementKey> noise_free_keys;  // same order
  // Same order: the gross grinder error added to the reading (effect
  // gross_errors; 0 for a clean reading, and for every reading without it).
  std::vector<double> gross_error_um;
  // With profiles: the shape they were drawn with and their noise floor
  // (mean |measured - noise-free| over all points).
  bool has_profiles = false;
  SimulatedProfileShape profile_shape;
  double profile_noise_floor_um = 0;
  double noise_floor_um = 0;
  double grinder_noise_sd_um = 0;
  double roll_scatter_sd = 0;  // relative, per physical roll and campaign
  // SimulatorOptions::roll_wear_factor_sd > 0: each roll's lifelong factor.
  std::map<std::string, double> roll_wear_factor;
};

struct Simulation {
  Dataset data;
  SimulationTruth truth;
};

// Names accepted in SimulatorOptions::effects, with a one-line description.
std::vector<std::pair<std::string, std::string>> SimulatorEffects();

StatusOr<Simulation> Simulate(const SimulatorOptions& options);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_SIM_SIMULATOR_H_
