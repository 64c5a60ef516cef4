// Implausible measurements over the API (docs/api.md, POST
// /v1/measurements): a finite reading that cannot be physical wear is
// stored flagged and answered 201 with "suspect"; /metrics counts it and
// the dashboard shows it with its reason.
#include <string>

#include <gtest/gtest.h>

#include "tests/api/api_test_util.h"

namespace rollwear::api::testing {
namespace {

class SuspectRouterTest : public RouterTest {
 protected:
  void EndC1() {
    for (int i = 1; i <= 3; ++i) {
      ASSERT_EQ(
          Post("/v1/coils", CoilBody("K" + std::to_string(i), "C1", i)).status,
          201);
    }
    ASSERT_EQ(
        Post("/v1/campaigns/C1/end", {{"ended_at", "2026-03-01T20:00:00Z"}})
            .status,
        200);
  }
};

TEST_F(SuspectRouterTest, NegativeReadingIs201FlaggedAndRepeatsItsFlag) {
  ASSERT_NO_FATAL_FAILURE(EndC1());
  const json bad = MeasurementBody("C1", "F6", "top", "R-F6-top", -62.6);
  const HttpResponse r = Post("/v1/measurements", bad);
  ASSERT_EQ(r.status, 201) << r.body;
  const json answer = Parse(r);
  EXPECT_EQ(answer["outcome"], "created");
  // Under 8 stored readings: core's fixed bound, -4 * 12.5 µm.
  const std::string suspect = answer["suspect"].get<std::string>();
  EXPECT_EQ(suspect.rfind("negative_wear: -62.6 µm is below -50.0 µm", 0), 0u)
      << suspect;
  const HttpResponse again = Post("/v1/measurements", bad);
  ASSERT_EQ(again.status, 200) << again.body;
  EXPECT_EQ(Parse(again)["suspect"], suspect);
  EXPECT_EQ(store_->Counters().measurements, 1);

  const HttpResponse fine =
      Post("/v1/measurements",
           MeasurementBody("C1", "F7", "bottom", "R-F7-bottom", 85.5));
  ASSERT_EQ(fine.status, 201) << fine.body;
  EXPECT_TRUE(Parse(fine)["suspect"].is_null()) << fine.body;
  EXPECT_EQ(store_->Counters().measurements, 2);
  EXPECT_EQ(store_->Counters().suspect_measurements, 1);
}

TEST_F(SuspectRouterTest, MetricsCountAndDashboardShowsTheSuspect) {
  ASSERT_NO_FATAL_FAILURE(EndC1());
  ASSERT_EQ(Post("/v1/measurements",
                 MeasurementBody("C1", "F6", "top", "R-F6-top", -62.6))
                .status,
            201);
  ASSERT_EQ(Post("/v1/measurements",
                 MeasurementBody("C1", "F7", "bottom", "R-F7-bottom", 85.5))
                .status,
            201);
  const HttpResponse m = Get("/metrics");
  ASSERT_EQ(m.status, 200);
  for (const char* line : {"\nrollwear_measurements_stored 2\n",
                           "\nrollwear_measurements_suspect_stored 1\n"}) {
    EXPECT_NE(m.body.find(line), std::string::npos) << line << m.body;
  }
  const HttpResponse page = Get("/");
  ASSERT_EQ(page.status, 200);
  EXPECT_NE(page.body.find("Suspect measurements"), std::string::npos);
  EXPECT_NE(page.body.find("<li>F6/top of campaign C1: -62.6 µm — "
                           "negative_wear: -62.6 µm is below -50.0 µm"),
            std::string::npos)
      << page.body;
  // Only the flagged reading is listed; the plausible one is plotted.
  EXPECT_EQ(page.body.find("of campaign C1: 85.5"), std::string::npos);
}

}  // namespace
}  // namespace rollwear::api::testing
