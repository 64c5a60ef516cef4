// Carriers of one mechanism (core/diagnosis/diagnosis_carriers.cc,
// docs/diagnosis.md): in a mill whose coils all have one length and follow
// each other at a steady pace, a roll's rolled length, coil count and hours
// before a pass move together; wear that grows along the campaign is then
// equally well described along each. The engine must name the mechanism,
// "the wear rate grows along the campaign", and list the quantities that
// carry it, rather than refuse them as "not distinguishable" (an
// independent generator's mills, 23 November: refused in every seed); and
// it must stay quiet on the same mill without the growth.
//
// The mill is generated here, not by the simulator (whose coils vary in
// length, so that its campaign_growth is named as rolled length alone).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/base/random.h"
#include "core/diagnosis/diagnosis.h"
#include "core/model/wear_law.h"
#include "tests/core/simulator_test_util.h"

namespace rollwear {
namespace {

constexpr int kCampaigns = 150;
constexpr double kLengthF6M = 800;
constexpr double kLengthF7M = 950;

// Campaigns of 70..110 coils of one length per stand, one every 150 s
// (+0..10 s), at F6 and F7; wear by Wang's law (F / w * L) times
// 1 + growth * (rolled length before the pass) / 50 km, with a gauge noise
// of 4 um plus 3 %.
Dataset UniformCoilMill(double growth, uint64_t seed) {
  Random rng(seed);
  Dataset d;
  d.grades = {"CQ", "HSLA"};
  d.roll_types = {"ICDP", "HSS"};
  const UnixSeconds t0 = 1767225600;  // 2026-01-01
  int coil_count = 0;
  for (int c = 0; c < kCampaigns; ++c) {
    Campaign camp;
    camp.id = "C" + std::to_string(1000 + c);
    camp.started_at = t0 + static_cast<UnixSeconds>(c) * 86400;
    const int coils = 70 + static_cast<int>(rng.Below(41));
    double wear[4] = {0, 0, 0, 0};  // F6 top, F6 bottom, F7 top, F7 bottom
    double k[4];
    for (int s = 0; s < 4; ++s) {
      const int stand = s < 2 ? 6 : 7;
      const auto pos = s % 2 == 0 ? Position::kTop : Position::kBottom;
      Mount m;
      m.campaign = c;
      m.stand = stand;
      m.position = pos;
      const int roll = static_cast<int>(rng.Below(12));
      m.roll_id = "R" + std::to_string(stand) + (s % 2 == 0 ? "T" : "B") +
                  std::to_string(roll);
      m.roll_type = roll % 2;
      m.diameter_mm = 620 + rng.Uniform(0, 60);
      m.hardness_hb = 75 + rng.Uniform(0, 5);
      d.mounts.push_back(m);
      k[s] = (stand == 6 ? 1.0e-4 : 1.2e-4) * (s % 2 == 0 ? 1.0 : 1.02) *
             (m.roll_type == 1 ? 0.9 : 1.0);
    }
    UnixSeconds t = camp.started_at;
    for (int i = 0; i < coils; ++i, ++coil_count) {
      d.coil_ids.push_back("H" + std::to_string(coil_count));
      const int grade = rng.Uniform() < 0.7 ? 0 : 1;
      const double width = 1000 + rng.Uniform(0, 500);
      const double h5 = 4 + rng.Uniform(0, 2);
      const double h6 = h5 * 0.8, h7 = h6 * 0.88;
      for (int stand : {6, 7}) {
        Pass p;
        p.campaign = c;
        p.coil = coil_count;
        p.seq = i + 1;
        p.rolled_at = t;
        p.grade = grade;
        p.stand = stand;
        p.width_mm = std::round(width);
        p.length_m = stand == 6 ? kLengthF6M : kLengthF7M;
        p.force_kn = std::round((stand == 6 ? 20000 : 14000) *
                                std::exp(rng.Normal(0, 0.12)) *
                                (grade == 1 ? 1.2 : 1.0));
        p.entry_thickness_mm = stand == 6 ? h5 : h6;
        p.exit_thickness_mm = stand == 6 ? h6 : h7;
        p.temperature_c = std::round(920 + rng.Normal(0, 15));
        p.speed_mps = 8 + rng.Uniform(0, 4);
        d.passes.push_back(p);
        const double before_m = i * p.length_m;
        const double load = p.force_kn / p.width_mm * p.length_m;
        const double multiplier = 1 + growth * before_m / 50000;
        for (int s = stand == 6 ? 0 : 2, e = s + 2; s < e; ++s) {
          wear[s] += k[s] * load * multiplier;
        }
      }
      t += 150 + static_cast<UnixSeconds>(rng.Below(11));
    }
    camp.ended_at = t + 600;
    for (int s = 0; s < 4; ++s) {
      Measurement m;
      m.campaign = c;
      m.stand = s < 2 ? 6 : 7;
      m.position = s % 2 == 0 ? Position::kTop : Position::kBottom;
      m.roll_id = d.mounts[c * 4 + s].roll_id;
      m.measured_at = camp.ended_at + 7200;
      m.wear_center_um = wear[s] + rng.Normal(0, 4 + 0.03 * wear[s]);
      d.measurements.push_back(m);
    }
    d.campaigns.push_back(camp);
  }
  return d;
}

const char* kAlongCampaign[] = {"campaign_length_before_m",
                                "campaign_coils_before", "hours_since_mount"};

// Three seeds of the mill each way (of six tried while writing this test,
// a growth of 0.4 was named with its carriers in 6 and the null was quiet in
// 6; at a growth of 0.2, 4 of 6 were named and 2 located, not named).
TEST(DiagnosisCarriersTest, GrowthAlongTheCampaignIsNamedWithItsCarriers) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    StatusOr<DiagnosisReport> r =
        Diagnose(UniformCoilMill(0.4, seed), DiagnosisOptions{});
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    ASSERT_EQ(r->verdict, "missing_physics_found");
    ASSERT_FALSE(r->findings.empty());
    const Finding& f = r->findings[0];
    EXPECT_EQ(f.mechanism, "wear_rate_growth_along_campaign") << f.explanation;
    EXPECT_TRUE(f.scope.empty()) << f.explanation;
    // The fitted covariate is first among the carriers, and every carrier
    // is one of the three quantities of the roll's service in the campaign.
    ASSERT_GE(f.carriers.size(), 2u) << f.explanation;
    EXPECT_EQ(f.carriers[0], f.covariate);
    for (const std::string& c : f.carriers) {
      EXPECT_NE(
          std::find(std::begin(kAlongCampaign), std::end(kAlongCampaign), c),
          std::end(kAlongCampaign))
          << c;
    }
    EXPECT_NE(f.explanation.find("Carried by"), std::string::npos)
        << f.explanation;
    EXPECT_LT(f.gap_val_after_um, f.gap_val_before_um);
  }
}

// Where the data can tell the carriers apart, none is listed: the
// simulator's coils vary in length (width and gauge), so its growth along
// the rolled length is named on campaign_length_before_m alone (the
// scorecard's campaign_growth seed 101).
TEST(DiagnosisCarriersTest, CarriersThatTheDataTellApartAreNotListed) {
  const simulator_test::Diagnosed d =
      simulator_test::DiagnoseSimulated(101, {"campaign_growth"});
  ASSERT_EQ(d.report.verdict, "missing_physics_found");
  ASSERT_FALSE(d.report.findings.empty());
  const Finding& f = d.report.findings[0];
  EXPECT_EQ(f.covariate, "campaign_length_before_m") << f.explanation;
  EXPECT_TRUE(f.carriers.empty()) << f.explanation;
  EXPECT_EQ(f.explanation.find("Carried by"), std::string::npos);
}

TEST(DiagnosisCarriersTest, TheSameMillWithoutGrowthIsQuiet) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    StatusOr<DiagnosisReport> r =
        Diagnose(UniformCoilMill(0.0, seed), DiagnosisOptions{});
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    EXPECT_TRUE(r->findings.empty())
        << r->findings[0].covariate << ": " << r->findings[0].explanation;
    EXPECT_EQ(r->verdict, "no_significant_mismatch");
  }
}

}  // namespace
}  // namespace rollwear
