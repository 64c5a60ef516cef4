// Effect families of the mill simulator: concealed effects with several
// forms, strengths and scopes each, for testing that a diagnosis names the
// right physics in the right place, and says "unexplained" (never a proxy)
// when the truth lies outside what one recorded quantity can describe.
// Every family changes only quantities the data format records (or adds a
// text column to measurements.csv, which the format allows).
//
// A family is selected as NAME (its variant - form, scope, level - drawn
// from the seed) or NAME:K (variant K); the strength is always drawn from
// the seed, from its own random stream, so the other draws of the
// simulation stay as they were (sim_internal.h, Stream).
//
//   scoped            a covariate effect at one stand or one roll position
//   scoped_factor     a covariate effect on one grade or one roll type
//   grade_stand       one grade wears one stand (mostly the last) more
//   roll_type_stand   one roll type wears more at one stand only
//   roll_type_pair_stand two roll types wear more at one stand (not
//                     identifiable in a two-stand mill)
//   grade_roll_position one grade wears one roll position more
//   grinder           a text column of measurements.csv; one level reads low
//   grinder_null      the same column, no offset (must stay quiet)
//   calendar_drift    wear rate or reading drifting with calendar time
//   stoppages         stoppages inside campaigns; wear grows with hours
//   stoppages_null    the same stoppages, no wear effect (must stay quiet)
//   inexpressible_*   order of grades, a covariate effect on dry (or
//                     lubricated) passes only, a night shift, bad rolls
//                     (by serial), a roll's service, temperature x speed
//                     interaction, autocorrelated roll factor, noise
//                     bursts by period
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/sim/sim_families_internal.h"
#include "core/sim/sim_internal.h"

namespace rollwear::sim {
namespace {

using families::Base;
using families::Fmt;
using families::InexpressibleBadRolls;
using families::InexpressibleBursts;
using families::InexpressibleCellCovariate;
using families::InexpressibleInteraction;
using families::InexpressibleLubrication;
using families::InexpressibleNightShift;
using families::InexpressibleOrder;
using families::InexpressibleRandomWalk;
using families::InexpressibleRestart;
using families::InexpressibleRollService;
using families::ScopedEffect;

using Draw = FamilyEffect (*)(int variant, Random* rng, uint64_t seed,
                              int num_campaigns);

struct FamilySpec {
  const char* name;
  const char* description;
  int num_variants;
  Draw draw;
};

// Stand and position of a sim slot as a scope.
bool InScope(const std::map<std::string, std::string>& scope, int slot) {
  const int stand = 6 + slot / 2;
  auto it = scope.find("stand");
  if (it != scope.end() && it->second != "F" + std::to_string(stand)) {
    return false;
  }
  it = scope.find("position");
  return it == scope.end() ||
         it->second == PositionName(static_cast<Position>(slot % 2));
}

// scoped: one of the old covariate effects, acting at one stand or one roll
// position only. Variant k: covariate k % 4, scope k / 4 % 3.
FamilyEffect Scoped(int variant, Random* rng, uint64_t, int) {
  const int where = variant / 4 % 3;
  std::map<std::string, std::string> scope = {
      {"stand", where == 1 ? "F6" : "F7"}};
  if (where == 2) scope["position"] = "top";
  return ScopedEffect(
      "scoped", variant % 4, rng, scope, "where the scope says",
      [scope](const EffectContext& c) { return InScope(scope, c.slot); });
}

// scoped_factor: one of the old covariate effects, acting on one grade or
// one roll type only (the scope a K structure by grade or roll type leaves
// open: that grade's or type's K is right on average, its dependence on the
// covariate is not). Variant k: covariate k % 4, scope k / 4 % 4 (grade
// S355, roll type ICDP-S2, grade HSLA350, roll type ICDP-S1).
FamilyEffect ScopedFactor(int variant, Random* rng, uint64_t, int) {
  const int scope = variant / 4 % 4;
  const bool by_grade = scope % 2 == 0;
  const int level = scope == 0 ? 2 : scope == 1 ? 1 : scope == 2 ? 3 : 0;
  const std::string label =
      by_grade ? Grades()[level].label : RollTypes()[level].label;
  return ScopedEffect(
      "scoped_factor", variant % 4, rng,
      {{by_grade ? "grade" : "roll_type", label}},
      std::string("on ") + (by_grade ? "grade " : "roll type ") + label,
      [by_grade, level](const EffectContext& c) {
        return (by_grade ? c.grade : c.roll_type) == level;
      });
}

// grade_stand: one grade wears one stand more (x1.2..1.5): the last stand
// in variants 0..3 (grades S355, HSLA350, CQ, HSLA420), F6 in 4..5.
FamilyEffect GradeStand(int variant, Random* rng, uint64_t, int) {
  static const int kGrades[] = {2, 3, 0, 4, 2, 3};
  const int grade = kGrades[variant % 6];
  const int stand = variant % 6 < 4 ? 7 : 6;
  const double m = rng->Uniform(1.2, 1.5);
  FamilyEffect f = Base("grade_stand", "grade", "multiplier", m);
  f.truth.scope = {{"stand", "F" + std::to_string(stand)}};
  f.truth.levels = {Grades()[grade].label};
  f.truth.parameters = {{"multiplier", m}};
  f.truth.description = std::string("grade ") + Grades()[grade].label +
                        " wears the work rolls of F" + std::to_string(stand) +
                        " by a factor " + Fmt("%.2f", m) +
                        " more; other stands and grades as Wang's law";
  f.apply = [grade, stand, m](const EffectContext& c) {
    return c.grade == grade && c.pass->stand == stand ? m : 1.0;
  };
  return f;
}

// grade_roll_position: one grade wears one roll position more (x1.2..1.5):
// variant k: grade k % 4 of S355, HSLA350, CQ, HSLA420; F7/bottom for
// k / 4 even, F6/top otherwise. The other roll position of the stand, and
// the other stand, follow the wear law.
FamilyEffect GradeRollPosition(int variant, Random* rng, uint64_t, int) {
  static const int kGrades[] = {2, 3, 0, 4};
  const int grade = kGrades[variant % 4];
  const bool f7_bottom = variant / 4 % 2 == 0;
  const int stand = f7_bottom ? 7 : 6;
  const Position position = f7_bottom ? Position::kBottom : Position::kTop;
  const double m = rng->Uniform(1.2, 1.5);
  FamilyEffect f = Base("grade_roll_position", "grade", "multiplier", m);
  f.truth.scope = {{"stand", "F" + std::to_string(stand)},
                   {"position", PositionName(position)}};
  f.truth.levels = {Grades()[grade].label};
  f.truth.parameters = {{"multiplier", m}};
  f.truth.description = std::string("grade ") + Grades()[grade].label +
                        " wears the " + PositionName(position) +
                        " work roll of F" + std::to_string(stand) +
                        " by a factor " + Fmt("%.2f", m) +
                        " more; other roll positions and grades as Wang's law";
  const int slot = SimSlot(stand, position);
  f.apply = [grade, slot, m](const EffectContext& c) {
    return c.grade == grade && c.slot == slot ? m : 1.0;
  };
  return f;
}

// roll_type_stand: a roll type used at both stands wears more at one of
// them only (x1.2..1.5). Variant k: type k % 4 of ICDP-S1, ICDP-S2,
// HiCr-S2, HSS-S2; stand F7 for k / 4 even, F6 otherwise.
FamilyEffect RollTypeStand(int variant, Random* rng, uint64_t, int) {
  static const int kTypes[] = {0, 1, 5, 7};
  const int type = kTypes[variant % 4];
  const int stand = variant / 4 % 2 == 0 ? 7 : 6;
  const double m = rng->Uniform(1.2, 1.5);
  FamilyEffect f = Base("roll_type_stand", "roll_type", "multiplier", m);
  f.truth.scope = {{"stand", "F" + std::to_string(stand)}};
  f.truth.levels = {RollTypes()[type].label};
  f.truth.parameters = {{"multiplier", m}};
  f.truth.description = std::string("rolls of type ") +
                        RollTypes()[type].label + " wear by a factor " +
                        Fmt("%.2f", m) + " more at F" + std::to_string(stand) +
                        " only";
  f.apply = [type, stand, m](const EffectContext& c) {
    return c.roll_type == type && c.pass->stand == stand ? m : 1.0;
  };
  return f;
}

// roll_type_pair_stand: two of the four roll types used at both stands
// wear more at one stand only (x1.2..1.5 each, one draw): variant k takes
// pair k % 6 of (ICDP-S1, ICDP-S2, HiCr-S2, HSS-S2), at F7 for k even, F6
// otherwise. In a mill measured at two stands that is the same data as the
// other two types wearing as much more at the other stand (the stands' and
// types' K take up the factor): expressible, but not identifiable, so the
// answer must locate it (roll type x stand) and name neither pair.
FamilyEffect RollTypePairStand(int variant, Random* rng, uint64_t, int) {
  static const int kTypes[] = {0, 1, 5, 7};
  static const int kPairs[6][2] = {{0, 1}, {0, 2}, {0, 3},
                                   {1, 2}, {1, 3}, {2, 3}};
  const int a = kTypes[kPairs[variant % 6][0]],
            b = kTypes[kPairs[variant % 6][1]];
  const int stand = variant % 2 == 0 ? 7 : 6;
  const double m = rng->Uniform(1.2, 1.5);
  FamilyEffect f = Base("roll_type_pair_stand", "", "multiplier", m);
  f.truth.expressible = false;
  f.truth.mismatch = "roll type x stand";
  f.truth.scope = {{"stand", "F" + std::to_string(stand)}};
  f.truth.levels = {RollTypes()[a].label, RollTypes()[b].label};
  f.truth.parameters = {{"multiplier", m}};
  f.truth.description =
      std::string("rolls of types ") + RollTypes()[a].label + " and " +
      RollTypes()[b].label + " wear by a factor " + Fmt("%.2f", m) +
      " more at F" + std::to_string(stand) +
      " only; the other two types wearing as much more at the "
      "other stand is the same data";
  f.apply = [a, b, stand, m](const EffectContext& c) {
    return (c.roll_type == a || c.roll_type == b) && c.pass->stand == stand
               ? m
               : 1.0;
  };
  return f;
}

// grade_pair_stand: two of four grades (S355, HSLA350, CQ, HSLA420; pair
// k % 6) wear more at one stand only (x1.2..1.5, one draw), F7 for k even,
// F6 otherwise. Two cells: named right only as both (two findings, one
// level each); one of them named alone says "elsewhere the law holds" of
// the other, which is wrong physics.
FamilyEffect GradePairStand(int variant, Random* rng, uint64_t, int) {
  static const int kGrades[] = {2, 3, 0, 4};
  static const int kPairs[6][2] = {{0, 1}, {0, 2}, {0, 3},
                                   {1, 2}, {1, 3}, {2, 3}};
  const int a = kGrades[kPairs[variant % 6][0]],
            b = kGrades[kPairs[variant % 6][1]];
  const int stand = variant % 2 == 0 ? 7 : 6;
  const double m = rng->Uniform(1.2, 1.5);
  FamilyEffect f = Base("grade_pair_stand", "grade", "multiplier", m);
  f.truth.scope = {{"stand", "F" + std::to_string(stand)}};
  f.truth.levels = {Grades()[a].label, Grades()[b].label};
  f.truth.parameters = {{"multiplier", m}};
  f.truth.description = std::string("grades ") + Grades()[a].label + " and " +
                        Grades()[b].label + " wear the work rolls of F" +
                        std::to_string(stand) + " by a factor " +
                        Fmt("%.2f", m) + " more: two cells";
  f.apply = [a, b, stand, m](const EffectContext& c) {
    return (c.grade == a || c.grade == b) && c.pass->stand == stand ? m : 1.0;
  };
  return f;
}

// grinder: a text column of measurements.csv naming who or what took the
// reading; one level reads low by 8..25 um on its share (20..50 %) of the
// readings. Variant: column grinder (G1/G2), gauge (GA/GB/GC), crew
// (A/B/C/D).
FamilyEffect ColumnOffset(int variant, Random* rng, bool null_effect) {
  static const char* kColumns[] = {"grinder", "gauge", "crew"};
  static const std::vector<std::vector<std::string>> kLevels = {
      {"G1", "G2"}, {"GA", "GB", "GC"}, {"A", "B", "C", "D"}};
  const int which = variant % 3;
  const double offset = rng->Uniform(8, 25);
  const double share = rng->Uniform(0.2, 0.5);
  const std::vector<std::string>& levels = kLevels[which];
  const int low = static_cast<int>(levels.size()) - 1;  // the last level
  FamilyEffect f = Base(null_effect ? "grinder_null" : "grinder",
                        kColumns[which], "offset", null_effect ? 0 : -offset);
  f.kind = EffectKind::kMeasurement;
  f.column = kColumns[which];
  f.column_levels = levels;
  const double rest = (1 - share) / low;
  f.column_shares.assign(levels.size(), rest);
  f.column_shares[low] = share;
  f.truth.parameters = {{"share", share}};
  if (null_effect) {
    f.truth.null_effect = true;
    f.truth.description = "measurements.csv has a text column " + f.column +
                          " naming who took each reading; no level reads "
                          "differently";
    return f;
  }
  f.truth.levels = {levels[low]};
  f.truth.parameters["offset_um"] = -offset;
  f.truth.description = "readings of " + f.column + " " + levels[low] + " (" +
                        Fmt("%.0f", 100 * share) + " % of them) read " +
                        Fmt("%.1f", offset) + " um low";
  f.apply = [low, offset](const EffectContext& c) {
    return c.column_level == low ? -offset : 0.0;
  };
  return f;
}
FamilyEffect Grinder(int variant, Random* rng, uint64_t, int) {
  return ColumnOffset(variant, rng, false);
}
FamilyEffect GrinderNull(int variant, Random* rng, uint64_t, int) {
  return ColumnOffset(variant, rng, true);
}

// calendar_drift, in campaign order (which is calendar order): the wear
// rate rises linearly over the whole period by g (0.2..0.4) or steps up by
// g at a campaign in the middle third (covariate rolled_at), or the
// reading drifts low by 15..35 um linearly or in one step (measured_at).
FamilyEffect CalendarDrift(int variant, Random* rng, uint64_t, int) {
  const int form = variant % 4;
  const bool reading = form >= 2;
  const bool step = form % 2 == 1;
  const double size = reading ? rng->Uniform(15, 35) : rng->Uniform(0.2, 0.4);
  const double at = rng->Uniform(0.35, 0.65);
  FamilyEffect f = Base(
      "calendar_drift", reading ? "measured_at" : "rolled_at",
      std::string(reading ? "reading_" : "rate_") + (step ? "step" : "linear"),
      reading ? -size : size);
  f.kind = reading ? EffectKind::kMeasurement : EffectKind::kWearRate;
  f.truth.parameters = {
      {reading ? "offset_um" : "gain", reading ? -size : size}};
  if (step) f.truth.parameters["step_at_fraction"] = at;
  f.truth.description =
      std::string(
          reading
              ? "the reading drifts low by up to " + Fmt("%.1f um", size)
              : "the wear rate rises by up to " + Fmt("%.0f %%", 100 * size)) +
      (step ? " in one step part-way through the period"
            : " linearly over the period") +
      " (calendar time, campaign by campaign)";
  f.apply = [reading, step, size, at](const EffectContext& c) {
    const double t =
        c.num_campaigns > 1 ? c.campaign / (c.num_campaigns - 1.0) : 0.0;
    const double x = step ? (t >= at ? 1.0 : 0.0) : t;
    return reading ? -size * x : 1 + size * x;
  };
  return f;
}

// per_coil: every coil adds a = 0.25..0.5 um of wear to each work roll it
// passes, whatever its length and load (the bite's impact at threading,
// head and tail), at both stands or at one (F6 or F7): 8..16 % of an
// average pass's wear. Described by the per_coil term (model_terms.h).
FamilyEffect PerCoil(int variant, Random* rng, uint64_t, int) {
  const double a = rng->Uniform(0.25, 0.5);
  const int stand = rng->Uniform() < 0.5 ? 6 : 7;
  FamilyEffect f = Base("per_coil", "campaign_coils_before", "per_coil", a);
  f.kind = EffectKind::kWearAdded;
  f.truth.parameters = {{"um_per_coil", a}};
  const bool scoped = variant == 1;
  if (scoped) f.truth.scope = {{"stand", "F" + std::to_string(stand)}};
  f.truth.description =
      "every coil adds " + Fmt("%.2f um", a) + " of wear to each work roll " +
      (scoped ? "of F" + std::to_string(stand) : std::string("it passes")) +
      ", whatever its length and load";
  const std::map<std::string, std::string> scope = f.truth.scope;
  f.apply = [a, scope](const EffectContext& c) {
    return InScope(scope, c.slot) ? a : 0.0;
  };
  return f;
}

// stoppages: about 1.5 % of the coils are followed by an idle time of
// 0.5..4 h (a breakdown, a change of programme), so hours in service and
// rolled length part ways. The wear rate grows with hours since the roll
// change (thermal fatigue, oxide growth on the idle hot roll), linearly
// or saturating; the null variant has the stoppages only.
FamilyEffect Stoppages(int variant, Random* rng, bool null_effect) {
  const bool saturating = variant % 2 == 1;
  const double beta = rng->Uniform(0.4, 0.8);
  FamilyEffect f = Base(null_effect ? "stoppages_null" : "stoppages",
                        null_effect ? "" : "hours_since_mount",
                        null_effect  ? "none"
                        : saturating ? "1 + beta (1 - exp(-h / 6 h))"
                                     : "1 + beta h / 10 h",
                        null_effect ? 0 : beta);
  f.stoppage_probability = 0.015;
  f.stoppage_min_h = 0.5;
  f.stoppage_max_h = 4;
  f.truth.parameters = {{"stoppage_probability", 0.015}, {"stoppage_max_h", 4}};
  if (null_effect) {
    f.truth.null_effect = true;
    f.truth.description =
        "stoppages inside campaigns (idle 0.5..4 h after 1.5 % of the "
        "coils); wear follows Wang's law";
    return f;
  }
  f.truth.parameters["beta"] = beta;
  f.truth.description =
      "stoppages inside campaigns part hours in service from rolled length; "
      "the wear rate grows with hours_since_mount: " +
      f.truth.form;
  f.apply = [saturating, beta](const EffectContext& c) {
    const double h = c.hours_since_mount;
    return saturating ? 1 + beta * (1 - std::exp(-h / 6)) : 1 + beta * h / 10;
  };
  return f;
}
// gated_lubrication: roll-gap lubrication lowers wear by gamma =
// 0.3..0.45 only on one side of a threshold of another pass quantity: above
// a speed v0 = 10.5..12.5 m/s (variant 0: the oil film needs speed), or
// below an entry temperature t0 = 895..910 C (variant 1: on hotter strip it
// burns off). Described by a flag term behind a gate (TermScope::gate).
FamilyEffect GatedLubrication(int variant, Random* rng, uint64_t, int) {
  const double gamma = rng->Uniform(0.3, 0.45);
  const bool by_speed = variant == 0;
  const double at =
      by_speed ? rng->Uniform(10.5, 12.5) : rng->Uniform(895.0, 910.0);
  FamilyEffect f =
      Base("gated_lubrication", "lubrication",
           by_speed ? "flag above speed" : "flag below temperature", gamma);
  f.truth.scope = {{"gate", by_speed ? "speed_mps" : "temperature_c"},
                   {"gate_side", by_speed ? "above" : "below"}};
  f.truth.parameters = {{"gamma", gamma}, {"gate_at", at}};
  f.truth.description =
      "roll-gap lubrication lowers the wear rate by " +
      Fmt("%.0f %%", 100 * gamma) + " only " +
      (by_speed ? "above " + Fmt("%.1f m/s", at)
                : "below an entry temperature of " + Fmt("%.0f C", at)) +
      "; elsewhere it changes nothing";
  f.apply = [gamma, by_speed, at](const EffectContext& c) {
    if (!c.pass->lubrication) return 1.0;
    const bool inside =
        by_speed ? c.pass->speed_mps >= at : c.pass->temperature_c < at;
    return inside ? 1 - gamma : 1.0;
  };
  return f;
}

FamilyEffect StoppagesOn(int variant, Random* rng, uint64_t, int) {
  return Stoppages(variant, rng, false);
}
FamilyEffect StoppagesNull(int variant, Random* rng, uint64_t, int) {
  return Stoppages(variant, rng, true);
}

const std::vector<FamilySpec>& Families() {
  static const std::vector<FamilySpec> kFamilies = {
      {"scoped",
       "a covariate effect (temperature, speed, hardness or campaign length) "
       "at one stand or one roll position only",
       12, &Scoped},
      {"scoped_factor",
       "a covariate effect (temperature, speed, hardness or campaign length) "
       "on one grade or one roll type only",
       16, &ScopedFactor},
      {"grade_stand", "one grade wears one stand (mostly F7) x1.2..1.5 more", 6,
       &GradeStand},
      {"roll_type_stand", "one roll type wears x1.2..1.5 more at one stand", 8,
       &RollTypeStand},
      {"roll_type_pair_stand",
       "two roll types wear more at one stand only: the same data as the "
       "other two at the other stand; not identifiable",
       6, &RollTypePairStand},
      {"grade_pair_stand",
       "two grades wear x1.2..1.5 more at one stand only: two cells, named "
       "right only as both",
       6, &GradePairStand},
      {"grade_roll_position",
       "one grade wears one roll position (F7/bottom or F6/top) x1.2..1.5 "
       "more",
       8, &GradeRollPosition},
      {"grinder",
       "a text column of measurements.csv (grinder/gauge/crew); one level "
       "reads 8..25 um low",
       3, &Grinder},
      {"grinder_null", "the grinder column with no offset (quiet expected)", 3,
       &GrinderNull},
      {"calendar_drift",
       "wear rate (rolled_at) or reading (measured_at) drifting with "
       "calendar time, linear or step",
       4, &CalendarDrift},
      {"stoppages",
       "stoppages inside campaigns; wear grows with hours since mount, "
       "linear or saturating",
       2, &StoppagesOn},
      {"stoppages_null", "stoppages inside campaigns, no wear effect", 1,
       &StoppagesNull},
      {"per_coil",
       "every coil adds 0.25..0.5 um of wear per roll whatever its length "
       "(the bite's impact), at both stands or at one",
       2, &PerCoil},
      {"gated_lubrication",
       "lubrication lowers wear only above some speed or below some entry "
       "temperature (a flag behind a threshold of another quantity)",
       2, &GatedLubrication},
      {"inexpressible_order",
       "a hard grade right after the roll change wears more (campaign "
       "order x grade); not expressible",
       2, &InexpressibleOrder},
      {"inexpressible_lubrication",
       "a covariate effect (temperature, speed, hardness or campaign length) "
       "on dry (or on lubricated) passes only; not expressible",
       8, &InexpressibleLubrication},
      {"inexpressible_night_shift",
       "coils rolled at night (22-06 h) wear more or less; not expressible", 2,
       &InexpressibleNightShift},
      {"inexpressible_bad_rolls",
       "about one physical roll in ten wears more whenever mounted; not "
       "expressible",
       1, &InexpressibleBadRolls},
      {"inexpressible_roll_service",
       "a roll wears more the more campaigns it has served (linear or "
       "from the third); not expressible",
       2, &InexpressibleRollService},
      {"inexpressible_cell_covariate",
       "a covariate effect (temperature, speed, hardness or campaign length) "
       "on one roll type at one stand only; not expressible",
       8, &InexpressibleCellCovariate},
      {"inexpressible_interaction",
       "temperature x speed interaction without main effects; not "
       "expressible",
       1, &InexpressibleInteraction},
      {"inexpressible_random_walk",
       "roll-position factor autocorrelated across campaigns; not "
       "expressible",
       1, &InexpressibleRandomWalk},
      {"inexpressible_bursts",
       "extra wear scatter in some calendar periods; not expressible", 1,
       &InexpressibleBursts},
      {"inexpressible_restart",
       "the first coils after a stoppage wear more (a cooled roll); not "
       "expressible",
       1, &InexpressibleRestart},
  };
  return kFamilies;
}

// The spec of `name` ("grade_stand" or "grade_stand:3") and its variant
// (-1: from the seed), or nullptr.
const FamilySpec* Find(const std::string& name, int* variant) {
  const size_t colon = name.find(':');
  const std::string base = name.substr(0, colon);
  *variant = -1;
  if (colon != std::string::npos) {
    const std::string k = name.substr(colon + 1);
    if (k.empty() || k.size() > 3 ||
        k.find_first_not_of("0123456789") != std::string::npos) {
      return nullptr;
    }
    *variant = std::stoi(k);
  }
  for (const FamilySpec& f : Families()) {
    if (base == f.name) {
      return *variant < f.num_variants ? &f : nullptr;
    }
  }
  return nullptr;
}

uint64_t NameIndex(const char* name) {
  uint64_t h = 14695981039346656037ull;  // FNV-1a
  for (const char* p = name; *p != 0; ++p) {
    h = (h ^ static_cast<unsigned char>(*p)) * 1099511628211ull;
  }
  return h;
}

}  // namespace

bool IsFamilyName(const std::string& name) {
  int variant;
  return Find(name, &variant) != nullptr;
}

FamilyEffect DrawFamily(const std::string& name, uint64_t seed,
                        int num_campaigns) {
  int variant;
  const FamilySpec* spec = Find(name, &variant);
  Random rng = MakeRandom(seed, Stream::kFamily, NameIndex(spec->name));
  const int drawn =
      static_cast<int>(rng.Below(static_cast<uint64_t>(spec->num_variants)));
  if (variant < 0) variant = drawn;
  FamilyEffect f = spec->draw(variant, &rng, seed, num_campaigns);
  f.truth.name = name;
  f.truth.parameters["variant"] = variant;
  return f;
}

std::vector<std::pair<std::string, std::string>> FamilyList() {
  std::vector<std::pair<std::string, std::string>> out;
  for (const FamilySpec& f : Families()) {
    out.emplace_back(f.name, std::string(f.description) + " (" +
                                 std::to_string(f.num_variants) +
                                 " variants: NAME:0..)");
  }
  return out;
}

}  // namespace rollwear::sim
