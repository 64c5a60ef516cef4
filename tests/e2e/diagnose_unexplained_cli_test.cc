// The third verdict through the binary: a simulated mill whose grinder
// reads campaigns alternately 10 µm high and 10 µm low (no recorded
// quantity alternates with it) is answered `mismatch_located_unexplained`, with the mismatch
// located in plain words on stdout and in the JSON's `unexplained`, and no
// physics named.
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/e2e/e2e_util.h"

namespace rollwear::e2e {
namespace {

// Adds `offset_um` to wear_center_um (the last column) of every
// measurement of an even-numbered campaign (C0002, C0004 ...: every other
// campaign in time order) and subtracts it from the others.
void OffsetAlternateCampaigns(const std::string& path, double offset_um) {
  std::istringstream in(ReadFile(path));
  std::string line, out;
  std::getline(in, line);
  ASSERT_EQ(line, "campaign_id,stand,position,roll_id,measured_at,wear_center_um");
  out = line + "\n";
  while (std::getline(in, line)) {
    const size_t comma = line.rfind(',');
    const int campaign = std::stoi(line.substr(1, line.find(',') - 1));
    const double wear =
        std::stod(line.substr(comma + 1)) + (campaign % 2 == 0 ? offset_um : -offset_um);
    line = line.substr(0, comma + 1) + std::to_string(wear);
    out += line + "\n";
  }
  std::ofstream(path) << out;
}

TEST(DiagnoseUnexplainedCliTest, LocatesWithoutNamingPhysics) {
  TempDir dir;
  std::string out;
  ASSERT_EQ(RunRollwear({"simulate", "--out", dir / "data", "--seed", "31", "--campaigns",
                         "200"},
                        &out),
            0)
      << out;
  ASSERT_NO_FATAL_FAILURE(OffsetAlternateCampaigns(dir / "data/measurements.csv", 10.0));
  ASSERT_EQ(RunRollwear({"diagnose", "--data", dir / "data", "--json", dir / "diag.json"},
                        &out),
            0)
      << out;
  EXPECT_NE(out.find("verdict: mismatch_located_unexplained"), std::string::npos) << out;
  EXPECT_NE(out.find("mismatch at campaign order"), std::string::npos) << out;
  EXPECT_NE(out.find("no recorded quantity explains it"), std::string::npos) << out;
  EXPECT_EQ(out.find("finding 1"), std::string::npos) << out;
  const json diag = json::parse(ReadFile(dir / "diag.json"));
  EXPECT_EQ(diag.at("verdict"), "mismatch_located_unexplained");
  EXPECT_EQ(diag.at("findings"), json::array());
  ASSERT_FALSE(diag.at("unexplained").empty()) << diag.dump();
  const json& u = diag.at("unexplained")[0];
  const std::string dim = u.at("dimension").get<std::string>();
  EXPECT_TRUE(dim == "runs_along_time" || dim == "lag1_along_time") << u;
  EXPECT_LT(u.at("p_value").get<double>(), 0.001) << u;
  EXPECT_GT(u.at("mean_residual_um").get<double>(), 5.0) << u;
  EXPECT_TRUE(u.at("where").is_string());
}

}  // namespace
}  // namespace rollwear::e2e
