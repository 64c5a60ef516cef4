// The grade x campaign-order check (core/diagnosis/diagnosis_order.cc,
// docs/diagnosis.md "Grade by campaign order") on the simulator's
// inexpressible order effect: a hard grade rolled in the first 20..35 coils
// after the roll change wears x(1 + s) more, which no term describes. The
// engine is told nothing; it must not name a campaign-order term (the
// effect is not one: the soft grades' opening coils wear as the law says)
// and must say where the mismatch lives. Before the check, seed 102 was
// called `no_significant_mismatch` (validation gap 10 % above the noise
// floor) and seed 109 was named `campaign_coils_before` everywhere.
#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/diagnosis/diagnosis.h"
#include "core/sim/simulator.h"
#include "tests/core/simulator_test_util.h"
#include "tests/core/test_size.h"

namespace rollwear {
namespace {

// The paper's size, also under the sanitizers: these seeds were checked at
// this size (the effect is weak: at 300 campaigns seed 102 is quiet).

DiagnosisReport DiagnoseSeed(uint64_t seed) {
  const Simulation sim =
      simulator_test::Simulated(seed, kPaperCampaigns, {"inexpressible_order"});
  StatusOr<DiagnosisReport> r = Diagnose(sim.data, DiagnosisOptions{});
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  return r.ok() ? std::move(r).value() : DiagnosisReport{};
}

// The entry of the check, or nullptr.
const Unexplained* OrderEntry(const DiagnosisReport& r) {
  const auto it = std::find_if(
      r.unexplained.begin(), r.unexplained.end(), [](const Unexplained& u) {
        return u.dimension == "grade_by_campaign_order";
      });
  return it == r.unexplained.end() ? nullptr : &*it;
}

// Seed 102: nothing else locates it. The place is a hard grade (DP600)
// whose coils rolled only later in the campaign are over-predicted: its K
// took up the opening coils' extra wear.
TEST(DiagnosisOrderTest, AHardGradesOpeningCoilsAreLocatedNotCalledNoise) {
  const DiagnosisReport r = DiagnoseSeed(102);
  EXPECT_TRUE(r.findings.empty());
  EXPECT_EQ(r.verdict, "mismatch_located_unexplained");
  const Unexplained* u = OrderEntry(r);
  ASSERT_NE(u, nullptr);
  EXPECT_LT(u->p_adjusted, 1e-6);
  EXPECT_NE(u->where.find("DP600"), std::string::npos) << u->where;
  EXPECT_LT(u->mean_residual_um, -5.0) << u->where;
}

// Seed 109: campaign-order terms everywhere fit part of it; the guard
// looks again with the check and refuses them, so nothing is named.
TEST(DiagnosisOrderTest, ACampaignOrderTermEverywhereIsNotNamedForIt) {
  const DiagnosisReport r = DiagnoseSeed(109);
  EXPECT_TRUE(r.findings.empty()) << r.findings.front().covariate;
  EXPECT_EQ(r.verdict, "mismatch_located_unexplained");
  ASSERT_NE(OrderEntry(r), nullptr);
  const bool refused = std::any_of(
      r.runners_up.begin(), r.runners_up.end(), [](const RunnerUp& u) {
        return u.reason.find("grade x campaign-order structure remains") !=
               std::string::npos;
      });
  EXPECT_TRUE(refused);
}

}  // namespace
}  // namespace rollwear
