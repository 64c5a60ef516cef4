// `rollwear calibrate` on a dataset with profiles.csv prints the fitted
// shape of the wear across the barrel and the profile gap, and --json holds
// the contract's "profile" object (api.md); without profiles.csv neither
// appears.
#include <string>

#include <gtest/gtest.h>

#include "core/dataset/dataset_io.h"
#include "tests/e2e/e2e_util.h"

namespace rollwear::e2e {
namespace {

TEST(ProfileCliTest, CalibrateReportsTheProfileShapeAndGap) {
  TempDir dir;
  std::string out, err;
  ASSERT_EQ(RunRollwear({"simulate", "--out", dir / "d", "--campaigns", "60",
                         "--seed", "3", "--profiles"},
                        &out, &err),
            0)
      << out << err;
  ASSERT_EQ(
      RunRollwear({"calibrate", "--data", dir / "d", "--json", dir / "c.json"},
                  &out, &err),
      0)
      << out << err;
  EXPECT_NE(out.find("profile shape (K from the centre fit"), std::string::npos)
      << out;
  EXPECT_NE(out.find("profile validation:"), std::string::npos) << out;
  const json j = json::parse(ReadFile(dir / "c.json"));
  ASSERT_TRUE(j.contains("profile")) << j.dump(2);
  const json& p = j.at("profile");
  StatusOr<Dataset> data = ReadDataset(dir / "d");
  ASSERT_TRUE(data.ok());
  // Every point is in a training or a validation campaign.
  EXPECT_EQ(p.at("n_points_train").get<int>() + p.at("n_points_val").get<int>(),
            static_cast<int>(data->profile_points.size()));
  EXPECT_GT(p.at("n_points_val").get<int>(), 5000);
  for (const char* name : {"beta2", "beta4", "alpha1", "alpha2", "alpha3"}) {
    EXPECT_TRUE(p.at("shape").at(name).is_number()) << name;
    EXPECT_GT(p.at("standard_errors").at(name).get<double>(), 0) << name;
  }
  // The gap against the truth's profile noise floor (11.5 µm for seed 3):
  // 60 campaigns leave K less certain than the core test's 120, so a wider
  // band than its 10 %.
  const json truth = json::parse(ReadFile(dir / "d.truth.json"));
  const double floor = truth.at("profile").at("noise_floor_um").get<double>();
  const double gap_val = p.at("gap_val_um").get<double>();
  EXPECT_GT(gap_val, 0.9 * floor);
  EXPECT_LT(gap_val, 1.2 * floor);
  EXPECT_LT(p.at("gap_edge_val_um").get<double>(),
            p.at("gap_body_val_um").get<double>())
      << "the worn band's ends carry little wear, hence little scatter";
}

TEST(ProfileCliTest, WithoutProfilesCalibrateSaysNothingOfProfiles) {
  TempDir dir;
  std::string error, out, err;
  ASSERT_TRUE(Simulate(dir / "d", 30, 4, &error)) << error;
  ASSERT_EQ(
      RunRollwear({"calibrate", "--data", dir / "d", "--json", dir / "c.json"},
                  &out, &err),
      0)
      << out << err;
  EXPECT_EQ(out.find("profile"), std::string::npos) << out;
  const json j = json::parse(ReadFile(dir / "c.json"));
  EXPECT_FALSE(j.contains("profile"));
}

}  // namespace
}  // namespace rollwear::e2e
