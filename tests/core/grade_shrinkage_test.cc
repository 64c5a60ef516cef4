// Option 1's grade factors as a random effect (calibration.h, grade
// shrinkage): on a mill whose grade codes are many and mostly rare, the free
// fit is not identified and the shrunk one is, predicts held-out campaigns
// better and estimates the grades' spread; on the paper's mill of nine
// well-used grades it changes almost nothing.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/base/random.h"
#include "core/fit/calibration.h"
#include "core/fit/identification.h"
#include "core/fit/study.h"
#include "core/model/aggregation.h"
#include "core/sim/simulator.h"

namespace rollwear {
namespace {

// A simulated mill whose every grade is split into sub-codes, as a real
// mill's order system splits a steel family: coil by coil, sub-code j of
// the coil's grade with probability proportional to 0.55^j (j < 12), so a
// few codes carry most coils and most codes are rare. A sub-code wears as
// its grade (the truth of `parent`).
struct SplitGrades {
  Simulation sim;
  std::map<std::string, std::string> parent;  // sub-code -> grade
};

SplitGrades MillWithRareGradeCodes(uint64_t seed, int campaigns) {
  SimulatorOptions o;
  o.seed = seed;
  o.num_campaigns = campaigns;
  StatusOr<Simulation> s = Simulate(o);
  EXPECT_TRUE(s.ok()) << s.status().ToString();
  SplitGrades out{std::move(s).value(), {}};
  Dataset& d = out.sim.data;
  Random rng(seed * 7919 + 1);
  std::map<int, int> code_of_coil;
  std::map<std::string, int> index;
  std::vector<std::string> labels;
  for (Pass& p : d.passes) {
    auto [it, fresh] = code_of_coil.emplace(p.coil, 0);
    if (fresh) {
      int j = 0;
      while (j < 11 && rng.Uniform() > 0.45) ++j;
      it->second = j;
    }
    const std::string label =
        d.grades[p.grade] + "-" + std::to_string(it->second);
    out.parent[label] = d.grades[p.grade];
    auto [at, added] = index.emplace(label, static_cast<int>(labels.size()));
    if (added) labels.push_back(label);
    p.grade = at->second;
  }
  d.grades = labels;
  return out;
}

WearStatistics WangStats(const Dataset& data) {
  const DatasetIndex index(data);
  StatusOr<WearStatistics> st = Aggregate(data, index, WearLaw::kWang);
  EXPECT_TRUE(st.ok()) << st.status().ToString();
  return std::move(st).value();
}

// Option 1 with its grades fitted freely, and shrunk (the default), on
// one split.
std::pair<StatusOr<SplitCalibration>, StatusOr<SplitCalibration>> FreeAndShrunk(
    const WearStatistics& st, const CampaignSplit& split) {
  CalibrationOptions free_opts;
  free_opts.shrink_grades = false;
  return {CalibrateOnSplit(st, split, free_opts),
          CalibrateOnSplit(st, split, {})};
}

TEST(GradeShrinkageTest, RareGradeCodesAreShrunkIdentifiedAndPredictBetter) {
  const SplitGrades mill = MillWithRareGradeCodes(5, 60);
  const WearStatistics st = WangStats(mill.sim.data);
  ASSERT_GT(st.grades.size(), 60u);
  const CampaignSplit split = SplitCampaigns(st);
  const auto [free_fit, shrunk] = FreeAndShrunk(st, split);
  ASSERT_TRUE(free_fit.ok() && shrunk.ok());
  ASSERT_TRUE(shrunk->result.summary.usable);
  EXPECT_FALSE(free_fit->result.grade_shrinkage.applied);
  const GradeShrinkage& g = shrunk->result.grade_shrinkage;
  ASSERT_TRUE(g.applied);
  EXPECT_TRUE(g.converged) << g.Sentence();
  EXPECT_GT(g.levels, 60);
  // Fewer effective parameters than codes: the rare ones are pooled.
  EXPECT_LT(g.effective_parameters, 0.8 * g.levels) << g.Sentence();
  EXPECT_GT(g.effective_parameters, 2.0) << g.Sentence();

  const Identification free_id = JudgeIdentification(
      free_fit->result, free_fit->train, free_fit->validation);
  const Identification shrunk_id =
      JudgeIdentification(shrunk->result, shrunk->train, shrunk->validation);
  EXPECT_FALSE(free_id.identified) << free_id.Sentence();
  EXPECT_TRUE(shrunk_id.identified) << shrunk_id.Sentence();
  // Measured on 60-campaign mills, seeds 1-6: free 29.8-44.7 um, shrunk
  // 16.7-20.0 um (0.38-0.67 of free).
  EXPECT_LT(shrunk->validation.gap_um, 0.8 * free_fit->validation.gap_um)
      << "shrunk " << shrunk->validation.gap_um << " free "
      << free_fit->validation.gap_um;

  // tau against the true spread of log kS over the codes with training
  // load (each code wears as its grade). With most codes rare, the evidence
  // estimate runs high: 1.7-3.9 x the true sd on seeds 1-6 at 60 to 240
  // campaigns (the rare codes' estimates carry the wear-proportional noise
  // the single sigma of the fit does not model), which shrinks less than
  // the truth would allow, never more. Asserted: the spread is neither
  // pooled away (tau > half the truth) nor left free (tau < 4 x).
  double sum = 0, sum_sq = 0;
  int n = 0;
  std::vector<double> load(st.grades.size(), 0.0);
  for (int o : st.MeasuredObservations(split.train)) {
    for (const CellLoad& c : st.observations[o].cells) load[c.grade] += c.load;
  }
  for (size_t s = 0; s < st.grades.size(); ++s) {
    if (load[s] <= 0) continue;
    const double v =
        std::log(mill.sim.truth.k_grade.at(mill.parent.at(st.grades[s])));
    sum += v;
    sum_sq += v * v;
    ++n;
  }
  const double true_sd =
      std::sqrt(std::max(0.0, sum_sq / n - sum * sum / n / n));
  EXPECT_GT(g.tau, 0.5 * true_sd) << g.Sentence() << " true sd " << true_sd;
  EXPECT_LT(g.tau, 4.0 * true_sd) << g.Sentence() << " true sd " << true_sd;
}

// Nine grades on a mill of 120 campaigns, each on thousands of coils (but
// a reading sums over many grades, so their factors are only partly
// determined): the evidence finds most of them fixed by the data (gamma 6.5
// of 9 measured), tau near the true spread of the nine factors (0.138
// against 0.110 measured) and the held-out gap no worse than the free fit's
// (16.25 against 16.57 um measured; 17.70 against 17.68 at 395 campaigns).
TEST(GradeShrinkageTest, WellUsedGradesAreShrunkLittleAndPredictNoWorse) {
  SimulatorOptions o;
  o.seed = 21;
  o.num_campaigns = 120;
  StatusOr<Simulation> sim = Simulate(o);
  ASSERT_TRUE(sim.ok());
  const WearStatistics st = WangStats(sim->data);
  const CampaignSplit split = SplitCampaigns(st);
  const auto [free_fit, shrunk] = FreeAndShrunk(st, split);
  ASSERT_TRUE(free_fit.ok() && shrunk.ok());
  const GradeShrinkage& g = shrunk->result.grade_shrinkage;
  ASSERT_TRUE(g.applied);
  EXPECT_TRUE(g.converged);
  EXPECT_EQ(g.levels, 9);
  EXPECT_GT(g.effective_parameters, 5.0) << g.Sentence();
  EXPECT_LE(g.effective_parameters, 9.0) << g.Sentence();
  double sum = 0, sum_sq = 0;
  for (const auto& [label, k] : sim->truth.k_grade) {
    sum += std::log(k);
    sum_sq += std::log(k) * std::log(k);
  }
  const double n = static_cast<double>(sim->truth.k_grade.size());
  const double true_sd = std::sqrt(sum_sq / n - sum * sum / n / n);
  EXPECT_GT(g.tau, 0.7 * true_sd) << g.Sentence();
  EXPECT_LT(g.tau, 1.5 * true_sd) << g.Sentence();
  EXPECT_LE(shrunk->validation.gap_um, 1.01 * free_fit->validation.gap_um);
}

}  // namespace
}  // namespace rollwear
