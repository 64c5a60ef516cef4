// Terms adopted on a mill's extra columns, run coil by coil by the daemon's
// predictor (core/model/predictor.h) from records' extra fields, equal the
// diagnosis engine's batch prediction from the Dataset's extra columns: a
// field a record lacks behaves as an empty cell, a factor level is matched
// by its label, and a level the term never saw counts as 1.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "core/dataset/extra_fields.h"
#include "core/dataset/pass_input.h"
#include "core/model/model_eval.h"
#include "core/model/predictor.h"
#include "tests/core/extra_terms_util.h"
#include "tests/core/simulator_test_util.h"

namespace rollwear {
namespace {

using extra_terms_test::AddExtraColumns;
using extra_terms_test::BatchPrediction;
using extra_terms_test::ExtraTerms;
using extra_terms_test::ModelWithTerms;

// The fields of a record as an API body would carry them: an empty factor
// cell is simply not sent.
ExtraFields AsBody(ExtraFields f) {
  std::erase_if(f.factor, [](const auto& kv) { return kv.second.empty(); });
  return f;
}

TEST(ExtraTermsTest, CoilByCoilFromFieldsEqualsBatchFromColumns) {
  Simulation sim = simulator_test::Simulated(61, 16);
  Dataset& d = sim.data;
  AddExtraColumns(&d);
  StatusOr<TermData> td = BuildTermData(d, WearLaw::kWang);
  ASSERT_TRUE(td.ok()) << td.status().ToString();
  ASSERT_GT(td->obs.size(), 40u);
  const WearModel model = ModelWithTerms(*td, ExtraTerms());
  const WearModel bare = ModelWithTerms(*td, {});
  const std::vector<double> batch = BatchPrediction(*td, model, true);
  const std::vector<double> batch_bare = BatchPrediction(*td, bare, true);
  const std::vector<double> reading = BatchPrediction(*td, model, false);

  const DatasetIndex index(d);
  int unseen_crew = 0, changed = 0;
  for (size_t o = 0; o < td->obs.size(); ++o) {
    const TermObservation& ob = td->obs[o];
    const Mount& mount = d.mounts[ob.mount];
    RollWearState st = MountRoll(
        model, RollPositionName(mount.stand, mount.position),
        d.roll_types[mount.roll_type], mount.diameter_mm, mount.hardness_hb,
        d.campaigns[ob.campaign].started_at,
        AsBody(ExtraFieldsOfRow(d.mount_extra, ob.mount)),
        AsBody(ExtraFieldsOfRow(d.campaign_extra, ob.campaign)));
    for (int pi : index.PassesOf(ob.campaign, mount.stand)) {
      PassInput in = PassInputOf(d, d.passes[pi]);
      in.extra = AsBody(in.extra);
      AddPass(model, in, &st);
    }
    EXPECT_NEAR(st.wear_um, batch[o], 1e-8 * batch[o]) << "observation " << o;
    unseen_crew += extra_terms_test::CrewOf(ob.campaign) == "C" ? 1 : 0;
    changed += std::abs(batch[o] / batch_bare[o] - 1) > 0.02 ? 1 : 0;
  }
  // The terms matter, and the never-seen level C occurs.
  EXPECT_GT(changed, static_cast<int>(td->obs.size()) / 2);
  EXPECT_GT(unseen_crew, 0);

  // Promotion's score (PredictMeasured, fields from the Dataset's rows)
  // gives the same wear, and the measurement term's reading.
  std::vector<int> all(d.campaigns.size());
  for (size_t c = 0; c < all.size(); ++c) all[c] = static_cast<int>(c);
  const std::vector<MeasuredPrediction> p = PredictMeasured(model, d, index, all);
  ASSERT_EQ(p.size(), td->obs.size());
  for (size_t o = 0; o < p.size(); ++o) {
    ASSERT_EQ(p[o].campaign, td->obs[o].campaign);
    ASSERT_EQ(p[o].slot, td->obs[o].slot);
    EXPECT_NEAR(p[o].wear_um, batch[o], 1e-8 * batch[o]);
    EXPECT_NEAR(p[o].expected_um, reading[o], 1e-8 * std::abs(reading[o]));
    // offset-linear: 4 * (probe - 30) / 5 µm
    const double probe = d.measurement_extra.numeric[0][p[o].measurement];
    EXPECT_NEAR(p[o].expected_um - p[o].wear_um, 0.8 * (probe - 30), 1e-9);
  }
}

TEST(ExtraTermsTest, MissingFieldIsAnEmptyCellAndUnknownLevelCountsOne) {
  const std::vector<ModelTerm> terms = ExtraTerms();
  WearModel model;
  model.terms = {terms[0], terms[1], terms[2]};
  PassInput pass;
  RollWearState state;
  // No field at all: the numeric term counts 1, the crew term takes the
  // empty text's level (exp(-0.2)), the supplier term (no "" level) 1.
  EXPECT_DOUBLE_EQ(PassTermMultiplier(model, pass, state), std::exp(-0.2));
  state.campaign_extra.factor = {{"crew", "B"}};
  state.mount_extra.factor = {{"supplier", "X"}};
  EXPECT_DOUBLE_EQ(PassTermMultiplier(model, pass, state), std::exp(0.25 + 0.15));
  state.campaign_extra.factor = {{"crew", "C"}};  // never seen in the fit
  pass.extra.numeric = {{"coolant_bar", 2.3}};
  EXPECT_DOUBLE_EQ(PassTermMultiplier(model, pass, state),
                   std::exp(0.3 * (2.3 - 2.15) / 0.15) * std::exp(0.15));
  // A term stored without its labels cannot match one: it counts 1.
  model.terms[2].levels.clear();
  EXPECT_DOUBLE_EQ(PassTermMultiplier(model, pass, state),
                   std::exp(0.3 * (2.3 - 2.15) / 0.15));
}

TEST(ExtraTermsTest, MergedFieldsAndRowsOfColumns) {
  ExtraFields coil, pass;
  coil.numeric = {{"a", 1}, {"c", 3}};
  coil.factor = {{"f", "x"}};
  pass.numeric = {{"b", 2}, {"c", 4}};
  const ExtraFields m = MergedExtraFields(coil, pass);
  EXPECT_EQ(m.numeric, (std::vector<std::pair<std::string, double>>{
                           {"a", 1}, {"b", 2}, {"c", 4}}));
  EXPECT_EQ(m.factor, coil.factor);
  Dataset d;
  d.pass_extra.numeric_names = {"z", "y"};
  d.pass_extra.numeric = {{std::nan(""), 5}, {7, 8}};
  extra_terms_test::AddFactor(&d.pass_extra, "f", {"", "q"});
  const ExtraFields row0 = ExtraFieldsOfRow(d.pass_extra, 0);
  EXPECT_EQ(row0.numeric, (std::vector<std::pair<std::string, double>>{{"y", 7}}));
  EXPECT_EQ(row0.factor, (std::vector<std::pair<std::string, std::string>>{{"f", ""}}));
  EXPECT_EQ(*ExtraFieldsOfRow(d.pass_extra, 1).Numeric("z"), 5);
}

}  // namespace
}  // namespace rollwear
