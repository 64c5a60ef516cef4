// Shared pieces of the simulator's effect families (sim_families.cc, the
// expressible ones and the table; sim_families_inexpressible.cc, the
// effects no term of the diagnosis vocabulary describes): the formatting
// and truth helpers, the old covariate effects the scoped families
// restrict, and the inexpressible families' draw functions.
// Thread-safety: pure functions; FamilyEffect values are immutable once
// drawn.
#ifndef ROLLWEAR_CORE_SIM_SIM_FAMILIES_INTERNAL_H_
#define ROLLWEAR_CORE_SIM_SIM_FAMILIES_INTERNAL_H_

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <utility>

#include "core/sim/sim_internal.h"

namespace rollwear::sim::families {

inline std::string Fmt(const char* format, double x) {
  char buf[96];
  std::snprintf(buf, sizeof(buf), format, x);
  return buf;
}

inline FamilyEffect Base(const char* name, const char* covariate,
                         std::string form, double strength) {
  FamilyEffect f;
  f.truth.name = name;
  f.truth.covariate = covariate;
  f.truth.form = std::move(form);
  f.truth.strength = strength;
  return f;
}

// The old covariate effects the scoped families restrict: covariate k of
// temperature (colder strip, harder scale), speed, roll hardness (Archard)
// and campaign length, each with its form and strength range.
inline constexpr const char* kScopedCovariates[] = {
    "temperature_c", "speed_mps", "hardness_hb", "campaign_length_before_m"};
inline constexpr const char* kScopedForms[] = {
    "exp(beta (900 - T) / 100)", "(v / 10)^beta", "(560 / HB)^beta",
    "1 + beta L_before / 100 km"};

inline double DrawScopedBeta(int which, Random* rng) {
  return which == 0   ? rng->Uniform(0.6, 1.0)
         : which == 1 ? rng->Uniform(0.6, 1.0)
         : which == 2 ? rng->Uniform(2.5, 4.0)
                      : rng->Uniform(0.5, 0.9);
}

// The multiplier of covariate effect `which` with strength `beta`.
inline double ScopedMultiplier(int which, double beta, const EffectContext& c) {
  switch (which) {
    case 0:
      return std::exp(beta * (900 - c.pass->temperature_c) / 100);
    case 1:
      return std::pow(c.pass->speed_mps / 10, beta);
    case 2:
      return std::pow(560 / c.mount->hardness_hb, beta);
    default:
      return 1 + beta * c.campaign_length_before_m / 1e5;
  }
}

// A scoped family's effect: covariate `which`, acting where `in_scope`
// says (described as "acts only `where`").
template <typename InScopeFn>
FamilyEffect ScopedEffect(const char* name, int which, Random* rng,
                          std::map<std::string, std::string> scope,
                          const std::string& where, InScopeFn in_scope) {
  const double beta = DrawScopedBeta(which, rng);
  FamilyEffect f =
      Base(name, kScopedCovariates[which], kScopedForms[which], beta);
  f.truth.scope = std::move(scope);
  f.truth.parameters = {{"beta", beta}};
  f.truth.description = "the " + std::string(kScopedCovariates[which]) +
                        " effect " + kScopedForms[which] + " acts only " +
                        where + "; elsewhere the wear is Wang's law";
  f.apply = [which, beta, in_scope](const EffectContext& c) {
    return in_scope(c) ? ScopedMultiplier(which, beta, c) : 1.0;
  };
  return f;
}

// The inexpressible families (sim_families_inexpressible.cc), each drawn as
// Draw in sim_families.cc: (variant, strength stream, seed, campaigns).
FamilyEffect InexpressibleOrder(int variant, Random* rng, uint64_t seed,
                                int num_campaigns);
FamilyEffect InexpressibleLubrication(int variant, Random* rng, uint64_t seed,
                                      int num_campaigns);
FamilyEffect InexpressibleNightShift(int variant, Random* rng, uint64_t seed,
                                     int num_campaigns);
FamilyEffect InexpressibleBadRolls(int variant, Random* rng, uint64_t seed,
                                   int num_campaigns);
FamilyEffect InexpressibleRollService(int variant, Random* rng, uint64_t seed,
                                      int num_campaigns);
FamilyEffect InexpressibleCellCovariate(int variant, Random* rng,
                                        uint64_t seed, int num_campaigns);
FamilyEffect InexpressibleInteraction(int variant, Random* rng, uint64_t seed,
                                      int num_campaigns);
FamilyEffect InexpressibleRandomWalk(int variant, Random* rng, uint64_t seed,
                                     int num_campaigns);
FamilyEffect InexpressibleBursts(int variant, Random* rng, uint64_t seed,
                                 int num_campaigns);
FamilyEffect InexpressibleRestart(int variant, Random* rng, uint64_t seed,
                                  int num_campaigns);

}  // namespace rollwear::sim::families

#endif  // ROLLWEAR_CORE_SIM_SIM_FAMILIES_INTERNAL_H_
