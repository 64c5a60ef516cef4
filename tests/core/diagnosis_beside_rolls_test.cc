// The look again beside the rolls' own scatter (diagnosis_look_again.cc):
// every mill's rolls scatter a little in their own wear resistance, and a
// true effect whose round left that scatter behind along roll_id used to be
// refused as "located structure remains (roll_id ...)" (before session 37
// these mills' grinder offset and roll type at a stand were not named:
// only the rolls, or nothing). Judged on the model
// that carries a per-roll term, the effect is named and the rolls' scatter
// after it; with the scatter alone only the rolls are named. The nested
// test there counts the readings of one campaign with the design effect of
// their shared noise (CampaignDesignEffect, Scott & Holt 1982).
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/base/random.h"
#include "core/diagnosis/diagnosis_look_again.h"
#include "core/diagnosis/diagnosis_stages_internal.h"
#include "tests/core/simulator_test_util.h"
#include "tests/core/test_size.h"

namespace rollwear {
namespace {

constexpr int kRollScatterCampaigns = test_size::FullOr(300, 200);
// Under the sanitizers one seed (test_size.h).
constexpr int kSeeds = test_size::FullOr(2, 1);
// Each roll's lifelong wear factor: sd 8 % of its log, enough that roll_id
// locates the mismatch most strongly before the effect is modelled.
constexpr double kRollFactorSd = 0.08;

DiagnosisReport DiagnoseWithRollScatter(uint64_t seed,
                                        std::vector<std::string> effects) {
  const Simulation sim = simulator_test::Simulated(
      seed, kRollScatterCampaigns, std::move(effects), 0, kRollFactorSd);
  StatusOr<DiagnosisReport> r = Diagnose(sim.data, DiagnosisOptions{});
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  return r.ok() ? std::move(r).value() : DiagnosisReport{};
}

std::vector<std::string> Mechanisms(const DiagnosisReport& r) {
  std::vector<std::string> out;
  for (const Finding& f : r.findings) out.push_back(f.mechanism);
  return out;
}

void ExpectNamedBesideTheRolls(const std::string& effect,
                               const std::string& mechanism) {
  for (int s = 0; s < kSeeds; ++s) {
    const DiagnosisReport r = DiagnoseWithRollScatter(101 + s, {effect});
    const std::vector<std::string> named = Mechanisms(r);
    EXPECT_EQ(named,
              (std::vector<std::string>{mechanism, "roll_wear_resistance"}))
        << effect << " seed " << 101 + s << "\n"
        << simulator_test::DescribeReport(r);
  }
}

TEST(DiagnosisBesideRollsTest, AGrinderOffsetIsNamedBesideTheRollsScatter) {
  ExpectNamedBesideTheRolls("grinder:0", "measurement_offset_by_grinder");
}

TEST(DiagnosisBesideRollsTest,
     ARollTypeAtOneStandIsNamedBesideTheRollsScatter) {
  ExpectNamedBesideTheRolls("roll_type_stand:0",
                            "roll_type_by_stand_interaction");
}

TEST(DiagnosisBesideRollsTest, TheRollsScatterAloneNamesOnlyTheRolls) {
  for (int s = 0; s < kSeeds; ++s) {
    const DiagnosisReport r = DiagnoseWithRollScatter(101 + s, {});
    EXPECT_EQ(Mechanisms(r), (std::vector<std::string>{"roll_wear_resistance"}))
        << "seed " << 101 + s << "\n"
        << simulator_test::DescribeReport(r);
  }
}

// A state of `campaigns` campaigns of 6 readings each; the readings' noise
// sd differs (0.5 to 2, in *sd, indexed like td.obs) and each reading's
// standardised value is a shared campaign part (sd `shared`) plus its own
// (sd `own`). The training set leaves out every fifth campaign and lists
// the rest backwards, so that st.train[i] != i.
diag::DiagnosisState ClusteredState(uint64_t seed, int campaigns, double shared,
                                    double own, std::vector<double>* sd) {
  diag::DiagnosisState st;
  Random rng(seed);
  for (int c = 0; c < campaigns; ++c) {
    const double a = rng.Normal(0, shared);
    for (int i = 0; i < 6; ++i) {
      TermObservation ob;
      ob.campaign = c;
      sd->push_back(0.5 + 0.5 * static_cast<double>(st.td.obs.size() % 4));
      ob.measured_um = (a + rng.Normal(0, own)) * sd->back();
      st.td.obs.push_back(ob);
    }
  }
  for (int o = static_cast<int>(st.td.obs.size()) - 1; o >= 0; --o) {
    if (st.td.obs[o].campaign % 5 != 0) st.train.push_back(o);
  }
  return st;
}

// Predictions aligned with st.train: `after` 0, `before` the candidate's
// contribution x (in sd units) below it, so that the residuals under the
// fitted model are the readings themselves.
std::vector<double> Before(const diag::DiagnosisState& st,
                           const std::vector<double>& sd,
                           const std::vector<double>& x_by_obs) {
  std::vector<double> out;
  for (int o : st.train) out.push_back(-x_by_obs[o] * sd[o]);
  return out;
}

TEST(DiagnosisBesideRollsTest, TheDesignEffectCountsCampaignsNotReadings) {
  // rho_e = 0.36 / (0.36 + 0.64) = 0.36 within campaigns of 6.
  std::vector<double> sd;
  const diag::DiagnosisState st = ClusteredState(5, 1500, 0.6, 0.8, &sd);
  const std::vector<double> after(st.train.size(), 0.0);
  Random rng(6);
  // A campaign-level candidate: the same standardised contribution on a
  // campaign's six readings, so rho_x = 0.99 and deff = 1 + 5 x 0.36 x
  // 0.99 = 2.8; and one that varies only between the readings of a
  // campaign, each reading its own unit.
  std::vector<double> campaign_level(st.td.obs.size()),
      reading_level(st.td.obs.size());
  for (size_t o = 0; o < st.td.obs.size(); o += 6) {
    const double x = rng.Normal(0, 1);
    for (size_t j = 0; j < 6; ++j) {
      campaign_level[o + j] = x;
      reading_level[o + j] = rng.Normal(0, 1);
    }
  }
  EXPECT_NEAR(
      diag::CampaignDesignEffect(st, sd, Before(st, sd, campaign_level), after),
      2.8, 0.3);
  EXPECT_LT(
      diag::CampaignDesignEffect(st, sd, Before(st, sd, reading_level), after),
      1.1);
  // No shared noise: no design effect whatever the candidate.
  std::vector<double> sd_independent;
  const diag::DiagnosisState independent =
      ClusteredState(7, 1500, 0.0, 1.0, &sd_independent);
  EXPECT_LT(diag::CampaignDesignEffect(
                independent, sd_independent,
                Before(independent, sd_independent, campaign_level),
                std::vector<double>(independent.train.size(), 0.0)),
            1.15);
}

}  // namespace
}  // namespace rollwear
