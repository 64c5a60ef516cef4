// The simulator's inexpressible effect families (sim_families.cc has the
// table and the others): effects no single recorded quantity describes, on
// which the diagnosis must answer "located, unexplained" with the right
// location and never a physics name. Each FamilyTruth::mismatch says where
// the mismatch lives (docs/diagnosis.md, "Simulator effect families").
// Thread-safety: pure functions (each draws from the Random it is given).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/model/covariates.h"
#include "core/sim/sim_families_internal.h"

namespace rollwear::sim::families {
namespace {

FamilyEffect Inexpressible(const char* name, std::string form, double strength,
                           std::string mismatch) {
  FamilyEffect f = Base(name, "", std::move(form), strength);
  f.truth.expressible = false;
  f.truth.mismatch = std::move(mismatch);
  return f;
}

}  // namespace

// inexpressible_order: a hard grade (kS >= 1.24) rolled soon after the roll
// change wears more: x(1 + s) within the first N coils (step) or
// x(1 + s exp(-coils_before / N)) (decay). Lives in campaign order x grade.
FamilyEffect InexpressibleOrder(int variant, Random* rng, uint64_t, int) {
  const bool decay = variant % 2 == 1;
  const double s = rng->Uniform(0.6, 1.0);
  const double n = rng->Uniform(20, 35);
  FamilyEffect f =
      Inexpressible("inexpressible_order", decay ? "decay" : "step", s,
                    "campaign order x grade");
  f.truth.parameters = {{"s", s}, {"n_coils", n}};
  f.truth.levels = {"HSLA420", "DP600", "API-X65", "API-X70"};
  f.truth.description =
      "a hard grade rolled soon after the roll change (first ~" +
      Fmt("%.0f", n) + " coils) wears the fresh surface more; its wear " +
      "depends on where in the campaign it comes";
  f.apply = [decay, s, n](const EffectContext& c) {
    if (Grades()[c.grade].k_grade < 1.24) return 1.0;
    if (decay) return 1 + s * std::exp(-c.coils_before / n);
    return c.coils_before < n ? 1 + s : 1.0;
  };
  return f;
}

// inexpressible_lubrication: one of the old covariate effects (temperature,
// speed, hardness, campaign length: variant k % 4) on the passes rolled
// without roll-gap lubrication only (variant k / 4 == 1: with it only). The
// vocabulary scopes a term by stand, position, roll type or grade, never by
// the lubrication flag: an unscoped term of the covariate fits it with a
// tiny p-value, and only its scale differing between lubricated and dry
// passes says it is not the right description. Lives in covariate x
// lubrication.
FamilyEffect InexpressibleLubrication(int variant, Random* rng, uint64_t, int) {
  const int which = variant % 4;
  const bool on = variant / 4 % 2 == 1;
  FamilyEffect f = ScopedEffect(
      "inexpressible_lubrication", which, rng, {},
      on ? "on lubricated passes" : "on passes rolled without lubrication",
      [on](const EffectContext& c) { return c.pass->lubrication == on; });
  f.truth.expressible = false;
  f.truth.covariate = "";  // no one covariate describes it
  f.truth.mismatch = std::string(kScopedCovariates[which]) + " x lubrication";
  return f;
}

// inexpressible_night_shift: coils rolled between 22:00 and 06:00 (UTC)
// wear x(1 + s), s 0.15..0.35 (variant 0), or x1/(1 + s) (variant 1): a
// night crew, the cooling water's temperature at night. Only the time of
// day follows it, which no term of the vocabulary is about.
FamilyEffect InexpressibleNightShift(int variant, Random* rng, uint64_t, int) {
  const bool more = variant % 2 == 0;
  const double s = rng->Uniform(0.15, 0.35);
  FamilyEffect f = Inexpressible(
      "inexpressible_night_shift",
      more ? "x(1 + s) 22-06 h" : "x1/(1 + s) 22-06 h", s, "time of day");
  f.truth.parameters = {{"s", s}};
  f.truth.description =
      std::string("coils rolled between 22:00 and 06:00 wear ") +
      (more ? "more" : "less") + " (a factor " +
      Fmt("%.2f", more ? 1 + s : 1 / (1 + s)) +
      "); no recorded quantity but the time of day follows it";
  const double m = more ? 1 + s : 1 / (1 + s);
  f.apply = [m](const EffectContext& c) {
    const int64_t hour = (c.pass->rolled_at % 86400 + 86400) % 86400 / 3600;
    return hour >= 22 || hour < 6 ? m : 1.0;
  };
  return f;
}

// inexpressible_bad_rolls: about one physical roll in ten (picked by its
// serial, roll_id, with a salt drawn from the seed) wears x(1.25..1.45)
// whenever it is mounted, while its recorded hardness and diameter are
// those of its type (a bad heat treatment). Nothing recorded but the
// serial follows it.
FamilyEffect InexpressibleBadRolls(int, Random* rng, uint64_t, int) {
  const double m = rng->Uniform(1.25, 1.45);
  const uint64_t salt = rng->Below(1u << 30);
  FamilyEffect f =
      Inexpressible("inexpressible_bad_rolls", "multiplier", m, "roll_id");
  f.truth.parameters = {{"multiplier", m}};
  f.truth.description =
      "about one roll in ten (by serial) wears " + Fmt("%.2f", m) +
      " times the wear law whenever mounted; its hardness and "
      "diameter are as recorded";
  f.apply = [m, salt](const EffectContext& c) {
    uint64_t h = 14695981039346656037ull ^ salt;  // FNV-1a of the serial
    for (char ch : c.mount->roll_id)
      h = (h ^ static_cast<unsigned char>(ch)) * 1099511628211ull;
    return (h >> 17) % 10 == 0 ? m : 1.0;
  };
  return f;
}

// inexpressible_roll_service: a roll wears more the longer it has served:
// x(1 + s n), s 0.025..0.045 (variant 0), or x(1 + s) once n >= 3, s
// 0.2..0.35 (variant 1), n its earlier campaigns in the simulation (a roll
// ground into a softer layer than its recorded hardness shows, a fatigued
// surface). Rolls serve in turn, so n follows the calendar; only the serials
// (roll_id) and the campaign order say how long a roll has served, which
// the data format names no quantity for.
FamilyEffect InexpressibleRollService(int variant, Random* rng, uint64_t, int) {
  const bool linear = variant % 2 == 0;
  const double s =
      linear ? rng->Uniform(0.025, 0.045) : rng->Uniform(0.2, 0.35);
  FamilyEffect f = Inexpressible("inexpressible_roll_service",
                                 linear ? "x(1 + s n)" : "x(1 + s) for n >= 3",
                                 s, kRollCampaignsBeforeName);
  f.truth.parameters = {{"s", s}};
  f.truth.description =
      linear ? "a roll wears " + Fmt("%.3f", s) +
                   " more per earlier campaign it served (by serial); no "
                   "recorded quantity but the roll's history follows it"
             : "a roll that has served 3 or more campaigns wears a factor " +
                   Fmt("%.2f", 1 + s) +
                   " more; no recorded quantity but the roll's history "
                   "follows it";
  f.apply = [linear, s](const EffectContext& c) {
    const int n = c.roll_campaigns_before;
    return linear ? 1 + s * n : (n >= 3 ? 1 + s : 1.0);
  };
  return f;
}

// inexpressible_cell_covariate: one of the old covariate effects
// (temperature, speed, hardness, campaign length: variant k % 4, strength
// as the scoped families) on one roll type at one stand only (F7 for
// k / 4 even, F6 otherwise; the type, of the four used at both stands, is
// drawn). A covariate term scoped to a stand and a roll type at once is not
// in the diagnosis's vocabulary: a cell takes the effect's mean there (or
// its twin at the other stand does), a term on the roll type or the stand
// is not uniform; the answer must locate it, never name the cell or a
// single-factor scope.
FamilyEffect InexpressibleCellCovariate(int variant, Random* rng, uint64_t,
                                        int) {
  static const int kTypes[] = {0, 1, 5, 7};
  const int which = variant % 4;
  const int stand = variant / 4 % 2 == 0 ? 7 : 6;
  const int type = kTypes[std::min(3, static_cast<int>(rng->Uniform(0, 4)))];
  const std::string label = RollTypes()[type].label;
  FamilyEffect f = ScopedEffect(
      "inexpressible_cell_covariate", which, rng,
      {{"stand", "F" + std::to_string(stand)}, {"roll_type", label}},
      "on roll type " + label + " at F" + std::to_string(stand),
      [type, stand](const EffectContext& c) {
        return c.roll_type == type && c.pass->stand == stand;
      });
  f.truth.expressible = false;
  f.truth.covariate.clear();  // not expressible: where, not what
  f.truth.mismatch =
      std::string("roll type x stand x ") + kScopedCovariates[which];
  return f;
}

// inexpressible_interaction: temperature x speed with no main effect:
// m = exp(b zT zv), zT = (900 - T) / 30 K, zv = ln(v / 10) / 0.25.
FamilyEffect InexpressibleInteraction(int, Random* rng, uint64_t, int) {
  const double b = rng->Uniform(0.15, 0.25);
  FamilyEffect f = Inexpressible("inexpressible_interaction",
                                 "exp(b (900 - T) / 30 * ln(v / 10) / 0.25)", b,
                                 "temperature_c x speed_mps");
  f.truth.parameters = {{"b", b}};
  f.truth.description =
      "cold strip wears more only at high speed and less at low speed (a "
      "temperature x speed interaction without main effects)";
  f.apply = [b](const EffectContext& c) {
    const double zt = (900 - c.pass->temperature_c) / 30;
    const double zv = std::log(c.pass->speed_mps / 10) / 0.25;
    return std::exp(b * zt * zv);
  };
  return f;
}

// inexpressible_random_walk: each roll position's wear rate carries a
// factor exp(x) with x an AR(1) over consecutive campaigns, x_c = rho
// x_{c-1} + sd sqrt(1 - rho^2) z (rho 0.9..0.97, sd 0.12..0.2).
FamilyEffect InexpressibleRandomWalk(int, Random* rng, uint64_t seed,
                                     int num_campaigns) {
  const double rho = rng->Uniform(0.9, 0.97);
  const double sd = rng->Uniform(0.12, 0.2);
  FamilyEffect f = Inexpressible("inexpressible_random_walk", "ar1", sd,
                                 "time (campaign order), by roll position");
  f.truth.parameters = {{"rho", rho}, {"sd", sd}};
  f.truth.description =
      "each roll position's wear rate wanders slowly from campaign to "
      "campaign (AR(1) in log, rho " +
      Fmt("%.2f", rho) + ", sd " + Fmt("%.2f", sd) +
      "): no recorded quantity follows it";
  auto walk = std::make_shared<std::vector<double>>(4 * num_campaigns);
  Random noise = MakeRandom(seed, Stream::kFamilyNoise, 0);
  std::array<double, 4> x{};
  for (double& v : x) v = sd * noise.Normal();
  for (int c = 0; c < num_campaigns; ++c) {
    for (int s = 0; s < 4; ++s) {
      if (c > 0) {
        x[s] = rho * x[s] + sd * std::sqrt(1 - rho * rho) * noise.Normal();
      }
      (*walk)[4 * c + s] = std::exp(x[s] - 0.5 * sd * sd);
    }
  }
  f.apply = [walk](const EffectContext& c) {
    return (*walk)[4 * c.campaign + c.slot];
  };
  return f;
}

// inexpressible_bursts: in 2..3 calendar periods (runs of 15..30
// consecutive campaigns) every roll's wear carries an extra lognormal
// factor (sd 0.2..0.35), fixed per roll and campaign: the spread grows in
// those periods, the mean does not move.
FamilyEffect InexpressibleBursts(int, Random* rng, uint64_t seed,
                                 int num_campaigns) {
  const double sd = rng->Uniform(0.2, 0.35);
  const int periods = 2 + static_cast<int>(rng->Below(2));
  FamilyEffect f = Inexpressible("inexpressible_bursts", "lognormal", sd,
                                 "time (spread by calendar period)");
  f.truth.parameters = {{"sd", sd}, {"periods", periods}};
  auto factor = std::make_shared<std::vector<double>>(4 * num_campaigns, 1.0);
  Random noise = MakeRandom(seed, Stream::kFamilyNoise, 1);
  for (int p = 0; p < periods; ++p) {
    const int length = 15 + static_cast<int>(rng->Below(16));
    const int first = static_cast<int>(
        rng->Below(static_cast<uint64_t>(std::max(1, num_campaigns - length))));
    for (int c = first; c < std::min(num_campaigns, first + length); ++c) {
      for (int s = 0; s < 4; ++s) {
        (*factor)[4 * c + s] = LogNormalMeanOne(&noise, sd);
      }
    }
    f.truth.levels.push_back("campaigns " + std::to_string(first + 1) + ".." +
                             std::to_string(first + length));
  }
  f.truth.description =
      "in a few calendar periods the wear of every roll scatters more (extra "
      "lognormal factor, sd " +
      Fmt("%.2f", sd) + ", mean 1)";
  f.apply = [factor](const EffectContext& c) {
    return (*factor)[4 * c.campaign + c.slot];
  };
  return f;
}

// inexpressible_restart: after a stoppage (kSimStopS or more idle) the
// next 4..9 coils wear x(1 + s), s in 0.6..1.0 (a roll cooled while the
// mill stood, its oxide film and thermal crown rebuilt). Besides the
// 2 % short stoppages of every campaign, 2 % of the coils are followed by
// an idle time of 0.2..1 h. Readings once per campaign see it only through
// the number of stops, which hours in service also count: a term over
// hours_since_mount fits part of it. The data format records rolled_at,
// not the stops: lives in the coils after a stop.
FamilyEffect InexpressibleRestart(int, Random* rng, uint64_t, int) {
  const double s = rng->Uniform(0.6, 1.0);
  const int n = 4 + static_cast<int>(rng->Below(6));
  FamilyEffect f =
      Inexpressible("inexpressible_restart", "step", s, "coils after a stop");
  f.stoppage_probability = 0.02;
  f.stoppage_min_h = 0.2;
  f.stoppage_max_h = 1;
  f.truth.parameters = {{"s", s}, {"n_coils", n}};
  f.truth.description = "the first " + std::to_string(n) +
                        " coils after a stoppage wear x" + Fmt("%.2f", 1 + s) +
                        " (a cooled roll rebuilding its surface)";
  f.apply = [s, n](const EffectContext& c) {
    return c.coils_since_stop < n ? 1 + s : 1.0;
  };
  return f;
}

}  // namespace rollwear::sim::families
