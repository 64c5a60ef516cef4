// Data quality in the CLI tools: a gauge fault of -62.6 µm is listed with
// its file:line and left out of the fit instead of refusing the dataset; a
// roll position without a pass makes a calibration not usable; --strict
// turns the warnings into errors (exit 1); import stores suspect
// measurements flagged (refused under --strict).
#include <string>

#include <gtest/gtest.h>

#include "core/dataset/dataset_io.h"
#include "engine/wear_prediction.h"
#include "storage/mill_store.h"
#include "tests/e2e/e2e_util.h"

namespace rollwear::e2e {
namespace {

constexpr char kSummary[] =
    "data quality: 1 warning(s), 1 suspect measurement(s) excluded from "
    "fitting: 1 negative_wear\n  measurements.csv:5 ";

// A simulated folder whose 4th measurement (line 5) reads -62.6 µm.
Dataset WriteGaugeFault(const TempDir& dir) {
  std::string error;
  EXPECT_TRUE(Simulate(dir / "clean", 30, 4, &error)) << error;
  StatusOr<Dataset> data = ReadDataset(dir / "clean");
  EXPECT_TRUE(data.ok());
  data->measurements[3].wear_center_um = -62.6;
  EXPECT_TRUE(WriteDataset(*data, dir / "fault").ok());
  return std::move(data).value();
}

TEST(DataQualityCliTest, CalibrateListsTheGaugeFaultAndFitsTheRest) {
  TempDir dir;
  const Dataset data = WriteGaugeFault(dir);
  std::string out, err;
  ASSERT_EQ(RunRollwear({"calibrate", "--data", dir / "fault", "--json",
                         dir / "c.json"},
                        &out, &err),
            0)
      << out << err;
  EXPECT_NE(out.find(kSummary), std::string::npos) << out;
  EXPECT_NE(out.find("-62.6 µm"), std::string::npos) << out;
  const json j = json::parse(ReadFile(dir / "c.json"));
  EXPECT_TRUE(j.at("usable").get<bool>());
  EXPECT_EQ(j.at("n_train").get<int>() + j.at("n_val").get<int>(),
            static_cast<int>(data.measurements.size()) - 1);
  const json& q = j.at("data_quality");
  EXPECT_EQ(q.at("suspect_measurements"), 1);
  EXPECT_EQ(q.at("counts").at("negative_wear"), 1);
  ASSERT_EQ(q.at("issues").size(), 1u);
  EXPECT_EQ(q.at("issues")[0].at("file"), "measurements.csv");
  EXPECT_EQ(q.at("issues")[0].at("line"), 5);
  EXPECT_EQ(q.at("issues")[0].at("value_um"), -62.6);

  // --strict: the warning is an error, exit 1, nothing written.
  EXPECT_EQ(RunRollwear({"calibrate", "--data", dir / "fault", "--strict",
                         "--json", dir / "s.json"},
                        &out, &err),
            1);
  EXPECT_NE(err.find("rollwear calibrate: --strict: 1 data-quality "
                     "warning(s), first measurements.csv:5 "),
            std::string::npos)
      << err;
  EXPECT_EQ(ReadFile(dir / "s.json"), "");
  // The clean folder passes --strict.
  EXPECT_EQ(RunRollwear({"calibrate", "--data", dir / "clean", "--strict"},
                        &out, &err),
            0)
      << err;
  EXPECT_NE(out.find("data quality: no warnings\n"), std::string::npos);
}

TEST(DataQualityCliTest, DiagnoseRunsAndReportsDataQuality) {
  TempDir dir;
  WriteGaugeFault(dir);
  std::string out, err;
  ASSERT_EQ(RunRollwear({"diagnose", "--data", dir / "fault", "--json",
                         dir / "d.json"},
                        &out, &err),
            0)
      << out << err;
  EXPECT_NE(out.find(kSummary), std::string::npos) << out;
  const json j = json::parse(ReadFile(dir / "d.json"));
  EXPECT_EQ(j.at("data_quality").at("suspect_measurements"), 1);
  EXPECT_EQ(j.at("data_quality").at("issues")[0].at("line"), 5);
  EXPECT_TRUE(j.contains("verdict"));
}

TEST(DataQualityCliTest, ImportStoresSuspectMeasurementsFlagged) {
  TempDir dir;
  const Dataset data = WriteGaugeFault(dir);
  const int n = static_cast<int>(data.measurements.size());
  std::string out, err;
  // --strict: refused, nothing imported.
  EXPECT_EQ(RunRollwear({"import", "--db", dir / "strict.db", dir / "fault",
                         "--strict"},
                        &out, &err),
            1);
  EXPECT_NE(err.find("nothing imported"), std::string::npos) << err;
  ASSERT_EQ(
      RunRollwear({"import", "--db", dir / "x.db", dir / "fault"}, &out, &err),
      0)
      << out << err;
  EXPECT_NE(out.find(kSummary), std::string::npos) << out;
  EXPECT_NE(out.find("\n1 suspect measurement(s) stored flagged (listed "
                     "above): kept, left out of calibration and diagnosis\n"),
            std::string::npos)
      << out;
  for (const char* db : {"strict.db", "x.db"}) {
    StatusOr<std::unique_ptr<storage::MillStore>> store =
        engine::OpenStore(dir / db);
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    const bool strict = std::string(db) == "strict.db";
    EXPECT_EQ((*store)->Counters().measurements, strict ? 0 : n);
    EXPECT_EQ((*store)->Counters().suspect_measurements, strict ? 0 : 1);
    if (strict) continue;
    StatusOr<storage::FittingData> fitting = (*store)->ReadFittingData();
    ASSERT_TRUE(fitting.ok());
    EXPECT_EQ(static_cast<int>(fitting->fit.measurements.size()), n - 1);
    ASSERT_EQ(fitting->quality.issues.size(), 1u);
    EXPECT_EQ(fitting->quality.issues[0].value_um, -62.6);
  }
}

TEST(DataQualityCliTest, PositionWithoutPassMakesCalibrationNotUsable) {
  TempDir dir;
  std::string error;
  ASSERT_TRUE(Simulate(dir / "clean", 30, 4, &error)) << error;
  StatusOr<Dataset> data = ReadDataset(dir / "clean");
  ASSERT_TRUE(data.ok());
  Mount extra = data->mounts[0];
  extra.stand = 5;  // the simulated mill rolls at F6 and F7 only
  extra.roll_id = "R-F5";
  data->mounts.push_back(extra);
  ASSERT_TRUE(WriteDataset(*data, dir / "f5").ok());
  std::string out, err;
  EXPECT_EQ(RunRollwear({"calibrate", "--data", dir / "f5", "--json",
                         dir / "c.json"},
                        &out, &err),
            1);
  EXPECT_NE(out.find("1 no_passes"), std::string::npos) << out;
  EXPECT_NE(out.find("not usable: a roll position received no pass"),
            std::string::npos)
      << out;
  const json j = json::parse(ReadFile(dir / "c.json"));
  EXPECT_FALSE(j.at("usable").get<bool>());
  EXPECT_EQ(j.at("data_quality").at("counts").at("no_passes"), 1);
  EXPECT_EQ(j.at("data_quality").at("issues")[0].at("file"), "mounts.csv");
}

}  // namespace
}  // namespace rollwear::e2e
