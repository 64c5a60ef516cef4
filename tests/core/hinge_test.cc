// The hinge family (core/model/term_family_hinge.cc), added as a plug-in:
// a wear rate that changes only beyond a knee of a pass covariate. On the
// simulator's cold_knee effect (below 895 °C the scale turns abrasive;
// above it Wang's law holds) the diagnosis names temperature with the
// hinge's side and a knee near the truth, where the log-linear and binned
// forms left structure across grades and were refused (seed 105 before
// the family: "inconsistent across grade", located, not named).
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/model/term_family.h"
#include "tests/core/simulator_test_util.h"

namespace rollwear {
namespace {

// Reduced under the sanitizers (150 campaigns, where the scorecard names
// it in 5 of 5 seeds).
TEST(HingeTest, AColdKneeIsNamedBelowItsKneeWhereTheTrendFormsWereRefused) {
  const int campaigns = test_size::FullOr(kPaperCampaigns, 150);
  for (uint64_t seed : {104u, 105u}) {
    const simulator_test::Diagnosed d =
        simulator_test::DiagnoseSimulated(seed, {"cold_knee"}, campaigns);
    ASSERT_EQ(d.report.findings.size(), 1u)
        << seed << simulator_test::DescribeReport(d.report);
    const Finding& f = d.report.findings[0];
    EXPECT_EQ(f.covariate, "temperature_c") << seed;
    EXPECT_EQ(f.form, "hinge") << seed;
    // Colder strip wears more: the multiplier falls as temperature rises.
    EXPECT_TRUE(f.shape == "decreasing" || f.shape == "decaying")
        << seed << " " << f.shape;
    EXPECT_EQ(f.mechanism, "cold_strip_hardness_and_scale") << seed;
    EXPECT_LT(f.parameters.at("scale"), 0) << seed;  // below the knee
    // The truth: exp(0.15 max(0, 895 - T) / 10 K), a knee at 895 °C.
    EXPECT_NEAR(f.parameters.at("knee"), 895.0, 10.0) << seed;
    EXPECT_GT(f.parameters.at("beta"), 0) << seed;
    EXPECT_LT(f.gap_val_after_um, f.gap_val_before_um) << seed;
  }
}

// The mechanism is named from whether the multiplier rises with the
// covariate: for a hinge that is b's sign and the side, not the profile
// over the 5th..95th percentiles, which is flat when the knee lies past
// them (it would have named the opposite physics).
TEST(HingeTest, ItRisesWithTheCovariateByItsSideAndSignEvenWhereFlat) {
  ModelTerm t;
  t.form = TermForm::kHinge;
  t.covariate = "temperature_c";
  TermWordingInput in;
  in.profile_shape = [] { return std::make_pair(std::string("flat"), false); };
  in.readable = [](double v) { return WordFormat("%.0f C", v); };
  struct Case {
    double b, scale;
    bool up;
  };
  for (const Case& c : {Case{0.5, 20, true}, Case{0.5, -20, false},
                        Case{-0.5, 20, false}, Case{-0.5, -20, true}}) {
    t.params = {c.b, 900};
    t.scale = c.scale;
    TermWording w;
    FamilyOf(TermForm::kHinge).Word(t, in, &w);
    EXPECT_EQ(w.up, c.up) << c.b << " " << c.scale;
    EXPECT_EQ(w.parameters.at("knee"), 900);
  }
  // Every bound of its box is a bracket (a knee at an edge is no knee).
  for (int j : {0, 1}) {
    EXPECT_FALSE(FamilyOf(TermForm::kHinge).BoundIsALimit(j, false));
    EXPECT_FALSE(FamilyOf(TermForm::kHinge).BoundIsALimit(j, true));
  }
}

// The family's own arithmetic: 1 on the far side of the knee, exp(b u)
// beyond it on the side the scale's sign says, and the knee's derivative
// only where the term acts.
TEST(HingeTest, TheTermActsOnlyBeyondItsKneeOnItsSide) {
  ModelTerm t;
  t.form = TermForm::kHinge;
  t.covariate = "temperature_c";
  t.params = {0.6, 900.0};
  t.scale = -20.0;  // below the knee, 20 K per unit
  double grad[2] = {9, 9};
  EXPECT_EQ(TermMultiplier(t, 920.0, grad), 1.0);
  EXPECT_EQ(grad[0], 0.0);
  EXPECT_EQ(grad[1], 0.0);
  EXPECT_NEAR(TermMultiplier(t, 860.0, grad), std::exp(0.6 * 2.0), 1e-12);
  EXPECT_NEAR(grad[0], 2.0 * std::exp(1.2), 1e-12);
  EXPECT_NEAR(grad[1], 0.6 * std::exp(1.2) / 20.0, 1e-12);
  t.scale = 20.0;  // above it
  EXPECT_EQ(TermMultiplier(t, 860.0, nullptr), 1.0);
  EXPECT_NEAR(TermMultiplier(t, 950.0, nullptr), std::exp(0.6 * 2.5), 1e-12);
  // A stored hinge needs a side.
  t.scale = 0;
  const std::optional<TermFieldError> e =
      FamilyOf(TermForm::kHinge).CheckStored(t);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->field, "scale");
}

}  // namespace
}  // namespace rollwear
