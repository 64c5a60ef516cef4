// WearModel <-> JSON: exact round trips for every law and option, with
// covariance (including non-finite entries), and rejection of bad input.
#include "storage/model_codec.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "storage/model_levels.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::BitEqual;

WearModel MakeModel(WearLaw law, int option) {
  StatusOr<KStructure> ks = KStructure::ForOption(
      option, {"F6/top", "F6/bottom", "F7/top", "F7/bottom"},
      {"ICDP-S3", "HSS-S1", "HSS-S2"}, {"S235", "DP600"});
  EXPECT_TRUE(ks.ok());
  WearModel m;
  m.law = law;
  m.structure = *ks;
  for (int i = 0; i < m.structure.num_coefficients(); ++i) {
    m.k.push_back(0.1 + 1.0 / 3.0 * i + 1e-17 * i);  // awkward decimals
  }
  m.cao_exponent = law == WearLaw::kCao ? 1.2345678901234567 : 1.0;
  const int p = m.num_parameters();
  m.covariance.resize(p, p);
  for (int r = 0; r < p; ++r) {
    for (int c = 0; c < p; ++c) {
      m.covariance(r, c) = std::sin(r * 7.0 + c) * 1e-3 / 3.0;
    }
  }
  m.noise_sd_um = 4.123456789012345;
  m.noise_rel = 0.0512345678901;
  return m;
}

void ExpectSame(const WearModel& a, const WearModel& b) {
  EXPECT_EQ(a.law, b.law);
  EXPECT_EQ(a.structure.option(), b.structure.option());
  EXPECT_EQ(a.structure.positions(), b.structure.positions());
  EXPECT_EQ(a.structure.roll_types(), b.structure.roll_types());
  EXPECT_EQ(a.structure.grades(), b.structure.grades());
  ASSERT_EQ(a.k.size(), b.k.size());
  for (size_t i = 0; i < a.k.size(); ++i) EXPECT_TRUE(BitEqual(a.k[i], b.k[i]));
  EXPECT_TRUE(BitEqual(a.cao_exponent, b.cao_exponent));
  EXPECT_TRUE(BitEqual(a.noise_sd_um, b.noise_sd_um));
  EXPECT_TRUE(BitEqual(a.noise_rel, b.noise_rel));
  ASSERT_EQ(a.terms.size(), b.terms.size());
  for (size_t i = 0; i < a.terms.size(); ++i) {
    const ModelTerm &x = a.terms[i], &y = b.terms[i];
    EXPECT_EQ(x.covariate, y.covariate);
    EXPECT_EQ(x.form, y.form);
    ASSERT_EQ(x.params.size(), y.params.size());
    for (size_t j = 0; j < x.params.size(); ++j) {
      EXPECT_TRUE(BitEqual(x.params[j], y.params[j]));
    }
    EXPECT_TRUE(BitEqual(x.center, y.center));
    EXPECT_TRUE(BitEqual(x.scale, y.scale));
    EXPECT_EQ(x.edges, y.edges);
    EXPECT_EQ(x.num_levels, y.num_levels);
    EXPECT_EQ(x.levels, y.levels);
  }
  ASSERT_EQ(a.covariance.rows(), b.covariance.rows());
  ASSERT_EQ(a.covariance.cols(), b.covariance.cols());
  for (Eigen::Index r = 0; r < a.covariance.rows(); ++r) {
    for (Eigen::Index c = 0; c < a.covariance.cols(); ++c) {
      const double x = a.covariance(r, c), y = b.covariance(r, c);
      EXPECT_TRUE(BitEqual(x, y) || (std::isnan(x) && std::isnan(y)))
          << r << "," << c;
    }
  }
}

TEST(ModelCodecTest, RoundTripIsExactForEveryLawAndOption) {
  for (WearLaw law : {WearLaw::kWang, WearLaw::kNikitenko, WearLaw::kCao}) {
    for (int option : {1, 2, 3}) {
      const WearModel m = MakeModel(law, option);
      const std::string json = EncodeWearModel(m);
      StatusOr<WearModel> back = DecodeWearModel(json);
      ASSERT_TRUE(back.ok()) << back.status().ToString() << "\n" << json;
      ExpectSame(m, *back);
      EXPECT_EQ(EncodeWearModel(*back), json);
    }
  }
}

TEST(ModelCodecTest, AdoptedTermsRoundTrip) {
  WearModel m = MakeModel(WearLaw::kWang, 1);
  ModelTerm growth;
  growth.covariate = "campaign_length_before_m";
  growth.form = TermForm::kSaturating;
  growth.params = {0.4123456789012345, std::log(23456.789)};
  m.terms.push_back(growth);
  ModelTerm bins;
  bins.covariate = "temperature_c";
  bins.form = TermForm::kBinned;
  bins.params = {0.1, -0.2 / 3};
  bins.edges = {930.5, 951.25};
  bins.center = 1.0 / 3;
  bins.scale = 7.0 / 9;
  m.terms.push_back(bins);
  ModelTerm levels;
  levels.covariate = "operator_note";
  levels.form = TermForm::kPerLevel;
  levels.params = {0.05};
  levels.num_levels = 2;
  levels.levels = {"", "checked \"twice\""};  // labels, the empty one too
  m.terms.push_back(levels);
  const std::string json = EncodeWearModel(m);
  EXPECT_NE(json.find("\"form\":\"saturating\""), std::string::npos) << json;
  StatusOr<WearModel> back = DecodeWearModel(json);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  ExpectSame(m, *back);
  StatusOr<WearModel> over =
      ModelOverLevels(m, m.structure.positions(), {}, {});
  ASSERT_TRUE(over.ok());
  EXPECT_EQ(over->terms.size(), 3u);
  EXPECT_EQ(over->terms[2].levels, levels.levels);
  // A term stored before labels were kept (no "levels") decodes with none;
  // labels that are not strings are refused naming the field.
  StatusOr<std::vector<ModelTerm>> old = DecodeModelTerms(
      R"({"terms":[{"covariate":"x","form":"per_level","params":[0.1],"num_levels":2}]})");
  ASSERT_TRUE(old.ok()) << old.status().ToString();
  EXPECT_TRUE(old->front().levels.empty());
  StatusOr<std::vector<ModelTerm>> bad = DecodeModelTerms(
      R"({"terms":[{"covariate":"x","form":"per_level","params":[0.1],"num_levels":2,"levels":["a",1]}]})");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("terms[0].levels"), std::string::npos)
      << bad.status().message();
}

// A roll-effect term (the per-roll family) keeps its rolls, multipliers,
// prior sd and each roll's posterior sd and readings; a spread that does
// not match the rolls, or on another form, is refused naming the field.
TEST(ModelCodecTest, RollEffectTermsKeepTheirRollsAndSpread) {
  WearModel m = MakeModel(WearLaw::kWang, 1);
  ModelTerm rolls;
  rolls.covariate = "roll_id";
  rolls.form = TermForm::kRollEffect;
  rolls.levels = {"R1", "R2", "R3"};
  rolls.num_levels = 3;
  rolls.params = {0.1, -0.05, 0.0};
  rolls.scale = 0.18;
  rolls.level_sd = {0.04, 0.06, 0.18};
  rolls.level_readings = {7, 4, 0};
  m.terms.push_back(rolls);
  StatusOr<WearModel> back = DecodeWearModel(EncodeWearModel(m));
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  ASSERT_EQ(back->terms.size(), 1u);
  const ModelTerm& t = back->terms[0];
  EXPECT_EQ(t.form, TermForm::kRollEffect);
  EXPECT_EQ(t.levels, rolls.levels);
  EXPECT_EQ(t.params, rolls.params);
  EXPECT_EQ(t.scale, 0.18);
  EXPECT_EQ(t.level_sd, rolls.level_sd);
  EXPECT_EQ(t.level_readings, rolls.level_readings);
  // The served factor: R1's exp(0.1) with its own interval; an unknown
  // roll at 1 with the prior's.
  const std::optional<RollWearFactor> r1 = RollWearFactorOf(back->terms, "R1");
  ASSERT_TRUE(r1.has_value());
  EXPECT_NEAR(r1->value, std::exp(0.1), 1e-12);
  EXPECT_NEAR(r1->hi, std::exp(0.1 + 1.959964 * 0.04), 1e-9);
  EXPECT_EQ(r1->readings, 7);
  const std::optional<RollWearFactor> fresh =
      RollWearFactorOf(back->terms, "R9");
  ASSERT_TRUE(fresh.has_value());
  EXPECT_EQ(fresh->value, 1.0);
  EXPECT_EQ(fresh->readings, 0);
  EXPECT_NEAR(fresh->lo, std::exp(-1.959964 * 0.18), 1e-9);
  EXPECT_FALSE(RollWearFactorOf({}, "R1").has_value());
  for (
      const char* bad :
      {R"({"terms":[{"covariate":"roll_id","form":"roll_effect","params":[0.1,0.2],"num_levels":2,"levels":["a","b"],"level_sd":[0.1]}]})",
       R"({"terms":[{"covariate":"roll_id","form":"roll_effect","params":[0.1,0.2],"num_levels":2,"levels":["a","b"],"level_readings":[1,-2]}]})",
       R"({"terms":[{"covariate":"x","form":"per_level","params":[0.1],"num_levels":2,"level_sd":[0.1,0.1]}]})"}) {
    StatusOr<std::vector<ModelTerm>> out = DecodeModelTerms(bad);
    ASSERT_FALSE(out.ok()) << bad;
    EXPECT_NE(out.status().message().find("terms[0].level_"), std::string::npos)
        << out.status().message();
  }
}

// A stored model is held to its terms' family rules (term_family.h) as a
// --terms file is: a power term needs a centre > 0 (it computes
// log(z / centre)).
TEST(ModelCodecTest, AStoredModelKeepsItsTermsFamilyRules) {
  WearModel m = MakeModel(WearLaw::kWang, 1);
  ModelTerm power;
  power.covariate = "speed_mps";
  power.form = TermForm::kPower;
  power.params = {0.4};
  power.center = 0;
  m.terms.push_back(power);
  StatusOr<WearModel> back = DecodeWearModel(EncodeWearModel(m));
  ASSERT_FALSE(back.ok());
  EXPECT_NE(back.status().message().find("terms[0].center"), std::string::npos)
      << back.status().message();
  m.terms[0].center = 6.5;
  back = DecodeWearModel(EncodeWearModel(m));
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(back->terms[0].center, 6.5);
  // Wear per coil: stored and read back at its stand; never negative.
  ModelTerm per_coil;
  per_coil.covariate = "campaign_coils_before";
  per_coil.form = TermForm::kPerCoil;
  per_coil.params = {0.375};
  per_coil.scope.stand = 6;
  m.terms.push_back(per_coil);
  back = DecodeWearModel(EncodeWearModel(m));
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  ASSERT_EQ(back->terms.size(), 2u);
  EXPECT_EQ(back->terms[1].form, TermForm::kPerCoil);
  EXPECT_EQ(back->terms[1].params, std::vector<double>{0.375});
  EXPECT_EQ(back->terms[1].scope.stand, 6);
  m.terms[1].params = {-0.5};
  back = DecodeWearModel(EncodeWearModel(m));
  ASSERT_FALSE(back.ok());
  EXPECT_NE(back.status().message().find("terms[1].params"), std::string::npos)
      << back.status().message();
  // A knee: its side in the sign of the scale, kept; none is refused.
  m.terms.pop_back();
  ModelTerm hinge;
  hinge.covariate = "temperature_c";
  hinge.form = TermForm::kHinge;
  hinge.params = {0.8, 894.5};
  hinge.scale = -18.25;
  m.terms.push_back(hinge);
  back = DecodeWearModel(EncodeWearModel(m));
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  ASSERT_EQ(back->terms.size(), 2u);
  EXPECT_EQ(back->terms[1].form, TermForm::kHinge);
  EXPECT_EQ(back->terms[1].params, (std::vector<double>{0.8, 894.5}));
  EXPECT_EQ(back->terms[1].scale, -18.25);
  m.terms[1].scale = 0;
  back = DecodeWearModel(EncodeWearModel(m));
  ASSERT_FALSE(back.ok());
  EXPECT_NE(back.status().message().find("terms[1].scale"), std::string::npos)
      << back.status().message();
  // A gate: its covariate, side and threshold, kept.
  m.terms.pop_back();
  ModelTerm gated;
  gated.covariate = "lubrication";
  gated.form = TermForm::kFlag;
  gated.params = {-0.35};
  gated.scope.stand = 7;
  gated.scope.gate = "speed_mps";
  gated.scope.gate_at = 11.625;
  gated.scope.gate_above = false;
  m.terms.push_back(gated);
  back = DecodeWearModel(EncodeWearModel(m));
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(back->terms[1].scope, gated.scope);
}

// A gate is all three fields or none, with a side and a finite threshold,
// and never on a reading's term.
TEST(ModelCodecTest, AGateIsWholeAndOnAWearTerm) {
  const std::string head =
      R"({"terms":[{"covariate":"lubrication","form":"flag","params":[-0.3],)"
      R"("center":0,"scale":1,"scope":)";
  StatusOr<std::vector<ModelTerm>> ok = DecodeModelTerms(
      head + R"({"gate":"speed_mps","gate_side":"above","gate_at":11.5}}]})");
  ASSERT_TRUE(ok.ok()) << ok.status().ToString();
  EXPECT_EQ(ok->front().scope.gate, "speed_mps");
  EXPECT_TRUE(ok->front().scope.gate_above);
  EXPECT_EQ(ok->front().scope.gate_at, 11.5);
  const std::pair<const char*, const char*> bad[] = {
      {R"({"gate":"speed_mps","gate_side":"above"})", "scope.gate_at"},
      {R"({"gate":"speed_mps","gate_side":"over","gate_at":1})",
       "scope.gate_side"},
      {R"({"gate_side":"above","gate_at":1})", "scope.gate"},
      {R"({"gate":"","gate_side":"above","gate_at":1})", "scope.gate"},
      {R"({"gate":"speed_mps","gate_side":"below","gate_at":"11"})",
       "scope.gate_at"},
  };
  for (const auto& [scope, field] : bad) {
    StatusOr<std::vector<ModelTerm>> refused =
        DecodeModelTerms(head + scope + "}]}");
    ASSERT_FALSE(refused.ok()) << scope;
    EXPECT_NE(refused.status().message().find(std::string("terms[0].") + field),
              std::string::npos)
        << refused.status().message();
  }
  StatusOr<std::vector<ModelTerm>> reading = DecodeModelTerms(
      R"({"terms":[{"covariate":"cooling_h","form":"offset_linear",)"
      R"("params":[2],"center":0,"scale":1,"scope":)"
      R"({"gate":"speed_mps","gate_side":"above","gate_at":11.5}}]})");
  ASSERT_FALSE(reading.ok());
  EXPECT_NE(reading.status().message().find("terms[0].scope.gate"),
            std::string::npos)
      << reading.status().message();
}

// Scoped, cell and offset-per-level terms keep their scope and reference
// level; a term without "scope" (stored before scopes) applies everywhere.
TEST(ModelCodecTest, ScopedTermsRoundTrip) {
  WearModel m = MakeModel(WearLaw::kWang, 1);
  ModelTerm temp;
  temp.covariate = "temperature_c";
  temp.form = TermForm::kLogLinear;
  temp.params = {-0.25};
  temp.scope.stand = 7;
  temp.scope.position = 1;  // Position::kBottom;
  m.terms.push_back(temp);
  ModelTerm cell;
  cell.covariate = kCellCovariateName;
  cell.form = TermForm::kCell;
  cell.params = {0.26};
  cell.scope.stand = 6;
  cell.scope.roll_type = "HiCr-S2";
  cell.scope.grade = "HSLA";
  m.terms.push_back(cell);
  ModelTerm grinder;
  grinder.covariate = "grinder";
  grinder.form = TermForm::kOffsetPerLevel;
  grinder.params = {-15.5, 3.25};
  grinder.num_levels = 3;
  grinder.reference_level = 1;
  grinder.levels = {"B", "A", "C"};
  m.terms.push_back(grinder);
  const std::string json = EncodeWearModel(m);
  EXPECT_NE(json.find("\"scope\":{\"stand\":\"F7\",\"position\":\"bottom\"}"),
            std::string::npos)
      << json;
  StatusOr<WearModel> back = DecodeWearModel(json);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  ASSERT_EQ(back->terms.size(), 3u);
  EXPECT_EQ(back->terms[0].scope, temp.scope);
  EXPECT_EQ(back->terms[1].scope, cell.scope);
  EXPECT_EQ(back->terms[1].form, TermForm::kCell);
  EXPECT_EQ(back->terms[2].form, TermForm::kOffsetPerLevel);
  EXPECT_EQ(back->terms[2].reference_level, 1);
  EXPECT_EQ(back->terms[2].params, grinder.params);
  StatusOr<std::vector<ModelTerm>> old = DecodeModelTerms(
      R"({"terms":[{"covariate":"temperature_c","form":"log_linear","params":[0.1]}]})");
  ASSERT_TRUE(old.ok()) << old.status().ToString();
  EXPECT_TRUE(old->front().scope.IsAll());
  EXPECT_EQ(old->front().reference_level, 0);
  StatusOr<std::vector<ModelTerm>> bad = DecodeModelTerms(
      R"({"terms":[{"covariate":"x","form":"flag","params":[0.1],"scope":{"stand":"F9"}}]})");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("terms[0].scope.stand"),
            std::string::npos)
      << bad.status().message();
  // A reference level outside the levels (it would shift every offset onto
  // another level, or read past the parameters), or on another form.
  for (
      const char* doc :
      {R"({"terms":[{"covariate":"g","form":"offset_per_level","params":[1,2],"num_levels":3,"reference_level":3}]})",
       R"({"terms":[{"covariate":"g","form":"offset_per_level","params":[1,2],"num_levels":3,"reference_level":-1}]})",
       R"({"terms":[{"covariate":"x","form":"flag","params":[0.1],"reference_level":1}]})"}) {
    StatusOr<std::vector<ModelTerm>> refused = DecodeModelTerms(doc);
    ASSERT_FALSE(refused.ok()) << doc;
    EXPECT_NE(refused.status().message().find("terms[0].reference_level"),
              std::string::npos)
        << refused.status().message();
  }
  // A measurement term scoped by grade: a reading is of a roll, which
  // rolls many grades, so the scope has no meaning and is refused.
  StatusOr<std::vector<ModelTerm>> graded = DecodeModelTerms(
      R"({"terms":[{"covariate":"g","form":"offset_per_level","params":[1],"num_levels":2,)"
      R"("levels":["A","B"],"scope":{"grade":"HSLA"}}]})");
  ASSERT_FALSE(graded.ok());
  EXPECT_NE(graded.status().message().find("terms[0].scope.grade"),
            std::string::npos)
      << graded.status().message();
}

TEST(ModelCodecTest, CoefficientsAreListedByName) {
  const WearModel m = MakeModel(WearLaw::kWang, 1);
  const std::string json = EncodeWearModel(m);
  EXPECT_NE(json.find("\"kF[F6/top]\":0.1"), std::string::npos) << json;
  EXPECT_NE(json.find("\"kS[DP600]\""), std::string::npos);
  EXPECT_NE(json.find("\"law\":\"wang\""), std::string::npos);
  EXPECT_EQ(json.find("\"k\":"), std::string::npos);  // names are unique
}

TEST(ModelCodecTest, NonFiniteCovarianceAndEmptyCovariance) {
  WearModel m = MakeModel(WearLaw::kNikitenko, 3);
  m.covariance(0, 1) = std::numeric_limits<double>::quiet_NaN();
  m.covariance(1, 0) = std::numeric_limits<double>::infinity();
  m.covariance(2, 2) = -std::numeric_limits<double>::infinity();
  StatusOr<WearModel> back = DecodeWearModel(EncodeWearModel(m));
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  ExpectSame(m, *back);

  m.covariance.resize(0, 0);
  back = DecodeWearModel(EncodeWearModel(m));
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->covariance.rows(), 0);
}

TEST(ModelCodecTest, AmbiguousCoefficientNamesStillRoundTrip) {
  // kRS["A|B" x "C"] and kRS["A" x "B|C"] share the name "kRS[A|B|C]".
  StatusOr<KStructure> ks =
      KStructure::ForOption(2, {"F6/top"}, {"A|B", "A"}, {"C", "B|C"});
  ASSERT_TRUE(ks.ok());
  WearModel m;
  m.structure = *ks;
  for (int i = 0; i < m.structure.num_coefficients(); ++i) {
    m.k.push_back(0.5 + i);
  }
  StatusOr<WearModel> back = DecodeWearModel(EncodeWearModel(m));
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  ExpectSame(m, *back);
}

TEST(ModelCodecTest, PriorModelRoundTrips) {
  StatusOr<WearModel> prior =
      PriorModel(WearLaw::kCao, 2, {"F6/top", "F7/bottom"}, 0.3);
  ASSERT_TRUE(prior.ok());
  EXPECT_EQ(prior->K(0, -1, -1), 0.3);
  StatusOr<WearModel> back = DecodeWearModel(EncodeWearModel(*prior));
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  ExpectSame(*prior, *back);
}

TEST(ModelCodecTest, RejectsBadDocuments) {
  const std::string good = EncodeWearModel(MakeModel(WearLaw::kWang, 3));
  EXPECT_EQ(DecodeWearModel("{").status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(DecodeWearModel("[]").status().code(),
            StatusCode::kInvalidArgument);
  std::string bad_law = good;
  bad_law.replace(bad_law.find("\"wang\""), 6, "\"oops\"");
  StatusOr<WearModel> r = DecodeWearModel(bad_law);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("law"), std::string::npos);
  std::string missing = good;
  missing.replace(missing.find("kF[F6/top]"), 10, "kF[F5/top]");
  r = DecodeWearModel(missing);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("coefficients.kF[F6/top]"),
            std::string::npos)
      << r.status().message();
}

TEST(ModelCodecTest, ModelOverLevelsTakesCoefficientsByNameUnknownIsOne) {
  const WearModel m = MakeModel(WearLaw::kWang, 1);
  StatusOr<WearModel> over = ModelOverLevels(
      m, {"F7/top", "F5/top"}, {"HSS-S1", "NEW"}, {"DP600", "S235", "X"});
  ASSERT_TRUE(over.ok());
  const KStructure& a = m.structure;
  const KStructure& b = over->structure;
  EXPECT_EQ(over->k[b.CoefficientIndex("kF[F7/top]")],
            m.k[a.CoefficientIndex("kF[F7/top]")]);
  EXPECT_EQ(over->k[b.CoefficientIndex("kF[F5/top]")], 1.0);
  EXPECT_EQ(over->k[b.CoefficientIndex("kR[HSS-S1]")],
            m.k[a.CoefficientIndex("kR[HSS-S1]")]);
  EXPECT_EQ(over->k[b.CoefficientIndex("kS[X]")], 1.0);
  EXPECT_EQ(over->covariance.rows(), 0);  // levels changed
  // Same K for a cell both know.
  EXPECT_EQ(over->K(0, 0, 0),
            m.K(a.PositionLevel("F7/top"), a.RollTypeLevel("HSS-S1"),
                a.GradeLevel("DP600")));
}

// The terms of a diagnosis JSON (its adopted_model) or of a model JSON;
// a bad term is refused naming terms[i].field.
TEST(ModelCodecTest, ModelTermsAreReadFromADiagnosisOrAModelAndChecked) {
  const std::string diag =
      R"({"verdict":"missing_physics_found","adopted_model":{"model":"wang","terms":[)"
      R"({"covariate":"campaign_length_before_m","form":"saturating","params":[0.4,11.5],)"
      R"("center":0,"scale":1}]}})";
  StatusOr<std::vector<ModelTerm>> t = DecodeModelTerms(diag);
  ASSERT_TRUE(t.ok()) << t.status().ToString();
  ASSERT_EQ(t->size(), 1u);
  EXPECT_EQ((*t)[0].form, TermForm::kSaturating);
  EXPECT_EQ((*t)[0].params, (std::vector<double>{0.4, 11.5}));
  // A knee below 895 (a hinge's negative scale: its side) is read as it is
  // (`calibrate --terms` on a cold-knee finding); a log-linear term's
  // scale must be positive, a hinge's must not be 0.
  StatusOr<std::vector<ModelTerm>> knee = DecodeModelTerms(
      R"({"terms":[{"covariate":"temperature_c","form":"hinge",)"
      R"("params":[0.8,895],"center":0,"scale":-18.5}]})");
  ASSERT_TRUE(knee.ok()) << knee.status().ToString();
  EXPECT_EQ(knee->front().scale, -18.5);
  for (
      const char* bad_scale :
      {R"({"terms":[{"covariate":"x","form":"log_linear","params":[0.1],"center":0,"scale":-1}]})",
       R"({"terms":[{"covariate":"x","form":"hinge","params":[0.1,2],"center":0,"scale":0}]})"}) {
    StatusOr<std::vector<ModelTerm>> refused = DecodeModelTerms(bad_scale);
    ASSERT_FALSE(refused.ok()) << bad_scale;
    EXPECT_NE(refused.status().message().find("terms[0].scale"),
              std::string::npos)
        << refused.status().message();
  }
  // A model's own "terms" round-trip through EncodeTerms.
  StatusOr<std::vector<ModelTerm>> again =
      DecodeModelTerms(R"({"terms":)" + EncodeTerms(*t) + "}");
  ASSERT_TRUE(again.ok());
  EXPECT_EQ((*again)[0].params, (*t)[0].params);
  struct Bad {
    const char* json;
    const char* field;
  };
  const Bad bad[] = {
      {R"({"terms":[{"covariate":"x","form":"log_linear","params":[0.1],"scale":0}]})",
       "terms[0].scale"},
      {R"({"terms":[{"covariate":"x","form":"power","params":[0.1],"center":-1}]})",
       "terms[0].center"},
      {R"({"terms":[{"covariate":"x","form":"log_linear","params":[0.1],"center":"a"}]})",
       "terms[0].center"},
      {R"({"terms":[{"covariate":"x","form":"binned","params":[0.1,0.2],"edges":[5,3]}]})",
       "terms[0].edges"},
      {R"({"terms":[{"covariate":"x","form":"decaying","params":[0.1]}]})",
       "terms[0].params"},
      {R"({"model":"wang"})", "no \"terms\""},
  };
  for (const Bad& b : bad) {
    StatusOr<std::vector<ModelTerm>> r = DecodeModelTerms(b.json);
    ASSERT_FALSE(r.ok()) << b.json;
    EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(r.status().message().find(b.field), std::string::npos)
        << r.status().message();
  }
}

}  // namespace
}  // namespace rollwear::storage
