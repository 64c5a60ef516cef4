// Every error case of docs/api.md and issue 3, through Router::Handle on
// the real MillStore: status, error code, field path, and that GET /v1/wear
// and the store's counters are unchanged afterwards.
#include <string>

#include <gtest/gtest.h>

#include "tests/api/api_test_util.h"

namespace rollwear::api::testing {
namespace {

TEST_F(RouterTest, MalformedJsonIs400WithNullField) {
  const std::string before = State();
  ExpectRejected(PostRaw("/v1/coils", "{\"coil_id\": \"K1\", "), 400,
                 "malformed_json", nullptr, before);
  ExpectRejected(PostRaw("/v1/coils", "not json"), 400, "malformed_json",
                 nullptr, before);
  ExpectRejected(PostRaw("/v1/roll-changes", ""), 400, "malformed_json",
                 nullptr, before);
}

TEST_F(RouterTest, BodyThatIsNotAnObjectIs400) {
  const std::string before = State();
  ExpectRejected(PostRaw("/v1/coils", "[1, 2, 3]"), 400, "wrong_type", nullptr,
                 before);
}

TEST_F(RouterTest, TooDeepNestingIs400) {
  const std::string before = State();
  std::string deep = "{\"a\":";
  for (int i = 0; i < 100; ++i) deep += "[";
  for (int i = 0; i < 100; ++i) deep += "]";
  deep += "}";
  ExpectRejected(PostRaw("/v1/coils", deep), 400, "nesting_too_deep", nullptr,
                 before);
}

TEST_F(RouterTest, WrongTypeNamesTheJsonPath) {
  const std::string before = State();
  json coil = CoilBody("K1", "C1", 1);
  coil["passes"][1]["force_kn"] = "17500";
  ExpectRejected(Post("/v1/coils", coil), 400, "wrong_type",
                 "passes[1].force_kn", before);

  coil = CoilBody("K1", "C1", 1);
  coil["seq"] = 1.5;  // a number, but not an integer
  ExpectRejected(Post("/v1/coils", coil), 400, "wrong_type", "seq", before);

  coil = CoilBody("K1", "C1", 1);
  coil["seq"] = "1";
  ExpectRejected(Post("/v1/coils", coil), 400, "wrong_type", "seq", before);

  coil = CoilBody("K1", "C1", 1);
  coil["passes"] = json::object();
  ExpectRejected(Post("/v1/coils", coil), 400, "wrong_type", "passes", before);

  coil = CoilBody("K1", "C1", 1);
  coil["passes"][0] = 42;
  ExpectRejected(Post("/v1/coils", coil), 400, "wrong_type", "passes[0]",
                 before);

  coil = CoilBody("K1", "C1", 1);
  coil["passes"][0]["lubrication"] = 0.5;
  ExpectRejected(Post("/v1/coils", coil), 400, "wrong_type",
                 "passes[0].lubrication", before);

  json roll_change = RollChangeBody("C2", "2026-03-02T06:00:00Z");
  roll_change["rolls"][2]["hardness_hb"] = nullptr;
  ExpectRejected(Post("/v1/roll-changes", roll_change), 400, "wrong_type",
                 "rolls[2].hardness_hb", before);
}

TEST_F(RouterTest, MissingFieldIs400) {
  const std::string before = State();
  json coil = CoilBody("K1", "C1", 1);
  coil["passes"][0].erase("width_mm");
  ExpectRejected(Post("/v1/coils", coil), 400, "missing_field",
                 "passes[0].width_mm", before);
  coil = CoilBody("K1", "C1", 1);
  coil.erase("coil_id");
  ExpectRejected(Post("/v1/coils", coil), 400, "missing_field", "coil_id",
                 before);
}

TEST_F(RouterTest, NegativeOrZeroForceWidthLengthAre400) {
  const std::string before = State();
  json coil = CoilBody("K1", "C1", 1);
  coil["passes"][1]["force_kn"] = -3.0;
  ExpectRejected(Post("/v1/coils", coil), 400, "out_of_range",
                 "passes[1].force_kn", before);
  coil = CoilBody("K1", "C1", 1);
  coil["passes"][0]["force_kn"] = 0;
  ExpectRejected(Post("/v1/coils", coil), 400, "out_of_range",
                 "passes[0].force_kn", before);
  coil = CoilBody("K1", "C1", 1);
  coil["passes"][0]["width_mm"] = 0.0;
  ExpectRejected(Post("/v1/coils", coil), 400, "out_of_range",
                 "passes[0].width_mm", before);
  coil = CoilBody("K1", "C1", 1);
  coil["passes"][1]["length_m"] = -820.5;
  ExpectRejected(Post("/v1/coils", coil), 400, "out_of_range",
                 "passes[1].length_m", before);
  coil = CoilBody("K1", "C1", 1);
  coil["passes"][1]["speed_mps"] = 0;
  ExpectRejected(Post("/v1/coils", coil), 400, "out_of_range",
                 "passes[1].speed_mps", before);
  coil = CoilBody("K1", "C1", 0);
  ExpectRejected(Post("/v1/coils", coil), 400, "out_of_range", "seq", before);
  coil = CoilBody("K1", "C1", 1);
  coil["passes"][0]["lubrication"] = 2;
  ExpectRejected(Post("/v1/coils", coil), 400, "out_of_range",
                 "passes[0].lubrication", before);
  coil = CoilBody("K1", "C1", 1);
  coil["passes"] = json::array();
  ExpectRejected(Post("/v1/coils", coil), 400, "out_of_range", "passes",
                 before);
}

TEST_F(RouterTest, ExitNotBelowEntryThicknessIs400) {
  const std::string before = State();
  json coil = CoilBody("K1", "C1", 1);
  coil["passes"][1]["exit_thickness_mm"] = 4.2;  // == entry
  ExpectRejected(Post("/v1/coils", coil), 400, "out_of_range",
                 "passes[1].exit_thickness_mm", before);
  coil["passes"][1]["exit_thickness_mm"] = 5.0;  // > entry
  ExpectRejected(Post("/v1/coils", coil), 400, "out_of_range",
                 "passes[1].exit_thickness_mm", before);
}

TEST_F(RouterTest, BadTimestampIs400) {
  const std::string before = State();
  json coil = CoilBody("K1", "C1", 1, "yesterday");
  ExpectRejected(Post("/v1/coils", coil), 400, "invalid_value", "rolled_at",
                 before);
  coil = CoilBody("K1", "C1", 1, "2026-03-01 07:00:00");  // no offset
  ExpectRejected(Post("/v1/coils", coil), 400, "invalid_value", "rolled_at",
                 before);
}

TEST_F(RouterTest, UnknownStandNameIs400AndUnmountedStandIs422) {
  const std::string before = State();
  json coil = CoilBody("K1", "C1", 1);
  coil["passes"][0]["stand"] = "F9";
  ExpectRejected(Post("/v1/coils", coil), 400, "invalid_value",
                 "passes[0].stand", before);
  coil["passes"][0]["stand"] = "F7";  // twice in one coil
  ExpectRejected(Post("/v1/coils", coil), 400, "invalid_value",
                 "passes[1].stand", before);
  // F3 is a valid stand, but no roll is mounted there.
  coil["passes"][0]["stand"] = "F3";
  const HttpResponse r = Post("/v1/coils", coil);
  ExpectRejected(r, 422, "inconsistent", "passes[0].stand", before);
  EXPECT_EQ(Parse(r)["error"]["message"],
            "passes[0].stand: no roll mounted at F3 in campaign C1; its rolls "
            "are at F6/top, F6/bottom, F7/top, F7/bottom");
}

TEST_F(RouterTest, CoilForUnknownCampaignIs404) {
  const std::string before = State();
  ExpectRejected(Post("/v1/coils", CoilBody("K1", "NO-SUCH", 1)), 404,
                 "not_found", nullptr, before);
}

TEST_F(RouterTest, CoilForEndedCampaignIs422) {
  ASSERT_EQ(Post("/v1/campaigns/C1/end", {{"ended_at", "2026-03-01T20:00:00Z"}})
                .status,
            200);
  const std::string before = State();
  ExpectRejected(Post("/v1/coils", CoilBody("K1", "C1", 1)), 422,
                 "inconsistent", "campaign_id", before);
}

TEST_F(RouterTest, DuplicateCoilWithOtherContentIs409) {
  ASSERT_EQ(Post("/v1/coils", CoilBody("K1", "C1", 1)).status, 201);
  const std::string before = State();
  json other = CoilBody("K1", "C1", 1);
  other["passes"][0]["force_kn"] = 22000.0;
  ExpectRejected(Post("/v1/coils", other), 409, "conflict", nullptr, before);
}

TEST_F(RouterTest, DuplicateCoilWithSameContentIs200AndCountedOnce) {
  const HttpResponse first = Post("/v1/coils", CoilBody("K1", "C1", 1));
  ASSERT_EQ(first.status, 201) << first.body;
  const std::string after_first = State();
  EXPECT_EQ(store_->Counters().coils, 1);
  for (int i = 0; i < 3; ++i) {
    const HttpResponse again = Post("/v1/coils", CoilBody("K1", "C1", 1));
    EXPECT_EQ(again.status, 200) << again.body;
    EXPECT_EQ(Parse(again).value("outcome", ""), "unchanged");
    EXPECT_EQ(State(), after_first) << "a repeated coil was counted twice";
  }
  EXPECT_EQ(store_->Counters().coils, 1);
  EXPECT_EQ(router_->metrics()->coils_ingested(), 1);
}

TEST_F(RouterTest, OversizeBodyIs413) {
  ApiOptions options;
  options.body_limit_bytes = 1024;
  MakeRouter(options);
  const std::string before = State();
  json coil = CoilBody("K1", "C1", 1);
  coil["padding"] = std::string(2000, 'x');  // unknown field, but too big
  ExpectRejected(Post("/v1/coils", coil), 413, "payload_too_large", nullptr,
                 before);
}

TEST_F(RouterTest, MissingOrWrongTokenIs401WhenATokenIsConfigured) {
  ApiOptions options;
  options.token = "s3cret-token";
  MakeRouter(options);
  const std::string before = State();
  const json coil = CoilBody("K1", "C1", 1);
  ExpectRejected(Post("/v1/coils", coil), 401, "unauthorized", nullptr, before);
  ExpectRejected(Post("/v1/coils", coil, "Bearer wrong-token"), 401,
                 "unauthorized", nullptr, before);
  ExpectRejected(Post("/v1/coils", coil, "Bearer s3cret-toke"), 401,
                 "unauthorized", nullptr, before);
  ExpectRejected(Post("/v1/coils", coil, "Bearer s3cret-token-and-more"), 401,
                 "unauthorized", nullptr, before);
  ExpectRejected(Post("/v1/coils", coil, "Basic s3cret-token"), 401,
                 "unauthorized", nullptr, before);
  ExpectRejected(Post("/v1/calibrations", json::object()), 401, "unauthorized",
                 nullptr, before);
  ExpectRejected(Post("/v1/measurements",
                      MeasurementBody("C1", "F6", "top", "R-F6-top", 10)),
                 401, "unauthorized", nullptr, before);
  // GETs need no token; the right token is accepted.
  EXPECT_EQ(Get("/v1/wear").status, 200);
  EXPECT_EQ(Get("/healthz").status, 200);
  EXPECT_EQ(Post("/v1/coils", coil, "Bearer s3cret-token").status, 201);
  EXPECT_EQ(Post("/v1/coils", coil, "bearer s3cret-token").status, 200);
}

TEST_F(RouterTest, UnknownCalibrationIs404) {
  const std::string before = State();
  ExpectRejected(Get("/v1/calibrations/999"), 404, "not_found", nullptr,
                 before);
  ExpectRejected(Get("/v1/calibrations/abc"), 404, "not_found", nullptr,
                 before);
  ExpectRejected(Get("/v1/calibrations/-1"), 404, "not_found", nullptr, before);
}

TEST_F(RouterTest, BadCalibrationRequestIs400) {
  const std::string before = State();
  ExpectRejected(Post("/v1/calibrations", {{"model", "archard"}}), 400,
                 "invalid_value", "model", before);
  ExpectRejected(Post("/v1/calibrations", {{"option", 4}}), 400, "out_of_range",
                 "option", before);
  ExpectRejected(Post("/v1/calibrations", {{"option", "2"}}), 400, "wrong_type",
                 "option", before);
  EXPECT_TRUE(store_->ListCalibrations(10).empty());
}

// A control body is options only: a misspelt option must not silently run
// with the default (issue 14: {"modle": "cao"} ran a Wang calibration).
TEST_F(RouterTest, ControlBodiesRefuseUnknownFields) {
  const std::string before = State();
  const HttpResponse typo = Post("/v1/calibrations", {{"modle", "cao"}});
  ExpectRejected(typo, 400, "unknown_field", "modle", before);
  EXPECT_NE(Parse(typo)["error"]["message"].get<std::string>().find(
                "known: model, option"),
            std::string::npos)
      << typo.body;
  ExpectRejected(Post("/v1/calibrations", {{"model", "cao"}, {"optoin", 2}}),
                 400, "unknown_field", "optoin", before);
  // The unknown member is named even when a known one is bad too.
  ExpectRejected(Post("/v1/calibrations", {{"option", 9}, {"modle", "cao"}}),
                 400, "unknown_field", "modle", before);
  // An empty model is out of range (docs/api.md), a misspelt one invalid.
  ExpectRejected(Post("/v1/calibrations", {{"model", ""}}), 400,
                 "out_of_range", "model", before);
  ExpectRejected(Post("/v1/calibrations", {{"model", "wagn"}}), 400,
                 "invalid_value", "model", before);
  EXPECT_TRUE(store_->ListCalibrations(10).empty());

  ExpectRejected(Post("/v1/diagnoses", {{"adpot", true}}), 400, "unknown_field",
                 "adpot", before);
  ExpectRejected(Post("/v1/diagnoses", {{"adopt", false}, {"model", "cao"}}),
                 400, "unknown_field", "model", before);
  EXPECT_EQ(Get("/v1/diagnoses/1").status, 404) << "a diagnosis was queued";

  // The known fields alone are still accepted.
  const HttpResponse ok =
      Post("/v1/calibrations", {{"model", "cao"}, {"option", 3}});
  ASSERT_EQ(ok.status, 202) << ok.body;
  const json rec = Parse(Get("/v1/calibrations/" +
                             std::to_string(Parse(ok)["id"].get<int64_t>())));
  EXPECT_EQ(rec["model"], "cao");
  EXPECT_EQ(rec["option"], 3);
}

// A data body may carry fields the format does not define (the mill's own
// columns): they are accepted as its extra fields (their decoding:
// codec_decode_test.cc); a campaign end ignores them; an extra field that
// is an object or array is refused and nothing is stored.
TEST_F(RouterTest, DataBodiesAcceptExtraFields) {
  json rc = RollChangeBody("C2", "2026-03-02T06:00:00Z");
  rc["crew"] = "B";
  rc["rolls"][0]["supplier"] = "Gontermann";
  rc["rolls"][1]["grind_count"] = 3;
  HttpResponse r = Post("/v1/roll-changes", rc);
  ASSERT_EQ(r.status, 201) << r.body;
  EXPECT_EQ(Post("/v1/roll-changes", rc).status, 200);

  const std::string at = "2026-03-02T07:00:00Z";
  json coil = CoilBody("K1", "C2", 1, at);
  coil["operator_note"] = "night shift";
  coil["passes"][0]["water_flow_m3h"] = 120.5;
  coil["passes"][1]["bender"] = json{{"kn", 400}};
  const std::string before = State();
  ExpectRejected(Post("/v1/coils", coil), 400, "wrong_type",
                 "passes[1].bender", before);
  coil["passes"][1]["bender_kn"] = 400;
  coil["passes"][1].erase("bender");
  r = Post("/v1/coils", coil);
  ASSERT_EQ(r.status, 201) << r.body;
  r = Post("/v1/coils", coil);
  EXPECT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(Parse(r).value("outcome", ""), "unchanged");
  EXPECT_EQ(store_->Counters().coils, 1);

  json end = {{"ended_at", "2026-03-02T20:00:00Z"}, {"reason", "planned"}};
  r = Post("/v1/campaigns/C2/end", end);
  ASSERT_EQ(r.status, 200) << r.body;

  json m = MeasurementBody("C2", "F6", "top", "R-F6-top", 120);
  m["measured_at"] = "2026-03-02T22:00:00Z";  // after C2's end
  m["grinder"] = "G2";
  r = Post("/v1/measurements", m);
  EXPECT_EQ(r.status, 201) << r.body;
  EXPECT_EQ(store_->Counters().measurements, 1);
}

TEST_F(RouterTest, UnknownRoutesAre404AndWrongMethods405) {
  const std::string before = State();
  ExpectRejected(Get("/v1/nothing"), 404, "not_found", nullptr, before);
  ExpectRejected(Get("/v2/wear"), 404, "not_found", nullptr, before);
  ExpectRejected(Get("/v1/wear/F6/top/extra"), 404, "not_found", nullptr,
                 before);
  ExpectRejected(Get("/v1/coils"), 405, "method_not_allowed", nullptr, before);
  ExpectRejected(Post("/v1/wear", json::object()), 405, "method_not_allowed",
                 nullptr, before);
  ExpectRejected(Send("DELETE", "/v1/calibrations", ""), 405,
                 "method_not_allowed", nullptr, before);
  ExpectRejected(Send("PUT", "/v1/coils", CoilBody("K1", "C1", 1).dump()), 405,
                 "method_not_allowed", nullptr, before);
  // The Allow header lists what the routes declared with that pattern
  // answer; the 405 is labelled with the first of them.
  const auto allow = [](const HttpResponse& r) {
    for (const auto& [name, value] : r.headers) {
      if (name == "Allow") return value;
    }
    return std::string("<none>");
  };
  EXPECT_EQ(allow(Send("DELETE", "/v1/calibrations", "")), "GET, HEAD, POST");
  EXPECT_EQ(allow(Get("/v1/coils")), "POST");
  EXPECT_EQ(allow(Send("PUT", "/v1/wear/F6/top", "")), "GET, HEAD");
  EXPECT_EQ(Send("DELETE", "/v1/diagnoses", "").route.route_id,
            RouteId::kDiagnosesList);
  EXPECT_EQ(Get("/v1/nothing").route.route_id, RouteId::kUnmatched);
  // A literal route comes before the parameter that would take its path.
  EXPECT_EQ(Get("/v1/models/active").route.route_id, RouteId::kModelsActive);
  EXPECT_EQ(Get("/v1/models/history").route.route_id, RouteId::kModelHistory);
  EXPECT_EQ(Get("/v1/models/7").route.route_id, RouteId::kModel);
  EXPECT_EQ(Get("/v1/wear/F6/top/profile").route.route_id,
            RouteId::kWearProfile);
  EXPECT_EQ(Get("/v1/diagnoses/3/report").route.route_id,
            RouteId::kDiagnosisReport);
}

TEST_F(RouterTest, UnknownOrUnmountedWearPositionIs404) {
  const std::string before = State();
  ExpectRejected(Get("/v1/wear/F9/top"), 404, "not_found", nullptr, before);
  ExpectRejected(Get("/v1/wear/F6/middle"), 404, "not_found", nullptr, before);
  ExpectRejected(Get("/v1/wear/F1/top"), 404, "not_found", nullptr, before);
}

TEST_F(RouterTest, BadRollChangesAreRejected) {
  const std::string before = State();
  json rc = RollChangeBody("C2", "2026-03-02T06:00:00Z");
  rc["rolls"][1]["diameter_mm"] = 0;
  ExpectRejected(Post("/v1/roll-changes", rc), 400, "out_of_range",
                 "rolls[1].diameter_mm", before);
  rc = RollChangeBody("C2", "2026-03-02T06:00:00Z");
  rc["rolls"][3]["position"] = "top";  // F7/top twice
  ExpectRejected(Post("/v1/roll-changes", rc), 400, "invalid_value",
                 "rolls[3].stand", before);
  rc = RollChangeBody("C2", "2026-03-02T06:00:00Z");
  rc["rolls"][0]["position"] = "middle";
  ExpectRejected(Post("/v1/roll-changes", rc), 400, "invalid_value",
                 "rolls[0].position", before);
  // The key C1 is stored with other content.
  ExpectRejected(
      Post("/v1/roll-changes", RollChangeBody("C1", "2026-03-01T06:30:00Z")),
      409, "conflict", nullptr, before);
}

TEST_F(RouterTest, BadMeasurementsAreRejected) {
  ASSERT_EQ(Post("/v1/campaigns/C1/end", {{"ended_at", "2026-03-01T20:00:00Z"}})
                .status,
            200);
  const std::string before = State();
  ExpectRejected(Post("/v1/measurements",
                      MeasurementBody("C1", "F6", "top", "R-OTHER", 120)),
                 422, "inconsistent", "roll_id", before);
  ExpectRejected(Post("/v1/measurements",
                      MeasurementBody("C9", "F6", "top", "R-F6-top", 120)),
                 404, "not_found", nullptr, before);
  // A finite wear below zero is a warning, not a refusal
  // (router_suspect_test.cc); a number beyond double's range (no finite
  // wear) is refused as malformed.
  std::string huge = MeasurementBody("C1", "F6", "top", "R-F6-top", 120).dump();
  huge.replace(huge.find("120"), 3, "1e999");
  ExpectRejected(Send("POST", "/v1/measurements", huge), 400, "malformed_json",
                 nullptr, before);
  json m = MeasurementBody("C1", "F6", "top", "R-F6-top", 120);
  m["wear_center_um"] = "120";
  ExpectRejected(Post("/v1/measurements", m), 400, "wrong_type",
                 "wear_center_um", before);
  ASSERT_EQ(Post("/v1/measurements",
                 MeasurementBody("C1", "F6", "top", "R-F6-top", 120))
                .status,
            201);
  const std::string stored = State();
  EXPECT_EQ(Post("/v1/measurements",
                 MeasurementBody("C1", "F6", "top", "R-F6-top", 120))
                .status,
            200);
  ExpectRejected(Post("/v1/measurements",
                      MeasurementBody("C1", "F6", "top", "R-F6-top", 121)),
                 409, "conflict", nullptr, stored);
}

TEST_F(RouterTest, MeasurementOfARunningCampaignIs422) {
  const std::string before = State();
  const HttpResponse r = Post(
      "/v1/measurements", MeasurementBody("C1", "F6", "top", "R-F6-top", 120));
  ExpectRejected(r, 422, "inconsistent", "campaign_id", before);
  EXPECT_EQ(Parse(r)["error"]["message"],
            "campaign_id: campaign C1 has not ended: a roll is measured after "
            "its campaign (end it first)");
  EXPECT_EQ(store_->Counters().measurements, 0);
}

TEST_F(RouterTest, MeasurementBeforeItsCampaignEndedIs422) {
  ASSERT_EQ(Post("/v1/campaigns/C1/end", {{"ended_at", "2026-03-01T20:00:00Z"}})
                .status,
            200);
  const std::string before = State();
  json m = MeasurementBody("C1", "F6", "top", "R-F6-top", 120);
  m["measured_at"] = "2023-03-01T19:00:00Z";  // years early
  const HttpResponse r = Post("/v1/measurements", m);
  ExpectRejected(r, 422, "inconsistent", "measured_at", before);
  EXPECT_EQ(Parse(r)["error"]["message"],
            "measured_at: must not be before the end of campaign C1 "
            "(2026-03-01T20:00:00Z): a roll is measured after it is taken "
            "out, got 2023-03-01T19:00:00Z");
  EXPECT_EQ(store_->Counters().measurements, 0);
  m["measured_at"] = "2026-03-01T20:00:00Z";  // at the end: fine
  EXPECT_EQ(Post("/v1/measurements", m).status, 201);
}

TEST_F(RouterTest, CampaignEndErrors) {
  const std::string before = State();
  ExpectRejected(
      Post("/v1/campaigns/NO-SUCH/end", {{"ended_at", "2026-03-01T20:00:00Z"}}),
      404, "not_found", nullptr, before);
  ExpectRejected(Post("/v1/campaigns/C1/end", {{"ended_at", 12}}), 400,
                 "wrong_type", "ended_at", before);
  ASSERT_EQ(Post("/v1/campaigns/C1/end", {{"ended_at", "2026-03-01T20:00:00Z"}})
                .status,
            200);
  const std::string ended = State();
  EXPECT_EQ(Post("/v1/campaigns/C1/end", {{"ended_at", "2026-03-01T20:00:00Z"}})
                .status,
            200);
  ExpectRejected(
      Post("/v1/campaigns/C1/end", {{"ended_at", "2026-03-01T21:00:00Z"}}), 409,
      "conflict", nullptr, ended);
}

TEST(HttpStatusFor, MapsEveryStatusCode) {
  EXPECT_EQ(HttpStatusFor(StatusCode::kInvalidArgument), 400);
  EXPECT_EQ(HttpStatusFor(StatusCode::kNotFound), 404);
  EXPECT_EQ(HttpStatusFor(StatusCode::kAlreadyExists), 409);
  EXPECT_EQ(HttpStatusFor(StatusCode::kFailedPrecondition), 422);
  EXPECT_EQ(HttpStatusFor(StatusCode::kUnavailable), 503);
  EXPECT_EQ(HttpStatusFor(StatusCode::kIoError), 500);
  EXPECT_EQ(HttpStatusFor(StatusCode::kInternal), 500);
  EXPECT_EQ(HttpStatusFor(StatusCode::kNumericalFailure), 500);
}

}  // namespace
}  // namespace rollwear::api::testing
