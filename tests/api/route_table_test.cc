// The route table (api/routes.h, api/router_routes.cc): every metrics
// label is declared exactly once with a method and a pattern, no two
// routes share a method and pattern, and the pattern matcher takes what
// the API's paths need (one segment, a rest that may hold '/', decoding).
#include <set>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "api/metrics.h"
#include "api/routes.h"

namespace rollwear::api {
namespace {

TEST(RouteTableTest, EveryRouteIsDeclaredOnceWithAMethodAndPattern) {
  std::set<std::pair<std::string, std::string>> seen;
  for (int i = 0; i < kNumRoutes; ++i) {
    const auto id = static_cast<RouteId>(i);
    const RouteSpec& spec = RouteSpecOf(id);
    EXPECT_EQ(spec.id, id) << "route " << i << " is not in the table";
    if (id == RouteId::kUnmatched) {
      EXPECT_STREQ(spec.pattern, "unmatched");
      continue;
    }
    const std::string method = spec.method;
    EXPECT_TRUE(method == "GET" || method == "POST") << spec.pattern;
    EXPECT_EQ(spec.pattern[0], '/') << spec.pattern;
    EXPECT_TRUE(seen.emplace(method, spec.pattern).second)
        << method << " " << spec.pattern << " declared twice";
    // Every POST needs the token; no GET does.
    EXPECT_EQ(spec.needs_token, method == "POST") << spec.pattern;
    // Only the coil path runs asynchronously, and only wear reads inline.
    EXPECT_EQ(spec.execution == Execution::kAsync, id == RouteId::kCoils);
    EXPECT_EQ(spec.execution == Execution::kInline,
              id == RouteId::kWear || id == RouteId::kWearAt);
  }
}

// The metrics label is the OpenAPI path template: a rest parameter's '*'
// is the table's, not the label's (dashboards keep their series).
TEST(RouteTableTest, LabelsAreThePathTemplates) {
  EXPECT_STREQ(RouteLabel(RouteId::kCampaignEnd),
               "/v1/campaigns/{campaign_id}/end");
  EXPECT_STREQ(RouteLabel(RouteId::kRoll), "/v1/rolls/{roll_id}");
  EXPECT_STREQ(RouteLabel(RouteId::kRollPage), "/rolls/{roll_id}");
  EXPECT_STREQ(RouteLabel(RouteId::kWearAt), "/v1/wear/{stand}/{position}");
  EXPECT_STREQ(RouteLabel(RouteId::kUnmatched), "unmatched");
  EXPECT_STREQ(RoutePath(RouteId::kRoll), RouteLabel(RouteId::kRoll));
  for (int i = 0; i < kNumRoutes; ++i) {
    EXPECT_EQ(std::string(RouteLabel(static_cast<RouteId>(i))).find('*'),
              std::string::npos);
  }
}

TEST(RouteTableTest, PatternsTakeOneSegmentOrTheRest) {
  PathArgs a;
  EXPECT_TRUE(MatchPattern("/v1/wear", "/v1/wear", &a));
  EXPECT_FALSE(MatchPattern("/v1/wear", "/v1/wear/", &a));
  EXPECT_FALSE(MatchPattern("/v1/wear", "/v1/wea", &a));

  ASSERT_TRUE(
      MatchPattern("/v1/wear/{stand}/{position}", "/v1/wear/F6/top", &a));
  EXPECT_EQ(a[0], "F6");
  EXPECT_EQ(a[1], "top");
  EXPECT_FALSE(MatchPattern("/v1/wear/{stand}/{position}", "/v1/wear/F6/", &a));
  EXPECT_FALSE(
      MatchPattern("/v1/wear/{stand}/{position}", "/v1/wear//top", &a));
  EXPECT_FALSE(
      MatchPattern("/v1/wear/{stand}/{position}", "/v1/wear/F6/top/x", &a));
  ASSERT_TRUE(MatchPattern("/v1/wear/{stand}/{position}/profile",
                           "/v1/wear/F7/bottom/profile", &a));
  EXPECT_EQ(a[1], "bottom");

  // A rest parameter holds '/', raw or sent as %2F, and is decoded.
  ASSERT_TRUE(MatchPattern("/v1/rolls/{roll_id*}", "/v1/rolls/R%2F12", &a));
  EXPECT_EQ(a[0], "R/12");
  ASSERT_TRUE(MatchPattern("/v1/rolls/{roll_id*}", "/v1/rolls/R/12", &a));
  EXPECT_EQ(a[0], "R/12");
  EXPECT_FALSE(MatchPattern("/v1/rolls/{roll_id*}", "/v1/rolls/", &a));
  ASSERT_TRUE(MatchPattern("/v1/campaigns/{campaign_id*}/end",
                           "/v1/campaigns/C%2F7/end", &a));
  EXPECT_EQ(a[0], "C/7");
  EXPECT_FALSE(MatchPattern("/v1/campaigns/{campaign_id*}/end",
                            "/v1/campaigns//end", &a));
  EXPECT_FALSE(MatchPattern("/v1/campaigns/{campaign_id*}/end",
                            "/v1/campaigns/C7/ended", &a));
  // A one-segment parameter keeps an encoded slash inside its segment.
  ASSERT_TRUE(MatchPattern("/v1/diagnoses/{id}", "/v1/diagnoses/4%2F2", &a));
  EXPECT_EQ(a[0], "4/2");
}

}  // namespace
}  // namespace rollwear::api
