// ScoreScreen (core/fit/term_fit.h), the diagnosis' screen that computes
// the current model once per round, gives every candidate of the library
// exactly the statistic and degrees of freedom of ScoreStatistic: at the
// null starts (its fast path) and at a start away from the null (its
// fallback), against a baseline and against a model that already holds a
// term. Small data (40 campaigns), so it stays quick under the sanitizers.
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/diagnosis/diagnosis_internal.h"
#include "core/fit/term_fit.h"
#include "tests/core/simulator_test_util.h"

namespace rollwear {
namespace {

struct Current {
  std::vector<double> log_k;
  std::vector<TermSpec> terms;
};

// Every candidate (each start) scored both ways: bit for bit equal.
void ExpectScreenEqualsScore(const TermData& td, const std::vector<int>& train,
                             const Current& cur,
                             const std::vector<diag::Candidate>& cands) {
  const std::vector<double> sd =
      TermNoiseSd(td, train, cur.log_k, cur.terms, nullptr, true);
  const ScoreScreen screen(td, train, sd, cur.log_k, cur.terms);
  int tested = 0, positive = 0;
  for (const diag::Candidate& c : cands) {
    std::vector<std::vector<double>> starts = c.starts;
    if (starts.empty()) starts.push_back(c.spec.term.params);
    for (const std::vector<double>& start : starts) {
      TermSpec spec = c.spec;
      spec.term.params = start;
      int df_full = -1, df_screen = -2;
      const double full =
          ScoreStatistic(td, train, sd, cur.log_k, cur.terms, spec, &df_full);
      const double fast = screen.Statistic(spec, &df_screen);
      ASSERT_EQ(df_full, df_screen) << spec.term.covariate;
      ASSERT_EQ(full, fast) << spec.term.covariate << " "
                            << TermFormName(spec.term.form);
      ++tested;
      positive += full > 0 ? 1 : 0;
    }
  }
  // The library is not empty and the statistics are not all zero.
  EXPECT_GT(tested, 50);
  EXPECT_GT(positive, tested / 2);
}

TEST(ScoreScreenTest, EqualsScoreStatisticForEveryCandidate) {
  const Simulation sim = simulator_test::Simulated(71, 40, {"temperature"});
  StatusOr<TermData> td = BuildTermData(sim.data, WearLaw::kWang);
  ASSERT_TRUE(td.ok()) << td.status().ToString();
  std::vector<int> train;
  for (int o = 0; o < static_cast<int>(td->obs.size()); ++o) {
    if (o % 3 != 2) train.push_back(o);
  }
  const std::vector<double> unit(td->obs.size(), 5.0);
  StatusOr<TermFitResult> base = FitTerms(*td, train, unit, {}, {});
  ASSERT_TRUE(base.ok() && base->usable);
  const DiagnosisOptions options;
  const std::vector<diag::Candidate> cands =
      diag::MakeCandidates(*td, train, {}, options);
  ExpectScreenEqualsScore(*td, train, {base->log_k, {}}, cands);

  // Against a model holding a fitted term, and with starts away from the
  // null (the fallback path).
  const diag::Candidate& first = cands.front();
  StatusOr<TermFitResult> with =
      FitTerms(*td, train, unit, base->log_k, {first.spec});
  ASSERT_TRUE(with.ok() && with->usable);
  std::vector<diag::Candidate> moved = cands;
  for (diag::Candidate& c : moved) {
    c.starts.clear();
    for (double& p : c.spec.term.params) p = std::clamp(p + 0.05, -0.9, 0.9);
  }
  const std::set<int> used = {first.spec.covariate};
  ExpectScreenEqualsScore(*td, train, {with->log_k, with->terms},
                          diag::MakeCandidates(*td, train, used, options));
  ExpectScreenEqualsScore(*td, train, {with->log_k, with->terms}, moved);
}

}  // namespace
}  // namespace rollwear
