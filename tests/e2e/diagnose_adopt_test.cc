// Issue 15 through the real daemon: `rollwear serve` on a real SQLite file
// holding a simulated mill with a concealed effect the new vocabulary
// describes, POST /v1/diagnoses with adoption, then:
//  - the adopted model version (GET /v1/models/{v}) carries the finding's
//    term with its scope (a scoped covariate term, a factor cell, or two
//    cells at once), or
//    the grinder's offset_per_level term with its
//    level labels and reference level;
//  - the wear of a campaign rolled after the adoption (GET /v1/wear, the
//    daemon's coil-by-coil state) equals the offline prediction of the same
//    model over the same data (core PredictMeasured, itself equal to the
//    fit's batch prediction: tests/core/served_terms_test.cc) to 1e-9;
//  - what the grinder is expected to read (GET /v1/rolls/{id},
//    expected_reading_um) equals the offline expected reading to 1e-9, and
//    an adopted grinder offset moves it for the non-reference grinder only.
// The mill is simulated twice with one seed: `campaigns` campaigns and one
// more; the daemon imports the shorter (the simulator draws campaign by
// campaign, so it is the longer one's prefix) and is then sent the last
// campaign's roll change and coils over HTTP.
// Sizes (docs/development.md, sanitizer sizes): the scoped effect and the
// cell at 150 campaigns (Diagnose ≈ 3 s in Release), the grinder at 120
// (≈ 5 s), all at every build type.
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/dataset/dataset_io.h"
#include "core/model/aggregation.h"
#include "core/model/model_eval.h"
#include "storage/model_codec.h"
#include "tests/core/test_size.h"
#include "tests/e2e/e2e_util.h"

namespace rollwear::e2e {
namespace {

// The model of a GET /v1/models/{v} answer over the levels of `data`:
// option-1 coefficients by name (every one must be there) and the terms as
// the model store decodes them.
WearModel ModelOfAnswer(const json& answer, const Dataset& data) {
  WearModel m;
  EXPECT_TRUE(ParseWearLaw(answer.value("model", ""), &m.law)) << answer.dump();
  const DatasetIndex index(data);
  StatusOr<WearStatistics> stats = Aggregate(data, index, m.law);
  EXPECT_TRUE(stats.ok());
  if (!stats.ok()) return m;
  StatusOr<KStructure> structure = KStructure::ForOption(
      answer.value("option", 0), stats->positions, stats->roll_types, stats->grades);
  EXPECT_TRUE(structure.ok()) << answer.dump();
  if (!structure.ok()) return m;
  m.structure = *structure;
  const json& coefficients = answer["coefficients"];
  for (int i = 0; i < m.structure.num_coefficients(); ++i) {
    const std::string& name = m.structure.CoefficientName(i);
    EXPECT_TRUE(coefficients.contains(name) && coefficients[name].is_number()) << name;
    m.k.push_back(coefficients.value(name, 1.0));
  }
  StatusOr<std::vector<ModelTerm>> terms = storage::DecodeModelTerms(answer.dump());
  EXPECT_TRUE(terms.ok()) << terms.status().ToString();
  if (terms.ok()) m.terms = *terms;
  return m;
}

class DiagnoseAdoptTest : public ::testing::Test {
 protected:
  // Simulates, imports the first `campaigns`, starts the daemon, and runs
  // a diagnosis with adoption; returns the adopted model's answer.
  json AdoptFromDiagnosis(const std::string& effect, int seed, int campaigns) {
    std::string out;
    for (int n : {campaigns, campaigns + 1}) {
      const std::string folder = dir_ / ("sim" + std::to_string(n));
      EXPECT_EQ(RunRollwear({"simulate", "--out", folder, "--campaigns", std::to_string(n),
                             "--seed", std::to_string(seed), "--effect", effect},
                            &out),
                0)
          << out;
    }
    StatusOr<Dataset> first = ReadDataset(dir_ / ("sim" + std::to_string(campaigns)));
    StatusOr<Dataset> all = ReadDataset(dir_ / ("sim" + std::to_string(campaigns + 1)));
    EXPECT_TRUE(first.ok() && all.ok());
    if (!first.ok() || !all.ok()) return json();
    first_ = std::move(first).value();
    all_ = std::move(all).value();
    EXPECT_EQ(first_.campaigns.back().id, all_.campaigns[campaigns - 1].id);
    EXPECT_EQ(RunRollwear({"import", "--db", dir_ / "mill.db",
                           dir_ / ("sim" + std::to_string(campaigns))},
                          &out),
              0)
        << out;
    daemon_ = std::make_unique<Daemon>(dir_ / "mill.db", dir_ / "serve.log");
    std::string error;
    EXPECT_TRUE(daemon_->Start(&error)) << error;
    json answer;
    EXPECT_EQ(HttpPost(url(), "/v1/calibrations", "{}", &answer), 202) << answer.dump();
    const json run = WaitForJob(url(), "/v1/calibrations/" + std::to_string(answer.value("id", 0)));
    EXPECT_EQ(run.value("status", ""), "done") << run.dump();

    EXPECT_EQ(HttpPost(url(), "/v1/diagnoses", R"({"adopt": true})", &answer), 202)
        << answer.dump();
    report_ = WaitForJob(url(), "/v1/diagnoses/" + std::to_string(answer.value("id", 0)));
    EXPECT_EQ(report_.value("status", ""), "done") << report_.dump().substr(0, 2000);
    EXPECT_EQ(report_.value("verdict", ""), "missing_physics_found")
        << report_.dump().substr(0, 2000);
    const json& adoption = report_["adoption"];
    EXPECT_TRUE(adoption.is_object() && adoption.value("promoted", false))
        << report_.dump().substr(0, 2000);
    const int64_t version = adoption.is_object() && adoption["model_version"].is_number()
                                ? adoption["model_version"].get<int64_t>()
                                : 0;
    json model;
    EXPECT_EQ(HttpGet(url(), "/v1/models/" + std::to_string(version), &model), 200);
    json active;
    EXPECT_EQ(HttpGet(url(), "/v1/models/active", &active), 200);
    EXPECT_EQ(active.value("version", -1), version);
    return model;
  }

  // Sends the last campaign's roll change and coils; its wear under the
  // adopted model equals the offline prediction to 1e-9 relative.
  void ExpectNewCampaignWearMatchesOffline(const json& model) {
    const int last = static_cast<int>(all_.campaigns.size()) - 1;
    json answer;
    ASSERT_EQ(HttpPost(url(), "/v1/roll-changes", RollChangeJson(all_, last).dump(), &answer),
              201)
        << answer.dump();
    for (int k : CoilsOf(all_, last)) {
      ASSERT_EQ(HttpPost(url(), "/v1/coils", CoilJson(all_, k).dump(), &answer), 201)
          << answer.dump();
    }
    json wear;
    ASSERT_EQ(HttpGet(url(), "/v1/wear", &wear), 200);
    const std::map<std::string, double> served = WearByKey(wear);
    const WearModel m = ModelOfAnswer(model, all_);
    const DatasetIndex index(all_);
    int checked = 0;
    for (const MeasuredPrediction& p : PredictMeasured(m, all_, index, {last})) {
      const std::string key = all_.campaigns[last].id + "|" +
                              RollPositionName(SlotStand(p.slot), SlotPosition(p.slot));
      ASSERT_EQ(served.count(key), 1u) << key << " " << wear.dump();
      EXPECT_NEAR(served.at(key), p.wear_um, 1e-9 * p.wear_um) << key;
      ++checked;
    }
    EXPECT_EQ(checked, 4);
  }

  std::string url() const { return daemon_->url(); }

  TempDir dir_;
  std::unique_ptr<Daemon> daemon_;
  Dataset first_, all_;
  json report_;
};

TEST_F(DiagnoseAdoptTest, ScopedFindingIsAdoptedWithItsScopeAndServedAsInBatch) {
  const json model = AdoptFromDiagnosis("scoped:0", 4, 150);
  ASSERT_TRUE(model.is_object());
  // The finding (temperature at F7 only) and the stored term agree.
  ASSERT_FALSE(report_["findings"].empty());
  const json& finding = report_["findings"][0];
  EXPECT_EQ(finding.value("covariate", ""), "temperature_c");
  EXPECT_EQ(finding["scope"], json({{"stand", "F7"}})) << finding.dump();
  ASSERT_EQ(model["terms"].size(), 1u) << model.dump();
  const json& term = model["terms"][0];
  EXPECT_EQ(term.value("covariate", ""), "temperature_c");
  EXPECT_EQ(term.value("form", ""), "log_linear");
  EXPECT_EQ(term["scope"], json({{"stand", "F7"}})) << term.dump();
  ExpectNewCampaignWearMatchesOffline(model);
}

// A factor cell (issue 15: "adoption works with scoped and factor-cell
// terms"): roll type ICDP-S1 wearing x1.33 at F7 only (variant 0, seed 4),
// which the K structure (kF kR kS) cannot express. The daemon's diagnosis
// names the cell, the promoted model stores it as a cell term with its
// scope, and the next campaign is served as the batch prediction.
TEST_F(DiagnoseAdoptTest, FactorCellIsAdoptedAndServedAsInBatch) {
  const json model = AdoptFromDiagnosis("roll_type_stand:0", 4, 150);
  ASSERT_TRUE(model.is_object());
  ASSERT_FALSE(report_["findings"].empty());
  const json& finding = report_["findings"][0];
  EXPECT_EQ(finding.value("covariate", ""), "roll_type") << finding.dump();
  EXPECT_EQ(finding.value("form", ""), "cell") << finding.dump();
  EXPECT_EQ(finding["scope"], json({{"stand", "F7"}})) << finding.dump();
  EXPECT_EQ(finding["levels"], json::array({"ICDP-S1"})) << finding.dump();
  // A cell is one place by construction: no siblings to place.
  EXPECT_EQ(finding["scope_undetermined"], json::array()) << finding.dump();
  // The simulator's multiplier is 1.33; the cell's prior shrinks it a little.
  EXPECT_NEAR(finding["parameters"].value("multiplier", 0.0), 1.33, 0.1)
      << finding.dump();
  ASSERT_EQ(model["terms"].size(), 1u) << model.dump();
  const json& term = model["terms"][0];
  EXPECT_EQ(term.value("covariate", ""), "cell");
  EXPECT_EQ(term.value("form", ""), "cell");
  EXPECT_EQ(term["scope"], json({{"roll_type", "ICDP-S1"}, {"stand", "F7"}}))
      << term.dump();
  ExpectNewCampaignWearMatchesOffline(model);
}

// Two cells at once (session 16: a cell no longer ends the offer of
// cells): roll type ICDP-S1 and grade S355 each wearing more at F7 (seed 4,
// the paper's 395 campaigns). Both findings are adopted as two cell terms
// of one model version, and the next campaign is served as the batch
// prediction. At 150 campaigns (this test's size before session 18) the
// ICDP-S1 cell is refused since then: inside it, wear follows width (LR
// 14.2, p adjusted 0.0055; S355's wider coils at F7 take only part of it),
// the guard's look inside a cell; located, not named. Under the sanitizers
// (test_size.h) the mill is 200 campaigns, where the offline diagnosis of
// the same seed names both cells too (186 s under TSan at 395).
TEST_F(DiagnoseAdoptTest, TwoCellsAreAdoptedTogetherAndServedAsInBatch) {
  const json model = AdoptFromDiagnosis("grade_stand,roll_type_stand", 4,
                                        test_size::FullOr(395, 200));
  ASSERT_TRUE(model.is_object());
  ASSERT_EQ(report_["findings"].size(), 2u) << report_["findings"].dump();
  ASSERT_EQ(model["terms"].size(), 2u) << model.dump();
  std::map<std::string, json> scope_by_covariate;
  for (const json& f : report_["findings"]) {
    EXPECT_EQ(f.value("form", ""), "cell") << f.dump();
    EXPECT_EQ(f["scope"], json({{"stand", "F7"}})) << f.dump();
    scope_by_covariate[f.value("covariate", "")] = f["levels"];
  }
  EXPECT_EQ(scope_by_covariate["roll_type"], json::array({"ICDP-S1"}));
  EXPECT_EQ(scope_by_covariate["grade"], json::array({"S355"}));
  for (const json& term : model["terms"]) {
    EXPECT_EQ(term.value("form", ""), "cell") << term.dump();
    EXPECT_EQ(term["scope"].value("stand", ""), "F7") << term.dump();
  }
  ExpectNewCampaignWearMatchesOffline(model);
}

TEST_F(DiagnoseAdoptTest, GrinderOffsetMovesOnlyTheNonReferenceGrindersReadings) {
  const json model = AdoptFromDiagnosis("grinder:0", 3, 120);
  ASSERT_TRUE(model.is_object());
  ASSERT_EQ(model["terms"].size(), 1u) << model.dump();
  const json& term = model["terms"][0];
  EXPECT_EQ(term.value("covariate", ""), "grinder");
  EXPECT_EQ(term.value("form", ""), "offset_per_level");
  const std::vector<std::string> levels = term.value("levels", std::vector<std::string>{});
  ASSERT_EQ(levels.size(), 2u) << term.dump();
  const int reference = term.value("reference_level", 0);
  ASSERT_EQ(term["params"].size(), 1u);
  const double offset = term["params"][0].get<double>();
  EXPECT_LT(offset, -5.0);  // the simulator's low grinder reads 8..25 µm low
  const std::string low = levels[1 - reference];

  // The readings of the last 10 stored campaigns, roll by roll: the served
  // expected reading is the offline one, and it differs from the wear by
  // the offset exactly where the reading is the low grinder's.
  const WearModel m = ModelOfAnswer(model, first_);
  const DatasetIndex index(first_);
  std::vector<int> recent;
  for (int c = static_cast<int>(first_.campaigns.size()) - 10;
       c < static_cast<int>(first_.campaigns.size()); ++c) {
    recent.push_back(c);
  }
  const int grinder = 0;
  ASSERT_EQ(first_.measurement_extra.factor_names[grinder], "grinder");
  int low_readings = 0, reference_readings = 0;
  for (const MeasuredPrediction& p : PredictMeasured(m, first_, index, recent)) {
    const Measurement& me = first_.measurements[p.measurement];
    const std::string label =
        first_.measurement_extra.factor_levels[grinder]
                                              [first_.measurement_extra.factor[grinder][p.measurement]];
    json roll;
    ASSERT_EQ(HttpGet(url(), "/v1/rolls/" + me.roll_id, &roll), 200) << me.roll_id;
    const json* mount = nullptr;
    for (const json& x : roll["mounts"]) {
      if (x["campaign_id"] == first_.campaigns[p.campaign].id) mount = &x;
    }
    ASSERT_NE(mount, nullptr) << roll.dump();
    const double wear = (*mount)["predicted_wear_um"].get<double>();
    const double expected = (*mount)["expected_reading_um"].get<double>();
    EXPECT_NEAR(wear, p.wear_um, 1e-9 * p.wear_um);
    EXPECT_NEAR(expected, p.expected_um, 1e-9 * p.wear_um);
    if (label == low) {
      EXPECT_NEAR(expected - wear, offset, 1e-9 * p.wear_um) << me.roll_id;
      ++low_readings;
    } else {
      EXPECT_EQ(label, levels[reference]);
      EXPECT_NEAR(expected, wear, 1e-9 * p.wear_um) << me.roll_id;
      ++reference_readings;
    }
  }
  EXPECT_GT(low_readings, 0);
  EXPECT_GT(reference_readings, 0);
  ExpectNewCampaignWearMatchesOffline(model);
}

}  // namespace
}  // namespace rollwear::e2e
