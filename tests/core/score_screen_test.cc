// ScoreScreen (core/fit/term_fit.h), the diagnosis' screen that computes
// the current model once per round, gives every candidate of the library
// exactly the statistic and degrees of freedom of ScoreStatistic: at the
// null starts (its fast path) and at a start away from the null (its
// fallback), against a baseline and against a model that already holds a
// term. Small data (40 campaigns), so it stays quick under the sanitizers.
#include <algorithm>
#include <cmath>
#include <limits>
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
      ASSERT_EQ(full, fast)
          << spec.term.covariate << " " << TermFormName(spec.term.form);
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

  // Against a model holding wear per coil (an additive term, 0.3 µm per
  // coil, not fitted: these data have none): a candidate multiplier scales
  // the law's wear of a pass, not the wear added to it.
  TermSpec per_coil;
  per_coil.covariate = td->CovariateIndex("campaign_coils_before");
  ASSERT_GE(per_coil.covariate, 0);
  per_coil.term.covariate = "campaign_coils_before";
  per_coil.term.form = TermForm::kPerCoil;
  per_coil.term.params = {0.3};
  per_coil.lower = {0.0};
  per_coil.upper = {20.0};
  ExpectScreenEqualsScore(
      *td, train, {base->log_k, {per_coil}},
      diag::MakeCandidates(*td, train, {per_coil.covariate}, options));
}

// The fits' model of a reading (TermModel, core/fit/term_model_internal.h)
// equals the plain sum over passes of k_g * load * prod_t TermMultiplier:
// its exp-only path (u(z) per pass computed once per fit) and its cache
// included, at covariate values a mill's data can hold: missing (NaN),
// zero, negative and infinite.
TEST(TermModelTest, PredictionsEqualTheMultiplierProductAtEdgeValues) {
  const Simulation sim = simulator_test::Simulated(72, 30, {});
  StatusOr<TermData> built = BuildTermData(sim.data, WearLaw::kWang);
  ASSERT_TRUE(built.ok()) << built.status().ToString();
  TermData td = *std::move(built);
  const int temp = td.CovariateIndex("temperature_c");
  const int speed = td.CovariateIndex("speed_mps");
  const int lub = td.CovariateIndex("lubrication");
  ASSERT_GE(std::min({temp, speed, lub}), 0);
  const double kInf = std::numeric_limits<double>::infinity();
  const double kNaN = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> edge = {kNaN, 0.0, -0.0, -3.0, kInf, -kInf};
  // One pass of each of the first observations gets an edge value of
  // each covariate (the others keep the simulator's).
  for (int o = 0; o < 24 && o < static_cast<int>(td.obs.size()); ++o) {
    const TermObservation& obs = td.obs[o];
    const int i = obs.pass_begin + o % (obs.pass_end - obs.pass_begin);
    for (int k : {temp, speed, lub}) {
      td.z[k][i] = edge[(o + k) % edge.size()];
    }
  }
  std::vector<TermSpec> terms(3);
  terms[0].covariate = temp;
  terms[0].term.form = TermForm::kLogLinear;
  terms[0].term.params = {0.3};
  terms[0].term.center = 900;
  terms[0].term.scale = 40;
  terms[1].covariate = speed;
  terms[1].term.form = TermForm::kPower;
  terms[1].term.params = {-0.4};
  terms[1].term.center = 6;
  terms[2].covariate = lub;
  terms[2].term.form = TermForm::kFlag;
  terms[2].term.params = {-0.2};
  for (TermSpec& t : terms) t.term.covariate = td.catalog[t.covariate].name;
  const int p = static_cast<int>(td.positions.size());
  const int r = static_cast<int>(td.roll_types.size());
  std::vector<double> log_k(p + r + td.grades.size());
  for (size_t j = 0; j < log_k.size(); ++j) log_k[j] = -2.0 + 0.01 * j;
  std::vector<int> all(td.obs.size());
  for (int o = 0; o < static_cast<int>(all.size()); ++o) all[o] = o;

  const std::vector<double> got = PredictTerms(td, all, log_k, terms, true);
  ASSERT_EQ(got.size(), all.size());
  int finite = 0;
  for (int o : all) {
    const TermObservation& obs = td.obs[o];
    double want = 0;
    for (int i = obs.pass_begin; i < obs.pass_end; ++i) {
      const double base = log_k[obs.position] +
                          (obs.roll_type >= 0 ? log_k[p + obs.roll_type] : 0.0);
      double m = 1;
      for (const TermSpec& t : terms)
        m *= TermMultiplier(t.term, td.z[t.covariate][i], nullptr);
      want += std::exp(base + log_k[p + r + td.grade[i]]) * td.load[i] * m;
    }
    if (!std::isfinite(want)) {  // NaN as NaN, an infinity as itself
      EXPECT_TRUE(std::isnan(want) ? std::isnan(got[o]) : got[o] == want)
          << "observation " << o << ": " << got[o] << " vs " << want;
      continue;
    }
    ++finite;
    EXPECT_NEAR(got[o], want, 1e-12 * std::max(1.0, std::fabs(want)))
        << "observation " << o;
  }
  EXPECT_GT(finite, static_cast<int>(all.size()) / 2);
}

}  // namespace
}  // namespace rollwear
