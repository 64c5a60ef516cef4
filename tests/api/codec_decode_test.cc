// The request decoder (api/codec.h on api/json_scan.h) on its own: JSON
// syntax and nesting, integers and numbers, strings with escapes, member
// order, a member twice, and every rule of a data body's extra fields, each
// with the code and JSON path of its error.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "api/codec.h"
#include "tests/api/api_test_util.h"

namespace rollwear::api::testing {
namespace {

constexpr int kDepth = 16;

// The error of decoding `body` as a coil (the decoder must refuse it).
ApiError CoilError(const std::string& body, int max_depth = kDepth) {
  storage::CoilIn coil;
  ApiError error;
  EXPECT_FALSE(DecodeCoil(body, max_depth, &coil, &error)) << body;
  EXPECT_EQ(error.status, 400);
  EXPECT_FALSE(error.message.empty());
  return error;
}

storage::CoilIn Coil(const std::string& body) {
  storage::CoilIn coil;
  ApiError error;
  EXPECT_TRUE(DecodeCoil(body, kDepth, &coil, &error)) << error.message;
  return coil;
}

void ExpectCoilError(const json& body, const std::string& code,
                     const std::string& field) {
  const ApiError error = CoilError(body.dump());
  EXPECT_EQ(error.code, code) << error.message;
  EXPECT_EQ(error.field, field) << error.message;
}

TEST(CodecDecodeTest, MalformedJsonIsRefusedBeforeAnyField) {
  // A wrong field first, broken syntax later: the syntax wins.
  for (const std::string body :
       {R"({"coil_id": 5, "x": })", R"({"coil_id": "K1"} x)",
        R"({"coil_id": "K1"}})", R"({"a": [1, 2 3]})", R"({"a": nul})",
        R"({"a": truex})", R"({"a": 01})", R"({"a": 1.})", R"({"a": "\x"})",
        R"({"a": "\ud800"})", "{\"a\": \"tab\there\"}", "{\"a\": \"\xff\"}",
        "{\"a\": \"\xc3\x28\"}", "", "  ", "not json", R"([1, 2)"}) {
    const ApiError error = CoilError(body);
    EXPECT_EQ(error.code, "malformed_json") << body << ": " << error.message;
    EXPECT_EQ(error.field, "") << body;
  }
  // The position, where the parser knows it.
  EXPECT_NE(
      CoilError("{\"coil_id\": \"K1\",\n \"seq\": 1 2}").message.find("line 2"),
      std::string::npos);
}

TEST(CodecDecodeTest, NestingIsCountedOutsideStrings) {
  DiagnosisRequest request;
  ApiError error;
  // 3 levels: allowed at 3 (then refused as an unknown field), not at 2.
  const std::string three = R"({"a": [{"b": 1}]})";
  EXPECT_FALSE(DecodeDiagnosisRequest(three, 3, &request, &error));
  EXPECT_EQ(error.code, "unknown_field");
  EXPECT_FALSE(DecodeDiagnosisRequest(three, 2, &request, &error));
  EXPECT_EQ(error.code, "nesting_too_deep");
  EXPECT_EQ(error.field, "");
  // Brackets inside a string are text.
  EXPECT_FALSE(
      DecodeDiagnosisRequest(R"({"adopt": "[[[[\"[[["})", 1, &request, &error));
  EXPECT_EQ(error.code, "wrong_type");
  EXPECT_EQ(CoilError("{\"a\":" + std::string(1000, '[') +
                      std::string(1000, ']') + "}")
                .code,
            "nesting_too_deep");
  // Never closed: malformed before it is deep.
  EXPECT_EQ(CoilError(std::string(1000, '[')).code, "malformed_json");
  EXPECT_EQ(CoilError("[[[[[[[[[[[[[[[[[1]]]]]]]]]]]]]]]]]").code,
            "nesting_too_deep");
  EXPECT_EQ(CoilError("[[[[[[[[[[[[[[[[1]]]]]]]]]]]]]]]]").code, "wrong_type");
}

TEST(CodecDecodeTest, BodyMustBeAnObject) {
  for (const std::string body : {"[1, 2, 3]", "42", "\"K1\"", "true", "null"}) {
    const ApiError error = CoilError(body);
    EXPECT_EQ(error.code, "wrong_type") << body;
    EXPECT_EQ(error.field, "") << body;
  }
}

TEST(CodecDecodeTest, MemberOrderAndEscapesDoNotMatter) {
  const json sorted = CoilBody("K1", "C1", 3);  // members sorted by name
  const storage::CoilIn plain = Coil(sorted.dump());
  const nlohmann::ordered_json reordered = {{"passes", sorted["passes"]},
                                            {"grade", "DP600"},
                                            {"seq", 3},
                                            {"rolled_at", sorted["rolled_at"]},
                                            {"campaign_id", "C1"},
                                            {"coil_id", "K1"}};
  const storage::CoilIn again = Coil(reordered.dump());
  EXPECT_EQ(again.coil_id, plain.coil_id);
  EXPECT_EQ(again.rolled_at, plain.rolled_at);
  EXPECT_EQ(again.passes, plain.passes);
  // Escapes in names and values decode (\u005f is '_').
  std::string body = CoilBody("K1", "C1", 3).dump();
  body.replace(body.find("\"coil_id\":\"K1\""), 14,
               R"("coil\u005fid":"K\u00e9\n\"1\ud83d\ude00")");
  EXPECT_EQ(Coil(body).coil_id, "K\xc3\xa9\n\"1\xf0\x9f\x98\x80");
}

TEST(CodecDecodeTest, IntegersAreToldApartFromOtherNumbers) {
  const auto seq = [](const std::string& token) {
    std::string body = CoilBody("K1", "C1", 1).dump();
    body.replace(body.find("\"seq\":1"), 7, "\"seq\":" + token);
    return body;
  };
  EXPECT_EQ(Coil(seq("7")).seq, 7);
  EXPECT_EQ(CoilError(seq("7.0")).code, "wrong_type");
  EXPECT_EQ(CoilError(seq("7e0")).code, "wrong_type");
  EXPECT_EQ(CoilError(seq("123456789012345678901234567890")).code,
            "wrong_type");
  EXPECT_EQ(CoilError(seq("18446744073709551615")).code, "out_of_range");
  EXPECT_EQ(CoilError(seq("-0")).code, "out_of_range");
  EXPECT_EQ(CoilError(seq("1000000001")).code, "out_of_range");
  EXPECT_EQ(CoilError(seq("1000000001")).field, "seq");
  // lubrication 0/1 or a boolean.
  json coil = CoilBody("K1", "C1", 1);
  coil["passes"][1]["lubrication"] = true;
  EXPECT_TRUE(Coil(coil.dump()).passes[1].lubrication);
  coil["passes"][1]["lubrication"] = 1.0;
  ExpectCoilError(coil, "wrong_type", "passes[1].lubrication");
}

TEST(CodecDecodeTest, NumbersKeepTheirValueAndAreQuotedAsSent) {
  std::string body = CoilBody("K1", "C1", 1).dump();
  body.replace(body.find("21000.0"), 7, "2.1e4");
  EXPECT_EQ(Coil(body).passes[0].force_kn, 21000.0);
  body.replace(body.find("2.1e4"), 5, "-3.50");
  ApiError error = CoilError(body);
  EXPECT_EQ(error.code, "out_of_range");
  EXPECT_EQ(error.field, "passes[0].force_kn");
  EXPECT_EQ(error.message, "passes[0].force_kn must be > 0, got -3.50");
  // Beyond double's range: valid JSON, not a finite number.
  body.replace(body.find("-3.50"), 5, "1e999");
  error = CoilError(body);
  EXPECT_EQ(error.code, "out_of_range");
  EXPECT_EQ(error.field, "passes[0].force_kn");
  EXPECT_EQ(error.message, "passes[0].force_kn must be > 0, got inf");
}

TEST(CodecDecodeTest, MemberTwiceIsRefusedWithItsPath) {
  std::string body = CoilBody("K1", "C1", 1).dump();
  body.insert(1, R"("grade":"CQ",)");
  ApiError error = CoilError(body);
  EXPECT_EQ(error.code, "invalid_value");
  EXPECT_EQ(error.field, "grade");
  body = CoilBody("K1", "C1", 1).dump();
  body.insert(body.rfind("{") + 1, R"("crew":"A","crew":null,)");
  error = CoilError(body);
  EXPECT_EQ(error.code, "invalid_value");
  EXPECT_EQ(error.field, "passes[1].crew");
}

TEST(CodecDecodeTest, DataBodyExtraFieldsAreDecoded) {
  json coil = CoilBody("K1", "C1", 1);
  coil["operator_note"] = "night shift";
  coil["crew"] = "B";
  coil["inspected"] = true;
  coil["comment"] = nullptr;
  coil["passes"][0]["water_flow_m3h"] = 120.5;
  coil["passes"][0]["work_roll_bender"] = -4;
  coil["passes"][1]["cooling"] = false;
  const storage::CoilIn in = Coil(coil.dump());
  EXPECT_TRUE(in.extra.numeric.empty());
  ASSERT_EQ(in.extra.factor.size(), 3u);  // sorted by name; null not kept
  EXPECT_EQ(in.extra.factor[0].first, "crew");
  EXPECT_EQ(in.extra.factor[1],
            std::make_pair(std::string("inspected"), std::string("true")));
  EXPECT_EQ(*in.extra.Factor("operator_note"), "night shift");
  EXPECT_EQ(in.extra.Factor("comment"), nullptr);
  ASSERT_EQ(in.passes[0].extra.numeric.size(), 2u);
  EXPECT_EQ(in.passes[0].extra.numeric[0].first, "water_flow_m3h");
  EXPECT_EQ(*in.passes[0].extra.Numeric("water_flow_m3h"), 120.5);
  EXPECT_EQ(*in.passes[0].extra.Numeric("work_roll_bender"), -4.0);
  EXPECT_EQ(*in.passes[1].extra.Factor("cooling"), "false");
  EXPECT_TRUE(in.passes[1].extra.numeric.empty());

  json rc = RollChangeBody("C2", "2026-03-02T06:00:00Z");
  rc["crew"] = "B";
  rc["rolls"][1]["grind_count"] = 3;
  rc["rolls"][1]["supplier"] = "Gontermann";
  storage::RollChangeIn change;
  ApiError error;
  ASSERT_TRUE(DecodeRollChange(rc.dump(), kDepth, &change, &error))
      << error.message;
  EXPECT_EQ(*change.extra.Factor("crew"), "B");
  EXPECT_TRUE(change.rolls[0].extra.empty());
  EXPECT_EQ(*change.rolls[1].extra.Numeric("grind_count"), 3.0);
  EXPECT_EQ(*change.rolls[1].extra.Factor("supplier"), "Gontermann");

  json m = MeasurementBody("C1", "F6", "top", "R-F6-top", 120);
  m["grinder"] = "G2";
  m["depth_profile_points"] = 41;
  storage::MeasurementIn measurement;
  ASSERT_TRUE(DecodeMeasurement(m.dump(), kDepth, &measurement, &error))
      << error.message;
  EXPECT_EQ(*measurement.extra.Factor("grinder"), "G2");
  EXPECT_EQ(*measurement.extra.Numeric("depth_profile_points"), 41.0);
}

// The input rules run once per record: a record the decoder admitted
// says so (rules_checked), so the store does not run them again; one whose
// rules are broken is refused here, with its JSON path, and says nothing.
// A record built any other way starts unchecked and the store checks it.
TEST(CodecDecodeTest, AnAdmittedRecordSaysItsRulesWereChecked) {
  EXPECT_FALSE(storage::CoilIn().rules_checked);
  EXPECT_FALSE(storage::RollChangeIn().rules_checked);
  EXPECT_FALSE(storage::MeasurementIn().rules_checked);
  EXPECT_TRUE(Coil(CoilBody("K1", "C1", 1).dump()).rules_checked);
  json bad = CoilBody("K1", "C1", 1);
  bad["passes"][0]["force_kn"] = -5;
  storage::CoilIn coil;
  ApiError error;
  EXPECT_FALSE(DecodeCoil(bad.dump(), kDepth, &coil, &error));
  EXPECT_FALSE(coil.rules_checked);
  EXPECT_EQ(error.field, "passes[0].force_kn") << error.message;

  storage::RollChangeIn change;
  ASSERT_TRUE(DecodeRollChange(RollChangeBody("C2", "2026-03-02T06:00:00Z").dump(),
                               kDepth, &change, &error))
      << error.message;
  EXPECT_TRUE(change.rules_checked);
  storage::MeasurementIn measurement;
  ASSERT_TRUE(DecodeMeasurement(
      MeasurementBody("C1", "F6", "top", "R-F6-top", 120).dump(), kDepth,
      &measurement, &error))
      << error.message;
  EXPECT_TRUE(measurement.rules_checked);
  storage::MeasurementIn negative;
  EXPECT_FALSE(DecodeMeasurement(
      MeasurementBody("C1", "F6", "top", "", 120).dump(), kDepth,
      &negative, &error));
  EXPECT_FALSE(negative.rules_checked);
}

TEST(CodecDecodeTest, ExtraFieldOrderDoesNotMatter) {
  const std::string a =
      R"({"z_last":1,"a_first":"x","m":2.5,"coil_id":"K1","campaign_id":"C1",)"
      R"("seq":1,"rolled_at":"2026-03-01T07:00:00Z","grade":"DP600",)"
      R"("passes":[)" +
      PassBody("F6", 21000.0).dump() + "]}";
  const std::string b =
      R"({"coil_id":"K1","m":2.5,"campaign_id":"C1","a_first":"x",)"
      R"("seq":1,"rolled_at":"2026-03-01T07:00:00Z","grade":"DP600",)"
      R"("passes":[)" +
      PassBody("F6", 21000.0).dump() + R"(],"z_last":1})";
  EXPECT_EQ(Coil(a).extra, Coil(b).extra);
  EXPECT_EQ(Coil(a).extra.numeric.front().first, "m");
}

TEST(CodecDecodeTest, ExtraFieldRulesNameTheField) {
  json coil = CoilBody("K1", "C1", 1);
  coil["passes"][1]["bender"] = json{{"kn", 400}};
  ExpectCoilError(coil, "wrong_type", "passes[1].bender");
  coil = CoilBody("K1", "C1", 1);
  coil["profile"] = json::array({1, 2});
  ExpectCoilError(coil, "wrong_type", "profile");
  // One name at coil level and in a pass: the pass's is refused.
  coil = CoilBody("K1", "C1", 1);
  coil["crew"] = "B";
  coil["passes"][1]["crew"] = "C";
  ExpectCoilError(coil, "invalid_value", "passes[1].crew");
  coil["crew"] = nullptr;  // given, if empty
  ExpectCoilError(coil, "invalid_value", "passes[1].crew");
  // A column of coils.csv at the other level, an empty name.
  coil = CoilBody("K1", "C1", 1);
  coil["force_kn"] = 1;
  ExpectCoilError(coil, "invalid_value", "force_kn");
  coil = CoilBody("K1", "C1", 1);
  coil["passes"][1]["seq"] = 1;
  ExpectCoilError(coil, "invalid_value", "passes[1].seq");
  coil = CoilBody("K1", "C1", 1);
  coil["passes"][1][""] = 1;
  ExpectCoilError(coil, "out_of_range", "passes[1].");
  // A name longer than kMaxIdLength.
  coil = CoilBody("K1", "C1", 1);
  const std::string long_name(kMaxIdLength + 1, 'n');
  coil["passes"][0][long_name] = 1;
  ExpectCoilError(coil, "out_of_range", "passes[0]." + long_name);
  coil = CoilBody("K1", "C1", 1);
  coil[std::string(kMaxIdLength, 'n')] = 1;  // at the limit: kept
  EXPECT_EQ(Coil(coil.dump()).extra.numeric.size(), 1u);
  // A level longer than kMaxIdLength.
  coil = CoilBody("K1", "C1", 1);
  coil["note"] = std::string(kMaxIdLength + 1, 'x');
  ExpectCoilError(coil, "out_of_range", "note");
  // kMaxExtraFields per object, not one more.
  coil = CoilBody("K1", "C1", 1);
  for (size_t i = 0; i < kMaxExtraFields; ++i) {
    coil["passes"][0]["x" + std::to_string(100 + i)] = 1;
  }
  EXPECT_EQ(Coil(coil.dump()).passes[0].extra.numeric.size(), kMaxExtraFields);
  coil["passes"][0]["x" + std::to_string(100 + kMaxExtraFields)] = 1;
  ExpectCoilError(coil, "out_of_range",
                  "passes[0].x" + std::to_string(100 + kMaxExtraFields));
  // Beyond double's range.
  std::string body = CoilBody("K1", "C1", 1).dump();
  body.insert(1, R"("torque":-1e400,)");
  const ApiError error = CoilError(body);
  EXPECT_EQ(error.code, "out_of_range");
  EXPECT_EQ(error.field, "torque");

  json rc = RollChangeBody("C2", "2026-03-02T06:00:00Z");
  rc["ended_at"] = "2026-03-03T06:00:00Z";  // campaigns.csv's, not extra
  storage::RollChangeIn change;
  ApiError rc_error;
  EXPECT_FALSE(DecodeRollChange(rc.dump(), kDepth, &change, &rc_error));
  EXPECT_EQ(rc_error.code, "invalid_value");
  EXPECT_EQ(rc_error.field, "ended_at");
  rc = RollChangeBody("C2", "2026-03-02T06:00:00Z");
  rc["rolls"][3]["campaign_id"] = "C2";  // mounts.csv's
  EXPECT_FALSE(DecodeRollChange(rc.dump(), kDepth, &change, &rc_error));
  EXPECT_EQ(rc_error.code, "invalid_value");
  EXPECT_EQ(rc_error.field, "rolls[3].campaign_id");
  rc = RollChangeBody("C2", "2026-03-02T06:00:00Z");
  rc["rolls"][2]["chemistry"] = json{{"cr", 1.2}};
  EXPECT_FALSE(DecodeRollChange(rc.dump(), kDepth, &change, &rc_error));
  EXPECT_EQ(rc_error.code, "wrong_type");
  EXPECT_EQ(rc_error.field, "rolls[2].chemistry");

  json m = MeasurementBody("C1", "F6", "top", "R-F6-top", 120);
  m["profile"] = json::array({1, 2, 3});
  storage::MeasurementIn measurement;
  ApiError m_error;
  EXPECT_FALSE(DecodeMeasurement(m.dump(), kDepth, &measurement, &m_error));
  EXPECT_EQ(m_error.code, "wrong_type");
  EXPECT_EQ(m_error.field, "profile");
}

TEST(CodecDecodeTest, CampaignEndIgnoresOtherMembers) {
  UnixSeconds ended_at = 0;
  ApiError error;
  ASSERT_TRUE(DecodeCampaignEnd(
      R"({"reason": {"code": "planned"}, "ended_at": "2026-03-02T20:00:00Z"})",
      kDepth, &ended_at, &error))
      << error.message;
  EXPECT_GT(ended_at, 0);
  // Still JSON, and still one member of each name.
  EXPECT_FALSE(DecodeCampaignEnd(
      R"({"ended_at": "2026-03-02T20:00:00Z", "reason": [1,}")", kDepth,
      &ended_at, &error));
  EXPECT_EQ(error.code, "malformed_json");
  EXPECT_FALSE(DecodeCampaignEnd(
      R"({"ended_at": "2026-03-02T20:00:00Z", "ended_at": "2026-03-02T21:00:00Z"})",
      kDepth, &ended_at, &error));
  EXPECT_EQ(error.code, "invalid_value");
  EXPECT_EQ(error.field, "ended_at");
}

TEST(CodecDecodeTest, ControlBodiesRefuseEveryUnknownMember) {
  CalibrationRequest calibration;
  ApiError error;
  EXPECT_TRUE(DecodeCalibrationRequest(" \n", kDepth, &calibration, &error));
  EXPECT_TRUE(DecodeCalibrationRequest("{}", kDepth, &calibration, &error));
  EXPECT_FALSE(DecodeCalibrationRequest(R"({"model":"cao","note":null})",
                                        kDepth, &calibration, &error));
  EXPECT_EQ(error.code, "unknown_field");
  EXPECT_EQ(error.field, "note");
  EXPECT_FALSE(DecodeCalibrationRequest(R"({"model":"cao","model":"wang"})",
                                        kDepth, &calibration, &error));
  EXPECT_EQ(error.code, "invalid_value");
  EXPECT_EQ(error.field, "model");
  DiagnosisRequest diagnosis;
  EXPECT_TRUE(
      DecodeDiagnosisRequest(R"({"adopt":1})", kDepth, &diagnosis, &error));
  EXPECT_TRUE(diagnosis.adopt);
}

}  // namespace
}  // namespace rollwear::api::testing
