// service/sim_truth_json: the simulator's truth file parses as JSON and
// carries every measurement's noise-free wear and the concealed effects.
#include "service/sim_truth_json.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/core/simulator_test_util.h"

namespace rollwear {
namespace {

using simulator_test::Simulated;

TEST(SimTruthJsonTest, WritesEveryMeasurementAndEffect) {
  const Simulation sim = Simulated(3, 12, {"warm_measurement"}, 0.1);
  const std::string path =
      (std::filesystem::temp_directory_path() /
       ("rollwear_truth_test_" + std::to_string(::getpid()) + ".json"))
          .string();
  ASSERT_TRUE(WriteTruthJson(sim.truth, path).ok());
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  std::filesystem::remove(path);
  const nlohmann::json doc = nlohmann::json::parse(text.str());

  EXPECT_EQ(doc.at("seed").get<uint64_t>(), 3u);
  ASSERT_EQ(doc.at("noise_free_wear_um").size(), sim.data.measurements.size());
  const nlohmann::json& first = doc.at("noise_free_wear_um").at(0);
  EXPECT_EQ(first.at("campaign_id").get<std::string>(),
            sim.truth.noise_free_keys[0].campaign_id);
  EXPECT_DOUBLE_EQ(first.at("noise_free_wear_um").get<double>(),
                   sim.truth.noise_free_wear_um[0]);
  EXPECT_EQ(doc.at("k_roll_type").size(), sim.truth.k_roll_type.size());
  ASSERT_EQ(doc.at("effects").size(), 1u);
  EXPECT_EQ(doc.at("effects")[0].at("name").get<std::string>(),
            "warm_measurement");
  EXPECT_DOUBLE_EQ(
      doc.at("effects")[0].at("parameters").at("amplitude_um").get<double>(),
      60.0);
  EXPECT_DOUBLE_EQ(doc.at("noise_floor_um").get<double>(),
                   sim.truth.noise_floor_um);
}

TEST(SimTruthJsonTest, ListsTheGrossErrors) {
  const Simulation sim = Simulated(5, 60, {"gross_errors"});
  const nlohmann::json doc = nlohmann::json::parse(TruthJson(sim.truth));
  const nlohmann::json& rows = doc.at("noise_free_wear_um");
  ASSERT_EQ(rows.size(), sim.data.measurements.size());
  int gross = 0;
  for (size_t i = 0; i < rows.size(); ++i) {
    const double g = rows[i].at("gross_error_um").get<double>();
    EXPECT_DOUBLE_EQ(g, sim.truth.gross_error_um[i]);
    gross += g != 0;
  }
  EXPECT_GT(gross, 0);  // 3 % of 240 readings
  EXPECT_EQ(doc.at("gross_errors").get<int>(), gross);
  EXPECT_EQ(doc.at("effects")[0].at("covariate").get<std::string>(), "");
}

TEST(SimTruthJsonTest, DescribesTheProfilesShape) {
  SimulationTruth truth;
  EXPECT_FALSE(nlohmann::json::parse(TruthJson(truth)).contains("profile"));
  truth.has_profiles = true;
  truth.profile_shape = {-0.05, 1.2, 30, 4};
  truth.profile_noise_floor_um = 9.5;
  const nlohmann::json doc = nlohmann::json::parse(TruthJson(truth));
  const nlohmann::json& p = doc.at("profile");
  EXPECT_DOUBLE_EQ(p.at("body_beta2").get<double>(), -0.05);
  EXPECT_DOUBLE_EQ(p.at("edge_amplitude").get<double>(), 1.2);
  EXPECT_DOUBLE_EQ(p.at("edge_decay_mm").get<double>(), 30);
  EXPECT_DOUBLE_EQ(p.at("point_noise_sd_um").get<double>(), 4);
  EXPECT_DOUBLE_EQ(p.at("noise_floor_um").get<double>(), 9.5);
  EXPECT_NE(p.at("form").get<std::string>().find("exp(-d/edge_decay_mm)"),
            std::string::npos);
}

TEST(SimTruthJsonTest, NonFiniteNumbersAreNull) {
  SimulationTruth truth;
  truth.noise_floor_um = std::numeric_limits<double>::quiet_NaN();
  truth.k_grade["S1"] = std::numeric_limits<double>::infinity();
  const nlohmann::json doc = nlohmann::json::parse(TruthJson(truth));
  EXPECT_TRUE(doc.at("noise_floor_um").is_null());
  EXPECT_TRUE(doc.at("k_grade").at("S1").is_null());
  EXPECT_TRUE(doc.at("noise_free_wear_um").empty());
}

// Effect families: form, strength, scope, levels and expressibility; the
// old effects keep their four fields only.
TEST(SimTruthJsonTest, RecordsFamilyFormScopeLevels) {
  const Simulation sim = Simulated(
      6, 12, {"temperature", "grade_stand:0", "inexpressible_order"});
  const nlohmann::json doc = nlohmann::json::parse(TruthJson(sim.truth));
  const nlohmann::json& e = doc.at("effects");
  ASSERT_EQ(e.size(), 3u);
  EXPECT_FALSE(e[0].contains("form"));
  EXPECT_EQ(e[1].at("name"), "grade_stand:0");
  EXPECT_EQ(e[1].at("covariate"), "grade");
  EXPECT_EQ(e[1].at("form"), "multiplier");
  EXPECT_EQ(e[1].at("scope"), nlohmann::json({{"stand", "F7"}}));
  EXPECT_EQ(e[1].at("levels"), nlohmann::json({"S355"}));
  EXPECT_DOUBLE_EQ(e[1].at("strength").get<double>(),
                   sim.truth.effects[1].strength);
  EXPECT_TRUE(e[1].at("expressible").get<bool>());
  EXPECT_FALSE(e[1].contains("mismatch"));
  EXPECT_FALSE(e[2].at("expressible").get<bool>());
  EXPECT_EQ(e[2].at("mismatch"), "campaign order x grade");
  EXPECT_TRUE(e[2].at("scope").is_null());
}

}  // namespace
}  // namespace rollwear
