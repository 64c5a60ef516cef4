// Calendar steps (docs/diagnosis.md, the candidate table: a change on one
// day): a new roll supplier from one day on, with unchanged roll-type
// labels, is named as a step of started_at on that day with its
// multiplier, and a gauge recalibrated on one day as a step of the reading.
// Before session 12 the quantile-binned form put its edges where the
// campaigns fall, not where the change is, and the bin holding the change
// left part of it unexplained (supplier change gap/floor 1.086 on average).
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "core/diagnosis/diagnosis.h"
#include "core/sim/simulator.h"
#include "tests/core/simulator_test_util.h"
#include "tests/core/test_size.h"

namespace rollwear {
namespace {

constexpr double kSecondsPerDay = 86400.0;

// The first campaign's start, in days since the epoch (the covariate's
// unit, core/model/covariates.cc); the simulator counts its days from it.
double FirstStartDays(const Dataset& d) {
  double first = INFINITY;
  for (const Campaign& c : d.campaigns) {
    first = std::min(first, static_cast<double>(c.started_at) / kSecondsPerDay);
  }
  return first;
}

// Diagnoses `sim` and expects one finding, on `covariate`, of `shape`, with
// a single change point (one edge); returns it (or a default Finding after
// a failed expectation).
Finding OneStep(const Simulation& sim, const std::string& covariate,
                const std::string& shape) {
  StatusOr<DiagnosisReport> r = Diagnose(sim.data, DiagnosisOptions{});
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  if (!r.ok() || r->findings.size() != 1) {
    ADD_FAILURE() << "expected one finding";
    return Finding{};
  }
  const Finding& f = r->findings[0];
  EXPECT_EQ(f.covariate, covariate) << f.explanation;
  EXPECT_EQ(f.shape, shape) << f.explanation;
  EXPECT_EQ(f.parameters.count("edge0"), 1u) << f.explanation;
  EXPECT_EQ(f.parameters.count("edge1"), 0u) << f.explanation;
  return f;
}

TEST(DiagnosisStepTest, ANewSupplierIsNamedAsAStepOnItsDay) {
  const Simulation sim =
      simulator_test::Simulated(104, kPaperCampaigns, {"supplier_change"});
  const SimulatedEffect& truth = sim.truth.effects.at(0);
  const Finding f = OneStep(sim, "started_at", "step_up");
  ASSERT_EQ(f.parameters.count("edge0"), 1u);
  // The change day to within a day (campaigns start about every 6 hours),
  // and the new supplier's multiplier 1 + gamma (1.25) to within 0.05, a
  // fifth of the change.
  const double day = FirstStartDays(sim.data) + truth.parameters.at("day_step");
  EXPECT_NEAR(f.parameters.at("edge0"), day, 1.0) << f.explanation;
  EXPECT_NEAR(f.parameters.at("bin1_multiplier"),
              1 + truth.parameters.at("gamma"), 0.05)
      << f.explanation;
  EXPECT_NE(f.explanation.find("a step"), std::string::npos) << f.explanation;
}

// calendar_drift variant 3: the reading steps 31.2 um low from campaign
// ceil(0.386 x 394) on (a gauge recalibrated): a step of measured_at, the
// reading's own calendar, not a wear physics.
TEST(DiagnosisStepTest, AGaugeThatStepsIsNamedAsAStepOfTheReading) {
  const Simulation sim =
      simulator_test::Simulated(104, kPaperCampaigns, {"calendar_drift:3"});
  const SimulatedEffect& truth = sim.truth.effects.at(0);
  const Finding f = OneStep(sim, "measured_at", "step_down");
  ASSERT_EQ(f.parameters.count("edge0"), 1u);
  const int n = static_cast<int>(sim.data.campaigns.size());
  const int first_low = static_cast<int>(
      std::ceil(truth.parameters.at("step_at_fraction") * (n - 1)));
  ASSERT_LT(first_low, n);
  const double day =
      static_cast<double>(sim.data.campaigns[first_low].started_at) /
      kSecondsPerDay;
  EXPECT_NEAR(f.parameters.at("edge0"), day, 1.0) << f.explanation;
  // The offset to within 4 um (the simulator draws 15..35 um).
  EXPECT_NEAR(f.parameters.at("bin1_offset_um"),
              truth.parameters.at("offset_um"), 4.0)
      << f.explanation;
}

}  // namespace
}  // namespace rollwear
