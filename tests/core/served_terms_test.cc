// A served model with the diagnosis's whole vocabulary (issue 15): a scoped
// log-linear wear-rate term, a factor-cell term, an offset_per_level term
// on a text column of measurements.csv and a scoped offset_linear term on
// measured_at. Coil by coil (core/model/model_eval.h, the path the daemon
// and promotion run) it must give what the fit's own batch prediction
// (PredictTerms, core/fit/term_fit.h) gives, reading by reading, to 1e-9;
// a level of the text column is matched by its label, never by its index;
// a measurement term counts only on rolls inside its scope.
// (The daemon's replay of the same model is checked against
// PredictMeasured in tests/storage/store_history_test.cc.)
#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/fit/term_fit.h"
#include "core/fit/term_refit.h"
#include "core/model/model_eval.h"
#include "tests/core/served_terms_util.h"
#include "tests/core/simulator_test_util.h"
#include "tests/core/test_size.h"

namespace rollwear {
namespace {

class ServedTermsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    sim_ = simulator_test::Simulated(5, test_size::FullOr(60, 24), {"grinder:0"});
    const ExtraColumns& e = sim_.data.measurement_extra;
    ASSERT_EQ(e.factor_names.size(), 1u);
    ASSERT_GE(e.factor_levels[0].size(), 2u);
    for (int c = 0; c < static_cast<int>(sim_.data.campaigns.size()); ++c) {
      all_.push_back(c);
      (c % 3 == 2 ? validation_ : train_).push_back(c);
    }
    StatusOr<WearModel> model = RefitWithTerms(sim_.data, WearLaw::kWang,
                                               served_terms::VocabularyTerms(sim_.data, 0), train_);
    ASSERT_TRUE(model.ok()) << model.status().ToString();
    model_ = std::move(model).value();
    ASSERT_EQ(model_.terms.size(), 4u);
  }

  // The fit's batch prediction of every measured roll, by (campaign, slot).
  std::map<std::pair<int, int>, double> Batch(bool wear_only) const {
    StatusOr<TermData> td = BuildTermData(sim_.data, WearLaw::kWang);
    EXPECT_TRUE(td.ok());
    std::vector<TermSpec> specs;
    for (const ModelTerm& t : model_.terms) {
      TermSpec s;
      s.term = t;
      s.covariate = td->CovariateIndex(t.covariate);
      EXPECT_GE(s.covariate, 0) << t.covariate;
      specs.push_back(std::move(s));
    }
    std::vector<double> log_k;
    for (double k : model_.k) log_k.push_back(std::log(k));
    std::vector<int> subset(td->obs.size());
    for (size_t o = 0; o < subset.size(); ++o) subset[o] = static_cast<int>(o);
    const std::vector<double> y = PredictTerms(*td, subset, log_k, specs, wear_only);
    std::map<std::pair<int, int>, double> out;
    for (size_t o = 0; o < subset.size(); ++o) {
      out[{td->obs[o].campaign, td->obs[o].slot}] = y[o];
    }
    return out;
  }

  Simulation sim_;
  std::vector<int> all_, train_, validation_;
  WearModel model_;
};

TEST_F(ServedTermsTest, CoilByCoilEqualsTheFitsBatchPrediction) {
  const DatasetIndex index(sim_.data);
  const auto batch = Batch(false);
  const auto batch_wear = Batch(true);
  const std::vector<MeasuredPrediction> p = PredictMeasured(model_, sim_.data, index, all_);
  ASSERT_EQ(p.size(), batch.size());
  int offset_nonzero = 0;
  for (const MeasuredPrediction& x : p) {
    const double y = batch.at({x.campaign, x.slot});
    const double w = batch_wear.at({x.campaign, x.slot});
    EXPECT_NEAR(x.wear_um, w, 1e-9 * std::abs(w));
    EXPECT_NEAR(x.expected_um, y, 1e-9 * std::max(1.0, std::abs(y)));
    offset_nonzero += std::abs(x.expected_um - x.wear_um) > 0.1;
  }
  // The measurement terms act (and not on every reading: the reference
  // grinder's bottom rolls read the wear).
  EXPECT_GT(offset_nonzero, static_cast<int>(p.size()) / 4);
  EXPECT_LT(offset_nonzero, static_cast<int>(p.size()));
  // The fitted grinder offset is the simulator's: one level reads low.
  const ModelTerm& g = model_.terms[2];
  EXPECT_LT(*std::min_element(g.params.begin(), g.params.end()), -5.0);
}

// Each part of the offset, reading by reading: scope by roll, level by
// label. The term's levels reordered (a model stored by a daemon whose
// data met the levels in another order) reads the same.
TEST_F(ServedTermsTest, MeasurementTermsMatchLevelsByLabelInsideTheirScope) {
  const Dataset& d = sim_.data;
  WearModel reordered = model_;
  ModelTerm& g = reordered.terms[2];
  const ModelTerm& o = model_.terms[2];
  std::reverse(g.levels.begin(), g.levels.end());
  g.reference_level = g.num_levels - 1 - o.reference_level;
  std::vector<double> by_level(g.num_levels, 0.0);  // offset of label l
  for (int l = 0, j = 0; l < o.num_levels; ++l) {
    if (l != o.reference_level) by_level[l] = o.params[j++];
  }
  g.params.clear();
  for (int l = 0; l < g.num_levels; ++l) {
    if (l != g.reference_level) g.params.push_back(by_level[o.num_levels - 1 - l]);
  }
  const DatasetIndex index(d);
  const auto a = PredictMeasured(model_, d, index, validation_);
  const auto b = PredictMeasured(reordered, d, index, validation_);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].expected_um, b[i].expected_um);

  // One reading by hand: a top roll at F3 of a non-reference grinder.
  ReadingContext r;
  r.stand = 3;
  r.position = static_cast<int>(Position::kTop);
  r.roll_type = d.roll_types[0];
  r.measured_at = static_cast<UnixSeconds>(model_.terms[3].center * 86400.0) +
                  15 * 86400;  // 15 days after the centre: half a scale
  r.ended_at = r.measured_at - 3600;
  ExtraFields extra;
  const int level = o.reference_level == 0 ? 1 : 0;
  extra.factor.emplace_back(o.covariate, o.levels[level]);
  r.extra = &extra;
  const double drift = model_.terms[3].params[0] * 0.5;
  EXPECT_NEAR(MeasurementTermsOffset(model_, r), by_level[level] + drift, 1e-9);
  EXPECT_NEAR(MeasurementTermsOffset(reordered, r), by_level[level] + drift, 1e-9);
  r.position = static_cast<int>(Position::kBottom);  // outside the drift's scope
  EXPECT_NEAR(MeasurementTermsOffset(model_, r), by_level[level], 1e-9);
  extra.factor[0].second = "a grinder the fit never saw";  // adds nothing
  EXPECT_EQ(MeasurementTermsOffset(model_, r), 0.0);
  extra.factor.clear();  // no field: the empty text, not a level here
  EXPECT_EQ(MeasurementTermsOffset(model_, r), 0.0);
}

// The nightly refit starts from a stored term whose levels may be in
// another order than the data's: it is matched by label, so the refit from
// the reversed term predicts every reading as the refit from the data's
// order does, and the refitted term carries the data's labels in order.
TEST_F(ServedTermsTest, RefitMatchesAStoredTermsLevelsByLabel) {
  std::vector<ModelTerm> reversed = model_.terms;
  ModelTerm& g = reversed[2];
  const ModelTerm& o = model_.terms[2];
  std::vector<double> by_level(o.num_levels, 0.0);
  for (int l = 0, j = 0; l < o.num_levels; ++l) {
    if (l != o.reference_level) by_level[l] = o.params[j++];
  }
  std::reverse(g.levels.begin(), g.levels.end());
  g.reference_level = g.num_levels - 1 - o.reference_level;
  g.params.clear();
  for (int l = 0; l < g.num_levels; ++l) {
    if (l != g.reference_level) g.params.push_back(by_level[o.num_levels - 1 - l]);
  }
  StatusOr<WearModel> a = RefitWithTerms(sim_.data, WearLaw::kWang, model_.terms, train_);
  StatusOr<WearModel> b = RefitWithTerms(sim_.data, WearLaw::kWang, reversed, train_);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(b->terms[2].levels, sim_.data.measurement_extra.factor_levels[0]);
  EXPECT_EQ(b->terms[2].reference_level, a->terms[2].reference_level);
  const DatasetIndex index(sim_.data);
  const auto pa = PredictMeasured(*a, sim_.data, index, validation_);
  const auto pb = PredictMeasured(*b, sim_.data, index, validation_);
  ASSERT_EQ(pa.size(), pb.size());
  for (size_t i = 0; i < pa.size(); ++i) {
    EXPECT_NEAR(pa[i].expected_um, pb[i].expected_um, 1e-6) << i;
  }
}

// A measurement term scoped by grade has no meaning (a reading is of a
// roll, which rolls many grades): the refit refuses it.
TEST_F(ServedTermsTest, RefitRefusesAGradeScopedMeasurementTerm) {
  std::vector<ModelTerm> terms = {model_.terms[2]};
  terms[0].scope.grade = sim_.data.grades[0];
  StatusOr<WearModel> r = RefitWithTerms(sim_.data, WearLaw::kWang, terms, train_);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("cannot be scoped by grade"), std::string::npos)
      << r.status().ToString();
}

}  // namespace
}  // namespace rollwear
