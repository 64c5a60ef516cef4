// Locating the mismatch along the barrel (core/diagnosis/profile_locate.h):
// quiet on the simulator's clean profiles (several seeds); a drive-side
// edge that wears more is located at the drive-side edge; one stand's
// edges that wear more are located at that stand; nothing else is named.
#include "core/diagnosis/profile_locate.h"

#include <cstdio>
#include <set>
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include "core/diagnosis/diagnosis.h"
#include "core/fit/profile_fit.h"
#include "tests/core/profile_test_util.h"

namespace rollwear {
namespace {

void Print(const BarrelLocate& l) {
  std::printf("zones: edge OS %+.2f body OS %+.2f body DS %+.2f edge DS %+.2f µm"
              " (%d rolls)\n",
              l.edge_operator_um, l.body_operator_um, l.body_drive_um,
              l.edge_drive_um, l.n_rolls);
  for (const BarrelContrast& c : l.contrasts) {
    std::printf("  %-16s %-26s %+7.2f µm (sd %.2f, n %d) p %.2g%s\n",
                c.dimension.c_str(), c.where.c_str(), c.mean_um, c.sd_um,
                c.n_rolls, c.p_value, c.significant ? "  SIGNIFICANT" : "");
  }
}

// Multiplies the reading of every edge-zone point that `pick` accepts by
// `factor` (zones under the mill's own model and its fitted shape).
template <typename Pick>
void ScaleEdges(const CalibratedMill& mill, double factor, Pick pick,
                Dataset* data) {
  const DatasetIndex index(*data);
  StatusOr<ProfileFit> fit = FitProfileShape(mill.model, *data, index, mill.split);
  ASSERT_TRUE(fit.ok());
  std::vector<int> all(data->campaigns.size());
  for (size_t c = 0; c < all.size(); ++c) all[c] = static_cast<int>(c);
  // ProfileResiduals goes by roll in data order within a roll; match the
  // points back by (campaign, slot, x).
  std::set<std::tuple<int, int, double>> edge;
  for (const ProfileResidual& r :
       ProfileResiduals(mill.model, fit->shape, *data, index, all)) {
    if (r.edge && pick(r)) edge.insert({r.campaign, r.slot, r.x_mm});
  }
  for (ProfilePoint& p : data->profile_points) {
    if (edge.count({p.campaign, RollPositionSlot(p.stand, p.position), p.x_mm})) {
      p.wear_um *= factor;
    }
  }
}

TEST(ProfileLocateTest, QuietOnCleanProfiles) {
  for (uint64_t seed : {11, 21, 31}) {
    const CalibratedMill mill = seed == 11 ? WithProfiles() : [&] {
      return Calibrated(true, seed, 90);
    }();
    const DatasetIndex index(mill.sim.data);
    StatusOr<BarrelLocate> l =
        LocateAlongBarrel(mill.model, mill.sim.data, index, mill.split);
    ASSERT_TRUE(l.ok()) << l.status().ToString();
    std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
    Print(*l);
    EXPECT_FALSE(l->any_significant()) << "seed " << seed;
  }
}

TEST(ProfileLocateTest, DriveSideEdgeThatWearsMoreIsLocatedThere) {
  const CalibratedMill& mill = WithProfiles();
  Dataset data = mill.sim.data;
  ScaleEdges(mill, 1.15, [](const ProfileResidual& r) { return r.x_mm > 0; },
             &data);
  const DatasetIndex index(data);
  StatusOr<BarrelLocate> l = LocateAlongBarrel(mill.model, data, index, mill.split);
  ASSERT_TRUE(l.ok()) << l.status().ToString();
  Print(*l);
  ASSERT_TRUE(l->any_significant());
  EXPECT_EQ(l->contrasts[0].dimension, "edge_side");
  EXPECT_EQ(l->contrasts[0].where, "drive-side edge");
  EXPECT_GT(l->contrasts[0].mean_um, 0);
  EXPECT_GT(l->edge_drive_um, l->edge_operator_um);
  for (const BarrelContrast& c : l->contrasts) {
    EXPECT_FALSE(c.dimension == "body_side" && c.significant)
        << "the bodies are untouched";
  }
}

TEST(ProfileLocateTest, OneStandsEdgesAreLocatedAtThatStand) {
  const CalibratedMill& mill = WithProfiles();
  Dataset data = mill.sim.data;
  ScaleEdges(mill, 1.25,
             [](const ProfileResidual& r) { return SlotStand(r.slot) == 7; },
             &data);
  const DatasetIndex index(data);
  StatusOr<BarrelLocate> l = LocateAlongBarrel(mill.model, data, index, mill.split);
  ASSERT_TRUE(l.ok()) << l.status().ToString();
  Print(*l);
  ASSERT_TRUE(l->any_significant());
  EXPECT_EQ(l->contrasts[0].dimension, "barrel_zone@F7");
  EXPECT_GT(l->contrasts[0].mean_um, 0);
  for (const BarrelContrast& c : l->contrasts) {
    if (!c.significant) continue;
    // F7's edges, and the edges overall (which F7 lifts); no side, and not
    // F6 (the shape fitted on both stands leaves F6's edges a fraction of a
    // micron down: not material).
    EXPECT_TRUE(c.dimension == "barrel_zone@F7" || c.dimension == "barrel_zone")
        << c.dimension;
  }
}

// The whole diagnosis on profiles whose drive-side edges wear more and
// clean centre readings: nothing is named, the mismatch is located at the
// drive-side edge.
TEST(ProfileLocateTest, DiagnosisLocatesTheEdgeMismatchWithoutNamingPhysics) {
  const CalibratedMill& mill = WithProfiles();
  Dataset data = mill.sim.data;
  ScaleEdges(mill, 1.15, [](const ProfileResidual& r) { return r.x_mm > 0; },
             &data);
  StatusOr<DiagnosisReport> report = Diagnose(data, DiagnosisOptions{});
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  EXPECT_TRUE(report->findings.empty());
  EXPECT_EQ(report->verdict, "mismatch_located_unexplained");
  bool edge = false;
  for (const Unexplained& u : report->unexplained) {
    std::printf("unexplained: %s %s %+.2f µm p %.2g\n", u.dimension.c_str(),
                u.where.c_str(), u.mean_residual_um, u.p_value);
    if (u.dimension == "edge_side" && u.where == "drive-side edge") edge = true;
  }
  EXPECT_TRUE(edge);
}

}  // namespace
}  // namespace rollwear
