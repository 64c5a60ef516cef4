// The spread along time at every scale (docs/diagnosis.md, "Noise checks",
// spread_time_scale_S): a few periods of 15..30 campaigns in which every
// roll's wear scatters more (the simulator's inexpressible_bursts, which no
// term describes) must be located in one of those periods, not called
// noise. Before session 12 only calendar quarters were tested for spread,
// and the scorecard's five seeds all answered no_significant_mismatch.
#include <algorithm>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "core/diagnosis/diagnosis.h"
#include "core/sim/simulator.h"
#include "tests/core/simulator_test_util.h"
#include "tests/core/test_size.h"

namespace rollwear {
namespace {


struct Range {
  int first = 0, last = -1;
};

// "campaigns 84..112" (a truth level) or "... (campaigns 87-98 in time
// order) ..." (an Unexplained::where).
Range Campaigns(const std::string& text, const char* format) {
  Range r;
  const size_t at = text.find("campaigns ");
  if (at != std::string::npos)
    std::sscanf(text.c_str() + at, format, &r.first, &r.last);
  return r;
}

TEST(DiagnosisSpreadTest, BurstsOfScatterAreLocatedInTheirPeriods) {
  for (uint64_t seed : {101u, 102u}) {
    SCOPED_TRACE(seed);
    const Simulation sim = simulator_test::Simulated(seed, kPaperCampaigns,
                                                     {"inexpressible_bursts"});
    const SimulatedEffect& truth = sim.truth.effects.at(0);
    ASSERT_FALSE(truth.expressible);
    StatusOr<DiagnosisReport> r = Diagnose(sim.data, DiagnosisOptions{});
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    EXPECT_TRUE(r->findings.empty()) << r->findings[0].explanation;
    EXPECT_EQ(r->verdict, "mismatch_located_unexplained");
    // Every spread-along-time entry at a scale whose blocks are no longer
    // than the longest burst (S >= 16: 24-25 campaigns of 395; bursts run
    // 15-30) lies in a burst: at least half of its block inside one of the
    // periods (every campaign is measured, so a campaign's rank among the
    // measured ones is the simulator's number). Coarser entries are not
    // checked: half the calendar holds a burst whatever it says.
    int spread_entries = 0;
    for (const Unexplained& u : r->unexplained) {
      int scale = 0;
      if (std::sscanf(u.dimension.c_str(), "spread_time_scale_%d", &scale) !=
              1 ||
          scale < 16) {
        continue;
      }
      ++spread_entries;
      const Range block = Campaigns(u.where, "campaigns %d-%d");
      ASSERT_LE(block.first, block.last) << u.where;
      int inside = 0;
      for (const std::string& level : truth.levels) {
        const Range burst = Campaigns(level, "campaigns %d..%d");
        inside = std::max(inside, std::min(block.last, burst.last) -
                                      std::max(block.first, burst.first) + 1);
      }
      EXPECT_GE(2 * inside, block.last - block.first + 1) << u.where;
      // Wider than elsewhere by at least the material share (25 %).
      int spread_percent = 0;
      const size_t at = u.where.find("(spread ");
      ASSERT_NE(at, std::string::npos) << u.where;
      std::sscanf(u.where.c_str() + at, "(spread %d", &spread_percent);
      EXPECT_GE(spread_percent, 25) << u.where;
    }
    EXPECT_GE(spread_entries, 1);
  }
}

}  // namespace
}  // namespace rollwear
