// Mill simulator, effect families (core/sim/sim_families.cc): each family's
// effect is in the data by the amount its truth states, the truth records
// form, strength, scope and levels, the null variants change nothing they
// should not, and switching the families in leaves the old effects' output
// unchanged for the same seed (checksums taken before the families were
// added).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/model/covariates.h"
#include "core/model/wear_law.h"
#include "core/sim/simulator.h"
#include "tests/core/simulator_test_util.h"

namespace rollwear {
namespace {

using simulator_test::Simulated;

// FNV-1a over the bytes of every number and label a dataset records, and
// the truth's noise-free wear: any change of the output changes it.
class Fnv {
 public:
  void Add(double x) { Bytes(&x, sizeof x); }
  void Add(int64_t x) { Bytes(&x, sizeof x); }
  void Add(const std::string& s) { Bytes(s.data(), s.size()); }
  uint64_t value() const { return h_; }

 private:
  void Bytes(const void* p, size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (size_t i = 0; i < n; ++i) h_ = (h_ ^ b[i]) * 1099511628211ull;
  }
  uint64_t h_ = 14695981039346656037ull;
};

uint64_t Checksum(const Simulation& sim) {
  Fnv f;
  const Dataset& d = sim.data;
  for (const Campaign& c : d.campaigns) {
    f.Add(c.id);
    f.Add(c.started_at);
    f.Add(c.ended_at);
  }
  for (const Mount& m : d.mounts) {
    f.Add(m.roll_id);
    f.Add(int64_t{m.roll_type});
    f.Add(m.diameter_mm);
    f.Add(m.hardness_hb);
  }
  for (const Pass& p : d.passes) {
    f.Add(p.rolled_at);
    f.Add(int64_t{p.grade});
    f.Add(p.force_kn);
    f.Add(p.length_m);
    f.Add(p.temperature_c);
    f.Add(p.speed_mps);
    f.Add(p.exit_thickness_mm);
  }
  for (const Measurement& m : d.measurements) {
    f.Add(m.measured_at);
    f.Add(m.wear_center_um);
  }
  for (double w : sim.truth.noise_free_wear_um) f.Add(w);
  return f.value();
}

// Checksums of the effects that existed before the families (seed 5, 40
// campaigns; supplier_change 300, as its step comes on day 45), recorded
// on main at 22a9d83 before any family code: the families, the stoppage
// and column streams and the new options must leave them bit for bit.
struct OldEffectSum {
  const char* effect;
  uint64_t checksum;
};
const OldEffectSum kOldEffects[] = {
    {"", 0x3da84f1089d20b5aull},
    {"campaign_growth", 0x07f72a52e6145657ull},
    {"run_in", 0x64891da9514bcdceull},
    {"warm_measurement", 0x1e8a194245b6c29cull},
    {"temperature", 0x2eab2df574f2d0a4ull},
    {"lubrication", 0xa96503c39b6a997dull},
    {"hardness", 0x2bd22cad5acf2293ull},
    {"speed", 0x90412c41ce2898ccull},
    {"supplier_change", 0xca2db9b2133a1542ull},
    {"reduction", 0xf9b32e89e5faa694ull},
    {"diameter", 0xe0b748140476f3a6ull},
    {"gross_errors", 0x16aba9614182bf05ull},
};

TEST(SimulatorFamilyTest, OldEffectsUnchanged) {
  for (const OldEffectSum& e : kOldEffects) {
    const std::string n = e.effect;
    std::vector<std::string> effects;
    if (!n.empty()) effects.push_back(n);
    const Simulation sim =
        Simulated(5, n == "supplier_change" ? 300 : 40, effects);
    EXPECT_EQ(Checksum(sim), e.checksum) << "effect '" << n << "'";
    EXPECT_TRUE(sim.data.measurement_extra.factor_names.empty());
  }
}

// Each measurement with its baseline (true factors, Wang's law, no effect)
// and the share of that baseline from passes for which `in(pass, mount)`.
struct Row {
  const Measurement* m = nullptr;
  const Mount* mount = nullptr;
  double measured = 0, noise_free = 0, baseline = 0, share = 0;
  double mean_hours = 0, stand_length_m = 0;  // baseline-weighted / total
};
template <typename In>
std::vector<Row> Rows(const Simulation& sim, In in) {
  const Dataset& d = sim.data;
  const SimulationTruth& t = sim.truth;
  const auto mounts = simulator_test::MountsByKey(d);
  const auto passes = simulator_test::PassesByStand(d);
  std::vector<Row> out;
  for (size_t i = 0; i < d.measurements.size(); ++i) {
    Row r;
    r.m = &d.measurements[i];
    r.mount =
        mounts.at({r.m->campaign, r.m->stand, static_cast<int>(r.m->position)});
    r.measured = r.m->wear_center_um;
    r.noise_free = t.noise_free_wear_um[i];
    const double k =
        t.k_position.at(RollPositionName(r.m->stand, r.m->position)) *
        t.k_roll_type.at(d.roll_types[r.mount->roll_type]);
    const UnixSeconds start = d.campaigns[r.m->campaign].started_at;
    for (const Pass* p : passes.at({r.m->campaign, r.m->stand})) {
      const PassLoadInput load{p->force_kn,          p->width_mm,
                               p->length_m,          p->entry_thickness_mm,
                               p->exit_thickness_mm, r.mount->diameter_mm,
                               r.mount->hardness_hb};
      const double dw =
          k * t.k_grade.at(d.grades[p->grade]) * BaseLoad(WearLaw::kWang, load);
      r.baseline += dw;
      r.share += in(*p, *r.mount) ? dw : 0;
      r.mean_hours += dw * (p->rolled_at - start) / 3600.0;
      r.stand_length_m += p->length_m;
    }
    r.share /= r.baseline;
    r.mean_hours /= r.baseline;
    out.push_back(r);
  }
  return out;
}

// Least-squares slope through the origin of y on x.
double Slope(const std::vector<double>& x, const std::vector<double>& y) {
  double sxy = 0, sxx = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    sxy += x[i] * y[i];
    sxx += x[i] * x[i];
  }
  return sxy / sxx;
}

const SimulatedEffect& OnlyEffect(const Simulation& sim) {
  EXPECT_EQ(sim.truth.effects.size(), 1u);
  return sim.truth.effects.at(0);
}

// The grade x stand cell: measured wear / baseline - 1 against the cell's
// share of the baseline gives the truth's multiplier - 1 (from the noisy
// readings, within 0.1), and the other stand's readings show nothing.
TEST(SimulatorFamilyTest, GradeStandCellWearsByTheTrueFactor) {
  const Simulation sim = Simulated(31, 150, {"grade_stand:0"});
  const SimulatedEffect& e = OnlyEffect(sim);
  ASSERT_EQ(e.levels, std::vector<std::string>{"S355"});
  ASSERT_EQ(e.scope, (std::map<std::string, std::string>{{"stand", "F7"}}));
  EXPECT_EQ(e.covariate, "grade");
  EXPECT_GE(e.strength, 1.2);
  EXPECT_LE(e.strength, 1.5);
  const int s355 = Dataset::Intern(
      const_cast<std::vector<std::string>*>(&sim.data.grades), "S355");
  std::vector<double> share, excess;
  for (const Row& r :
       Rows(sim, [&](const Pass&p, const Mount&) { return p.grade == s355; })) {
    if (r.m->stand == 6) {
      EXPECT_NEAR(r.noise_free / r.baseline, 1, 1e-9);
      continue;
    }
    EXPECT_NEAR(r.noise_free / r.baseline, 1 + (e.strength - 1) * r.share,
                1e-9);
    share.push_back(r.share);
    excess.push_back(r.measured / r.baseline - 1);
  }
  EXPECT_NEAR(Slope(share, excess), e.strength - 1, 0.1);
}

TEST(SimulatorFamilyTest, RollTypeWearsMoreAtOneStandOnly) {
  const Simulation sim = Simulated(32, 150, {"roll_type_stand:0"});
  const SimulatedEffect& e = OnlyEffect(sim);
  ASSERT_EQ(e.levels, std::vector<std::string>{"ICDP-S1"});
  ASSERT_EQ(e.scope.at("stand"), "F7");
  std::vector<double> in_cell, out_cell;
  for (const Row& r :
       Rows(sim, [](const Pass&, const Mount&) { return true; })) {
    const bool cell = sim.data.roll_types[r.mount->roll_type] == "ICDP-S1";
    const bool f7 = r.m->stand == 7;
    EXPECT_NEAR(r.noise_free / r.baseline, cell && f7 ? e.strength : 1, 1e-9);
    if (cell) (f7 ? in_cell : out_cell).push_back(r.measured / r.baseline);
  }
  ASSERT_GT(in_cell.size(), 20u);
  ASSERT_GT(out_cell.size(), 20u);
  auto mean = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x / v.size();
    return s;
  };
  // Measured ratio of the type at F7 over the same type at F6.
  EXPECT_NEAR(mean(in_cell) / mean(out_cell), e.strength, 0.08);
}

TEST(SimulatorFamilyTest, ScopedTemperatureActsAtF7Only) {
  const Simulation sim = Simulated(33, 80, {"scoped:0"});
  const SimulatedEffect& e = OnlyEffect(sim);
  EXPECT_EQ(e.covariate, "temperature_c");
  EXPECT_EQ(e.scope.at("stand"), "F7");
  int changed = 0;
  for (const Row& r :
       Rows(sim, [](const Pass&, const Mount&) { return true; })) {
    if (r.m->stand == 6) {
      EXPECT_NEAR(r.noise_free / r.baseline, 1, 1e-9);
    } else {
      changed += std::abs(r.noise_free / r.baseline - 1) > 0.02;
    }
  }
  EXPECT_GT(changed, 60);
  // The position-scoped variant touches F7/top only.
  const Simulation top = Simulated(33, 20, {"scoped:8"});
  EXPECT_EQ(OnlyEffect(top).scope.at("position"), "top");
  for (const Row& r :
       Rows(top, [](const Pass&, const Mount&) { return true; })) {
    if (r.m->stand != 7 || r.m->position != Position::kTop) {
      EXPECT_NEAR(r.noise_free / r.baseline, 1, 1e-9);
    }
  }
}

// Over `rows`, the readings outside the effect's scope (in_scope false),
// each asserted to be Wang's law exactly, and the readings inside it that
// the effect changes by more than 1 %.
template <typename InScope>
std::pair<int, int> UntouchedAndChanged(const std::vector<Row>& rows,
                                        InScope in_scope) {
  int untouched = 0, changed = 0;
  for (const Row& r : rows) {
    if (!in_scope(r)) {
      EXPECT_NEAR(r.noise_free / r.baseline, 1, 1e-9);
      ++untouched;
    } else {
      changed += std::abs(r.noise_free / r.baseline - 1) > 0.01;
    }
  }
  return {untouched, changed};
}

// scoped_factor acts on its grade (variant 0: temperature on S355) or its
// roll type (variant 5: speed on ICDP-S2) only: a reading with none of
// that grade's passes, or of another roll type, is Wang's law exactly.
TEST(SimulatorFamilyTest, ScopedFactorActsOnItsGradeOrRollTypeOnly) {
  const Simulation by_grade = Simulated(34, 60, {"scoped_factor:0"});
  const SimulatedEffect& g = OnlyEffect(by_grade);
  EXPECT_EQ(g.covariate, "temperature_c");
  ASSERT_EQ(g.scope, (std::map<std::string, std::string>{{"grade", "S355"}}));
  const int s355 =
      static_cast<int>(std::find(by_grade.data.grades.begin(),
                                 by_grade.data.grades.end(), "S355") -
                       by_grade.data.grades.begin());
  const auto [untouched, changed] = UntouchedAndChanged(
      Rows(by_grade,
           [s355](const Pass& p, const Mount&) { return p.grade == s355; }),
      [](const Row& r) { return r.share > 0; });
  EXPECT_GT(changed, 20);
  EXPECT_GT(untouched, 0);
  const Simulation by_type = Simulated(34, 60, {"scoped_factor:5"});
  const SimulatedEffect& t = OnlyEffect(by_type);
  EXPECT_EQ(t.covariate, "speed_mps");
  ASSERT_EQ(t.scope,
            (std::map<std::string, std::string>{{"roll_type", "ICDP-S2"}}));
  const auto [type_untouched, type_changed] = UntouchedAndChanged(
      Rows(by_type, [](const Pass&, const Mount&) { return true; }),
      [&by_type](const Row& r) {
        return by_type.data.roll_types[r.mount->roll_type] == "ICDP-S2";
      });
  EXPECT_GT(type_changed, 10);
  EXPECT_GT(type_untouched, 10);
}

// The grinder column: measurements.csv gets it, its low level reads low by
// the truth's offset (measured within 6 um), the null variant not at all.
TEST(SimulatorFamilyTest, GrinderColumnReadsLowOnOneLevel) {
  for (const char* name : {"grinder:0", "grinder_null:0"}) {
    const Simulation sim = Simulated(34, 150, {name});
    const SimulatedEffect& e = OnlyEffect(sim);
    const ExtraColumns& x = sim.data.measurement_extra;
    ASSERT_EQ(x.factor_names, std::vector<std::string>{"grinder"});
    ASSERT_EQ(x.factor.at(0).size(), sim.data.measurements.size());
    const bool null = std::string(name) == "grinder_null:0";
    EXPECT_EQ(e.null_effect, null);
    EXPECT_EQ(e.covariate, "grinder");
    const double offset = null ? 0 : e.parameters.at("offset_um");
    if (!null) {
      EXPECT_EQ(e.levels, std::vector<std::string>{"G2"});
      EXPECT_LE(offset, -8);
      EXPECT_GE(offset, -25);
    }
    double sum[2] = {0, 0};
    int n[2] = {0, 0};
    const std::vector<Row> rows =
        Rows(sim, [](const Pass&, const Mount&) { return true; });
    for (size_t i = 0; i < rows.size(); ++i) {
      const int level = x.factor[0][i];
      EXPECT_NEAR(rows[i].noise_free - rows[i].baseline,
                  level == 1 ? offset : 0, 1e-9);
      sum[level] += rows[i].measured - rows[i].baseline;
      ++n[level];
    }
    const double share = static_cast<double>(n[1]) / (n[0] + n[1]);
    EXPECT_NEAR(share, e.parameters.at("share"), 0.06);
    EXPECT_NEAR(sum[1] / n[1] - sum[0] / n[0], offset, 6) << name;
  }
}

TEST(SimulatorFamilyTest, CalendarDriftFollowsCampaignOrder) {
  // rate_linear: the ratio grows linearly with the campaign index.
  const Simulation rate = Simulated(35, 100, {"calendar_drift:0"});
  const SimulatedEffect& e = OnlyEffect(rate);
  EXPECT_EQ(e.covariate, "rolled_at");
  EXPECT_EQ(e.form, "rate_linear");
  for (const Row& r :
       Rows(rate, [](const Pass&, const Mount&) { return true; })) {
    EXPECT_NEAR(r.noise_free / r.baseline,
                1 + e.strength * r.m->campaign / 99.0, 1e-9);
  }
  // reading_step: readings from the step on read low by the offset.
  const Simulation reading = Simulated(35, 100, {"calendar_drift:3"});
  const SimulatedEffect& f = OnlyEffect(reading);
  EXPECT_EQ(f.covariate, "measured_at");
  int low = 0;
  for (const Row& r :
       Rows(reading, [](const Pass&, const Mount&) { return true; })) {
    const double d = r.noise_free - r.baseline;
    EXPECT_TRUE(std::abs(d) < 1e-9 || std::abs(d - f.strength) < 1e-9) << d;
    low += d < 0;
  }
  EXPECT_GT(low, 100);
  EXPECT_LT(low, 300);
}

// Stoppages part hours in service from rolled length; with the effect the
// wear follows hours, the null variant changes no wear.
TEST(SimulatorFamilyTest, StoppagesPartHoursFromLength) {
  auto hours_length = [](const Simulation& sim) {
    std::vector<double> h, l;
    for (const Row& r :
         Rows(sim, [](const Pass&, const Mount&) { return true; })) {
      h.push_back(r.mean_hours);
      l.push_back(r.stand_length_m);
    }
    return simulator_test::Correlation(h, l);
  };
  const Simulation clean = Simulated(36, 100);
  const Simulation null = Simulated(36, 100, {"stoppages_null"});
  EXPECT_TRUE(OnlyEffect(null).null_effect);
  // Baseline-weighted mean hours since mount against the campaign's
  // length at the stand.
  EXPECT_GT(hours_length(clean), 0.5);
  EXPECT_LT(hours_length(null), hours_length(clean) - 0.2)
      << hours_length(null) << " vs " << hours_length(clean);
  for (const Row& r :
       Rows(null, [](const Pass&, const Mount&) { return true; })) {
    EXPECT_NEAR(r.noise_free / r.baseline, 1, 1e-9);
  }
  const Simulation on = Simulated(36, 100, {"stoppages:0"});
  const SimulatedEffect& e = OnlyEffect(on);
  EXPECT_EQ(e.covariate, "hours_since_mount");
  std::vector<double> ratio, hours;
  for (const Row& r :
       Rows(on, [](const Pass&, const Mount&) { return true; })) {
    // Linear in hours: the baseline-weighted mean hours give the ratio.
    EXPECT_NEAR(r.noise_free / r.baseline, 1 + e.strength * r.mean_hours / 10,
                1e-9);
  }
}

// A covariate effect on lubricated passes only: rolls of campaigns rolled
// dry are untouched, mostly lubricated ones change; the truth says it
// lives in temperature x lubrication and that no term describes it.
TEST(SimulatorFamilyTest, LubricationScopedEffectActsOnItsPassesOnly) {
  const Simulation sim = Simulated(38, 80, {"inexpressible_lubrication:4"});
  const SimulatedEffect& e = OnlyEffect(sim);
  EXPECT_FALSE(e.expressible);
  EXPECT_EQ(e.mismatch, "temperature_c x lubrication");
  const auto [untouched, changed] = UntouchedAndChanged(
      Rows(sim, [](const Pass& p, const Mount&) { return p.lubrication; }),
      [](const Row& r) { return r.share > 0; });
  EXPECT_GT(untouched, 20);
  EXPECT_GT(changed, 10);
}

// The night shift changes the passes rolled 22-06 h UTC only: a roll whose
// passes were all rolled by day is untouched.
TEST(SimulatorFamilyTest, NightShiftActsOnNightPassesOnly) {
  const Simulation sim = Simulated(39, 80, {"inexpressible_night_shift:0"});
  const SimulatedEffect& e = OnlyEffect(sim);
  EXPECT_FALSE(e.expressible);
  EXPECT_EQ(e.mismatch, "time of day");
  const std::vector<Row> rows = Rows(sim, [](const Pass& p, const Mount&) {
    const int64_t hour = p.rolled_at % 86400 / 3600;
    return hour >= 22 || hour < 6;
  });
  const auto [day, changed] =
      UntouchedAndChanged(rows, [](const Row& r) { return r.share > 0; });
  int all_night = 0;
  for (const Row& r : rows) {
    if (r.share != 1) continue;
    EXPECT_NEAR(r.noise_free / r.baseline, 1 + e.strength, 1e-9);
    ++all_night;
  }
  EXPECT_GT(day, 20);
  EXPECT_GT(all_night, 20);
  EXPECT_GE(changed, all_night);
}

// Bad rolls: each physical roll either carries the multiplier on every
// reading or on none, and about one in ten does.
TEST(SimulatorFamilyTest, BadRollsWearMoreWheneverMounted) {
  const Simulation sim = Simulated(40, 200, {"inexpressible_bad_rolls"});
  const SimulatedEffect& e = OnlyEffect(sim);
  EXPECT_EQ(e.mismatch, "roll_id");
  std::map<std::string, std::set<bool>> bad;
  for (const Row& r :
       Rows(sim, [](const Pass&, const Mount&) { return true; })) {
    const double ratio = r.noise_free / r.baseline;
    const bool more = std::abs(ratio - e.strength) < 1e-9;
    EXPECT_TRUE(more || std::abs(ratio - 1) < 1e-9) << ratio;
    bad[r.mount->roll_id].insert(more);
  }
  int num_bad = 0;
  for (const auto& [id, kinds] : bad) {
    EXPECT_EQ(kinds.size(), 1u) << id;
    num_bad += kinds.count(true) > 0;
  }
  EXPECT_GE(num_bad, 2);
  EXPECT_LE(num_bad, static_cast<int>(bad.size()) / 4);
}

// Roll service: each reading carries the multiplier of its roll's earlier
// campaigns n, as RollCampaignsBefore counts them from the serials and the
// campaign order (the diagnosis's locate-only covariate): 1 + s n for the
// linear variant, 1 + s from the third earlier campaign for the step.
TEST(SimulatorFamilyTest, RollServiceFollowsEachRollsEarlierCampaigns) {
  for (int variant : {0, 1}) {
    const Simulation sim = Simulated(
        42, 120, {"inexpressible_roll_service:" + std::to_string(variant)});
    const SimulatedEffect& e = OnlyEffect(sim);
    EXPECT_EQ(e.mismatch, "roll_campaigns_before");
    EXPECT_TRUE(e.covariate.empty());
    const std::vector<int> n = RollCampaignsBefore(sim.data);
    ASSERT_EQ(n.size(), sim.data.mounts.size());
    int max_n = 0, stepped = 0, rows = 0;
    for (const Row& r :
         Rows(sim, [](const Pass&, const Mount&) { return true; })) {
      const int k = n[r.mount - sim.data.mounts.data()];
      const double m = variant == 0 ? 1 + e.strength * k
                       : k >= 3     ? 1 + e.strength
                                    : 1.0;
      EXPECT_NEAR(r.noise_free / r.baseline, m, 1e-9) << "n = " << k;
      max_n = std::max(max_n, k);
      stepped += k >= 3;
      ++rows;
    }
    // Rolls come back: most readings are of rolls that served before.
    EXPECT_GE(max_n, 5);
    EXPECT_GT(stepped, rows / 4);
    EXPECT_LT(stepped, rows);
  }
}

// grade_roll_position (variant 0: S355 at F7/bottom): only the readings of
// that roll position with S355 passes change, the others are Wang's law.
TEST(SimulatorFamilyTest, GradeRollPositionActsAtItsRollPositionOnly) {
  const Simulation sim = Simulated(41, 80, {"grade_roll_position:0"});
  const SimulatedEffect& e = OnlyEffect(sim);
  EXPECT_EQ(e.covariate, "grade");
  EXPECT_EQ(e.scope, (std::map<std::string, std::string>{
                         {"stand", "F7"}, {"position", "bottom"}}));
  ASSERT_EQ(e.levels, std::vector<std::string>{"S355"});
  const int s355 = static_cast<int>(
      std::find(sim.data.grades.begin(), sim.data.grades.end(), "S355") -
      sim.data.grades.begin());
  const auto [untouched, changed] = UntouchedAndChanged(
      Rows(sim,
           [s355](const Pass& p, const Mount&) { return p.grade == s355; }),
      [](const Row& r) {
        return r.share > 0 && r.m->stand == 7 &&
               r.m->position == Position::kBottom;
      });
  EXPECT_GT(untouched, 3 * changed);  // three other roll positions
  EXPECT_GT(changed, 20);
}

TEST(SimulatorFamilyTest, InexpressibleEffectsSayWhereTheMismatchLives) {
  for (const char* name : {"inexpressible_order", "inexpressible_interaction",
                           "inexpressible_random_walk", "inexpressible_bursts",
                           "inexpressible_restart"}) {
    const Simulation sim = Simulated(37, 60, {name});
    const SimulatedEffect& e = OnlyEffect(sim);
    EXPECT_FALSE(e.expressible) << name;
    EXPECT_FALSE(e.mismatch.empty()) << name;
    EXPECT_EQ(e.covariate, "") << name;
    int changed = 0;
    for (const Row& r :
         Rows(sim, [](const Pass&, const Mount&) { return true; })) {
      changed += std::abs(r.noise_free / r.baseline - 1) > 0.03;
    }
    EXPECT_GT(changed, 20) << name;
  }
  // order: only rolls that saw a hard grade early in the campaign change.
  const Simulation order = Simulated(37, 60, {"inexpressible_order:0"});
  const SimulatedEffect& e = OnlyEffect(order);
  const double n = e.parameters.at("n_coils");
  for (const Row& r : Rows(order, [&](const Pass&p, const Mount&) {
         const std::string& g = order.data.grades[p.grade];
         return p.seq - 1 < n && (g == "HSLA420" || g == "DP600" ||
                                  g == "API-X65" || g == "API-X70");
       })) {
    EXPECT_NEAR(r.noise_free / r.baseline, 1 + e.strength * r.share, 1e-9);
  }
}

// Gross grinder errors combine with any effect: the noise-free wear is the
// effect's, a share of the readings carry a gross error.
TEST(SimulatorFamilyTest, GrossErrorsCombineWithAnyEffect) {
  SimulatorOptions o;
  o.seed = 38;
  o.num_campaigns = 150;
  o.effects = {"grade_stand"};
  const Simulation plain = Simulate(o).value();
  o.gross_error_fraction = 0.05;
  const Simulation gross = Simulate(o).value();
  ASSERT_EQ(gross.truth.effects.size(), 2u);
  EXPECT_EQ(gross.truth.effects[0].name, "gross_errors");
  EXPECT_EQ(gross.truth.effects[0].parameters.at("fraction"), 0.05);
  EXPECT_EQ(gross.truth.noise_free_wear_um, plain.truth.noise_free_wear_um);
  int n = 0;
  for (double g : gross.truth.gross_error_um) n += g != 0;
  // 600 readings: sd of the share 0.009; within 3 sd.
  EXPECT_NEAR(static_cast<double>(n) / gross.truth.gross_error_um.size(), 0.05,
              0.027);
  std::string error;
  o.effects = {"gross_errors"};
  EXPECT_FALSE(o.IsValid(&error));
  o.gross_error_fraction = 0;
  o.effects = {"grade_stand:6"};
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("unknown effect 'grade_stand:6'"), std::string::npos);
  o.effects = {"grade_stand", "grade_stand:1"};
  EXPECT_FALSE(o.IsValid(&error));
  o.effects = {"grade_stand:5", "grinder:2", "temperature"};
  EXPECT_TRUE(o.IsValid(&error)) << error;
}

// The variant comes from the seed without a suffix, and is the same one
// that NAME:K names.
TEST(SimulatorFamilyTest, VariantFromSeedOrSuffix) {
  std::set<double> variants;
  for (uint64_t seed = 1; seed <= 12; ++seed) {
    const Simulation s = Simulated(seed, 10, {"scoped"});
    const int v = static_cast<int>(OnlyEffect(s).parameters.at("variant"));
    variants.insert(v);
    const Simulation k = Simulated(seed, 10, {"scoped:" + std::to_string(v)});
    EXPECT_EQ(k.truth.noise_free_wear_um, s.truth.noise_free_wear_um);
  }
  EXPECT_GE(variants.size(), 4u);
}

}  // namespace
}  // namespace rollwear
