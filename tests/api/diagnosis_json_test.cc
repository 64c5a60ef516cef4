// The diagnosis JSON (api/diagnosis_json.h) writes the adopted terms as the
// stored model does: `rollwear calibrate --terms` (DecodeModelTerms) reads
// back the same scope and reference level, so a term adopted at F7 only is
// never refitted as a global one.
#include "api/diagnosis_json.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "storage/model_codec.h"

namespace rollwear::api {
namespace {

TEST(DiagnosisJsonTest, AdoptedTermsKeepScopeAndReferenceLevel) {
  DiagnosisReport report;
  report.law = "wang";
  report.verdict = "missing_physics_found";
  ModelTerm temp;
  temp.covariate = "temperature_c";
  temp.form = TermForm::kLogLinear;
  temp.params = {-0.25};
  temp.scope.stand = 7;
  ModelTerm grinder;
  grinder.covariate = "grinder";
  grinder.form = TermForm::kOffsetPerLevel;
  grinder.params = {-15.5, 3.25};
  grinder.num_levels = 3;
  grinder.reference_level = 1;
  grinder.levels = {"B", "A", "C"};
  report.terms = {temp, grinder};
  const std::string text = DiagnosisJsonText(report);
  const nlohmann::json j = nlohmann::json::parse(text);
  EXPECT_EQ(j["adopted_model"]["terms"][0]["scope"]["stand"], "F7") << text;
  StatusOr<std::vector<ModelTerm>> back = storage::DecodeModelTerms(text);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  ASSERT_EQ(back->size(), 2u);
  EXPECT_EQ((*back)[0].scope, temp.scope);
  EXPECT_EQ((*back)[1].reference_level, 1);
  EXPECT_EQ((*back)[1].levels, grinder.levels);
  EXPECT_EQ((*back)[1].params, grinder.params);
}

}  // namespace
}  // namespace rollwear::api
