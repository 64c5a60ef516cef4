// The simulator's option checks and its list of effects (old table and
// families), apart from the campaign loop of simulator.cc.
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/sim/sim_internal.h"
#include "core/sim/simulator.h"

namespace rollwear {

using sim::EffectSpec;

bool SimulatorOptions::IsValid(std::string* error) const {
  if (num_campaigns < 1 || num_campaigns > 100000) {
    *error = "num_campaigns must be in 1..100000";
    return false;
  }
  if (!(coils_per_campaign >= 10 && coils_per_campaign <= 2000)) {
    *error = "coils_per_campaign must be in 10..2000";
    return false;
  }
  if (!(missing_measurement_fraction >= 0 &&
        missing_measurement_fraction <= 1)) {
    *error = "missing_measurement_fraction must be in [0, 1]";
    return false;
  }
  if (!(roll_wear_factor_sd >= 0 && roll_wear_factor_sd <= 1)) {
    *error = "roll_wear_factor_sd must be in [0, 1]";
    return false;
  }
  if (!(gross_error_fraction >= 0 && gross_error_fraction <= 0.5)) {
    *error = "gross_error_fraction must be in [0, 0.5]";
    return false;
  }
  std::set<std::string> seen;
  for (const std::string& name : effects) {
    if (sim::FindEffect(name) == nullptr && !sim::IsFamilyName(name)) {
      std::string valid;
      for (const auto& [n, description] : SimulatorEffects()) {
        valid += valid.empty() ? "" : ", ";
        valid += n;
      }
      *error = "unknown effect '" + name + "' (valid: " + valid + ")";
      return false;
    }
    if (!seen.insert(name.substr(0, name.find(':'))).second) {
      *error = "effect '" + name + "' given twice";
      return false;
    }
  }
  if (gross_error_fraction > 0 && seen.count("gross_errors") > 0) {
    *error =
        "gross_error_fraction and the effect gross_errors exclude each "
        "other";
    return false;
  }
  return true;
}

std::vector<std::pair<std::string, std::string>> SimulatorEffects() {
  std::vector<std::pair<std::string, std::string>> out;
  for (const EffectSpec& e : sim::EffectTable()) {
    out.emplace_back(e.name, e.description);
  }
  for (auto& family : sim::FamilyList()) out.push_back(std::move(family));
  return out;
}

}  // namespace rollwear
