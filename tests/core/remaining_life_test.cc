// Remaining life until a wear limit (core/model/remaining_life.h): the
// formula on a hand-built state, and the coverage of its interval on a
// simulated mill. For every measured roll of the validation campaigns (not
// fitted on), the model predicts at mid-campaign (half the coils rolled)
// the remaining length until the position's limit; the truth is the length
// the rest of the campaign actually rolled until the roll's true wear
// reached it. The true wear along the campaign is the grinder's final
// reading (the true wear plus gauge noise of sd 8 µm) spread over the coils
// in proportion to the true law's increments (Wang's law with the
// simulator's true kS per grade; kF and kR are constant within a roll's
// campaign, so the shares need only those).
#include "core/model/remaining_life.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "core/fit/study.h"
#include "core/model/aggregation.h"
#include "core/model/metrics.h"
#include "core/model/predictor.h"
#include "tests/core/simulator_test_util.h"

namespace rollwear {
namespace {

TEST(RemainingLife, LinearInTheMixSoFarWithAnIntervalAroundIt) {
  WearModel model;
  model.noise_sd_um = 4;
  model.noise_rel = 0.1;
  RollWearState s;
  s.wear_um = 100;
  s.rolled_length_m = 20000;
  s.coils = 25;
  const std::optional<RemainingLife> life = PredictRemainingLife(model, s, 300);
  ASSERT_TRUE(life.has_value());
  EXPECT_NEAR(life->length_m, 40000, 1e-9);
  EXPECT_NEAR(life->coils, 50, 1e-12);
  // Upper bound 1.96 sqrt(16 + (0.1 * 100 f)^2) + 100 f = 300 at f < 3, the
  // lower one at f > 3; both solve the bound's equation.
  const double f_hi = 1 + life->length_lo_m / 20000;
  const double f_lo = 1 + *life->length_hi_m / 20000;
  auto half = [](double f) {
    return 1.959963984540054 * std::sqrt(16 + 100 * f * f);
  };
  EXPECT_NEAR(100 * f_hi + half(f_hi), 300, 1e-6);
  EXPECT_NEAR(100 * f_lo - half(f_lo), 300, 1e-6);
  EXPECT_NEAR(life->coils_lo, 25 * (f_hi - 1), 1e-9);
  // Over the limit: nothing left; no wear yet: no answer.
  EXPECT_EQ(PredictRemainingLife(model, s, 80)->length_m, 0);
  EXPECT_EQ(PredictRemainingLife(model, s, 80)->length_lo_m, 0);
  s.wear_um = 0;
  EXPECT_FALSE(PredictRemainingLife(model, s, 300).has_value());
}

// One measured roll of a campaign: its passes in coil order.
struct RollRun {
  int campaign = 0, slot = 0;
  std::vector<int> passes;  // indices into data.passes
  double final_um = 0;      // grinder's reading
  const Mount* mount = nullptr;
};

std::vector<RollRun> MeasuredRolls(const Dataset& d,
                                   const std::vector<int>& campaigns) {
  std::map<std::pair<int, int>, RollRun> runs;
  for (int c : campaigns) {
    for (const Measurement& m : d.measurements) {
      if (m.campaign != c) continue;
      RollRun& r = runs[{c, RollPositionSlot(m.stand, m.position)}];
      r.campaign = c;
      r.slot = RollPositionSlot(m.stand, m.position);
      r.final_um = m.wear_center_um;
    }
  }
  for (const Mount& m : d.mounts) {
    auto it = runs.find({m.campaign, RollPositionSlot(m.stand, m.position)});
    if (it != runs.end()) it->second.mount = &m;
  }
  for (size_t i = 0; i < d.passes.size(); ++i) {
    const Pass& p = d.passes[i];
    for (Position pos : {Position::kTop, Position::kBottom}) {
      auto it = runs.find({p.campaign, RollPositionSlot(p.stand, pos)});
      if (it != runs.end()) it->second.passes.push_back(static_cast<int>(i));
    }
  }
  std::vector<RollRun> out;
  for (auto& [key, r] : runs) {
    std::stable_sort(r.passes.begin(), r.passes.end(), [&](int a, int b) {
      return d.passes[a].seq < d.passes[b].seq;
    });
    if (r.mount != nullptr && r.passes.size() >= 20) out.push_back(r);
  }
  return out;
}

// The true law's wear increment of each of the roll's coils, up to the
// factors constant in its campaign (kF, kR), and each coil's length; returns
// the increments' sum.
double TrueIncrements(const Simulation& sim, const RollRun& r,
                      std::vector<double>* inc, std::vector<double>* len) {
  const Dataset& d = sim.data;
  double total = 0;
  for (int pi : r.passes) {
    const Pass& p = d.passes[pi];
    const PassLoadInput in{p.force_kn,          p.width_mm,
                           p.length_m,          p.entry_thickness_mm,
                           p.exit_thickness_mm, r.mount->diameter_mm,
                           r.mount->hardness_hb};
    inc->push_back(sim.truth.k_grade.at(d.grades[p.grade]) *
                   Load(WearLaw::kWang, in, 0));
    len->push_back(p.length_m);
    total += inc->back();
  }
  return total;
}

TEST(RemainingLife, IntervalCoversTheRestOfSimulatedCampaigns) {
  const Simulation sim = simulator_test::Simulated(61, 240);
  const Dataset& d = sim.data;
  const DatasetIndex index(d);
  const WearStatistics stats = *Aggregate(d, index, WearLaw::kWang);
  const CampaignSplit split = SplitCampaigns(stats, 2.0 / 3.0, 1);
  StatusOr<SplitCalibration> run =
      CalibrateOnSplit(stats, split, CalibrationOptions{});
  ASSERT_TRUE(run.ok()) << run.status().ToString();
  const WearModel& model = run->result.model;

  const std::vector<RollRun> rolls = MeasuredRolls(d, split.validation);
  // Each position's limit: the 30 % quantile of its final readings, so
  // most rolls reach it.
  std::map<int, std::vector<double>> finals;
  for (const RollRun& r : rolls) finals[r.slot].push_back(r.final_um);
  std::map<int, double> limit;
  for (auto& [slot, v] : finals) {
    std::sort(v.begin(), v.end());
    limit[slot] = v[static_cast<size_t>(0.3 * (v.size() - 1))];
  }
  int n = 0, covered = 0, censored = 0, unbounded = 0;
  std::vector<double> rel_error;
  for (const RollRun& r : rolls) {
    const double lim = limit[r.slot];
    std::vector<double> inc, len;
    const double total = TrueIncrements(sim, r, &inc, &len);
    const size_t mid = r.passes.size() / 2;
    RollWearState state = MountRoll(
        model, RollPositionName(SlotStand(r.slot), SlotPosition(r.slot)),
        d.roll_types[r.mount->roll_type], r.mount->diameter_mm,
        r.mount->hardness_hb);
    double true_um = 0;
    for (size_t j = 0; j < mid; ++j) {
      AddPass(model, PassInputOf(d, d.passes[r.passes[j]]), &state);
      true_um += r.final_um * inc[j] / total;
    }
    if (true_um >= lim) continue;  // already past the limit at mid-campaign
    // The length the rest of the campaign rolled until the true wear
    // reached the limit (linear within the coil that crosses it).
    double rolled = 0;
    bool reached = false;
    for (size_t j = mid; j < r.passes.size() && !reached; ++j) {
      const double add = r.final_um * inc[j] / total;
      if (true_um + add >= lim) {
        rolled += len[j] * (lim - true_um) / add;
        reached = true;
      } else {
        true_um += add;
        rolled += len[j];
      }
    }
    if (!reached) {
      ++censored;
      continue;
    }
    const std::optional<RemainingLife> life =
        PredictRemainingLife(model, state, lim);
    ASSERT_TRUE(life.has_value());
    ++n;
    if (!life->length_hi_m) ++unbounded;
    const double hi = life->length_hi_m.value_or(1e300);
    covered += rolled >= life->length_lo_m && rolled <= hi;
    rel_error.push_back(std::abs(life->length_m - rolled) / rolled);
  }
  std::sort(rel_error.begin(), rel_error.end());
  const double coverage = static_cast<double>(covered) / n;
  std::printf(
      "remaining life at mid-campaign: %d rolls reached the limit (%d did "
      "not, %d unbounded intervals); 95 %% interval coverage %.3f; median "
      "relative error of the remaining length %.3f\n",
      n, censored, unbounded, coverage, rel_error[rel_error.size() / 2]);
  ASSERT_GE(n, 150);
  EXPECT_GE(coverage, 0.88);
  EXPECT_LE(coverage, 0.995);
  EXPECT_LT(rel_error[rel_error.size() / 2], 0.35);
}

}  // namespace
}  // namespace rollwear
