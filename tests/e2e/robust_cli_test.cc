// The robust loss through the binary: on a simulated mill with the
// simulator's gross grinder errors (`--effect gross_errors`), `calibrate`
// and `diagnose` list the suspected outliers on stdout and in the
// `data_quality` object of their JSON, and the readings listed are the ones
// the truth file says the grinder got grossly wrong.
#include <cmath>
#include <map>
#include <string>
#include <tuple>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/e2e/e2e_util.h"

namespace rollwear::e2e {
namespace {

using Key = std::tuple<std::string, std::string, std::string>;

// Checks one tool's suspected_outliers against the truth; returns how many
// were listed.
int CheckOutliers(const json& quality, const std::map<Key, double>& gross) {
  EXPECT_EQ(quality.at("thresholds").at("outlier_threshold_sd").get<double>(),
            4.0);
  const json& list = quality.at("suspected_outliers");
  int listed_gross = 0;
  for (const json& o : list) {
    EXPECT_GT(std::abs(o.at("standardized_residual").get<double>()), 4.0) << o;
    const double measured = o.at("measured_um").get<double>();
    const double predicted = o.at("predicted_um").get<double>();
    EXPECT_EQ(o.at("standardized_residual").get<double>() > 0,
              measured > predicted);
    const std::string set = o.at("set").get<std::string>();
    EXPECT_TRUE(set == "training" || set == "validation") << set;
    const Key key{o.at("campaign_id").get<std::string>(),
                  o.at("stand").get<std::string>(),
                  o.at("position").get<std::string>()};
    listed_gross += gross.count(key) && gross.at(key) != 0;
  }
  const int n = static_cast<int>(list.size());
  EXPECT_GE(listed_gross, 3);
  EXPECT_GE(listed_gross, 0.8 * n);
  return n;
}

TEST(RobustCliTest, CalibrateAndDiagnoseListTheGrossErrors) {
  TempDir dir;
  std::string out;
  ASSERT_EQ(RunRollwear({"simulate", "--out", dir / "data", "--seed", "12",
                         "--campaigns", "200", "--effect", "gross_errors",
                         "--truth", dir / "truth.json"},
                        &out),
            0)
      << out;
  const json truth = json::parse(ReadFile(dir / "truth.json"));
  std::map<Key, double> gross;
  for (const json& r : truth.at("noise_free_wear_um")) {
    gross[{r.at("campaign_id").get<std::string>(),
           r.at("stand").get<std::string>(),
           r.at("position").get<std::string>()}] =
        r.at("gross_error_um").get<double>();
  }
  ASSERT_GT(truth.at("gross_errors").get<int>(), 10);

  ASSERT_EQ(RunRollwear({"calibrate", "--data", dir / "data", "--json",
                         dir / "cal.json"},
                        &out),
            0)
      << out;
  EXPECT_NE(out.find("suspected outliers: "), std::string::npos) << out;
  EXPECT_NE(out.find("r/sd = "), std::string::npos) << out;
  const json cal = json::parse(ReadFile(dir / "cal.json"));
  CheckOutliers(cal.at("data_quality"), gross);

  ASSERT_EQ(RunRollwear({"diagnose", "--data", dir / "data", "--json",
                         dir / "diag.json"},
                        &out),
            0)
      << out;
  EXPECT_NE(out.find("verdict: no_significant_mismatch"), std::string::npos)
      << out;
  EXPECT_NE(out.find("suspected outliers: "), std::string::npos) << out;
  const json diag = json::parse(ReadFile(dir / "diag.json"));
  CheckOutliers(diag.at("data_quality"), gross);
}

}  // namespace
}  // namespace rollwear::e2e
