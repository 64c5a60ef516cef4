// Helpers shared by the storage tests: a temporary directory per test, a
// store opened on a real SQLite file in it, and small builders of valid
// roll changes, coils and measurements.
//
// Thread-safety: TempDir is per test; the builders are pure functions.
#ifndef ROLLWEAR_TESTS_STORAGE_STORE_TEST_UTIL_H_
#define ROLLWEAR_TESTS_STORAGE_STORE_TEST_UTIL_H_

#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/base/status.h"
#include "core/dataset/dataset.h"
#include "engine/mounted_rolls.h"
#include "engine/wear_prediction.h"
#include "storage/mill_store.h"

namespace rollwear::storage {

// The engine's answers the storage tests check the store's state through.
using engine::Forecast;
using engine::ForecastPosition;
using engine::PositionWear;
using engine::ProfileWear;
using engine::WearSnapshot;

namespace testing {

// The engine's answers about `store`'s mounted rolls (wear, profile,
// forecast: engine/mounted_rolls.h).
inline engine::MountedRolls Mounted(const MillStore& store) {
  return engine::MountedRolls(&store);
}

// True when a and b have the same bits (a round trip that keeps every digit).
inline bool BitEqual(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// A fresh directory under the system temp dir, removed afterwards.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = info != nullptr ? std::string(info->test_suite_name()) +
                                             "." + info->name()
                                       : "storage";
    for (char& c : name) {
      if (c == '/') c = '_';
    }
    path_ = std::filesystem::temp_directory_path() /
            ("rollwear-" + name + "-" + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string File(const std::string& name) const {
    return (path_ / name).string();
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// SQL taking a file of this build back to schema version 4 (undoes
// versions 7, 6 and 5): tests that fake a file of an older rollwear run it
// before undoing the older versions.
inline constexpr const char* kUndoSchemaSixAndFive =
    "DROP TABLE profile_points; DROP TABLE model_history; DROP TABLE diagnoses; "
    "DROP INDEX mounts_by_roll; DROP INDEX measurements_by_roll; "
    "ALTER TABLE models DROP COLUMN pinned; DROP TABLE wear_limits; ";

inline std::unique_ptr<MillStore> OpenStore(const std::string& path,
                                            StoreOptions options = {}) {
  StatusOr<std::unique_ptr<MillStore>> store = engine::OpenStore(path, options);
  EXPECT_TRUE(store.ok()) << store.status().ToString();
  if (!store.ok()) return nullptr;
  return std::move(store).value();
}

// F6/F7 top and bottom rolls, as the study's mill.
inline RollChangeIn MakeRollChange(const std::string& campaign_id,
                                   UnixSeconds started_at,
                                   const std::string& suffix = "") {
  RollChangeIn in;
  in.campaign_id = campaign_id;
  in.started_at = started_at;
  const char* types[] = {"ICDP-S3", "ICDP-S2", "HSS-S1", "HSS-S2"};
  int i = 0;
  for (int stand : {6, 7}) {
    for (Position p : {Position::kTop, Position::kBottom}) {
      MountedRollIn r;
      r.stand = stand;
      r.position = p;
      r.roll_id = "R" + std::to_string(stand) +
                  (p == Position::kTop ? "T" : "B") + suffix;
      r.roll_type = types[i];
      r.diameter_mm = 700.5 + i;
      r.hardness_hb = 520 + 3 * i;
      in.rolls.push_back(r);
      ++i;
    }
  }
  return in;
}

// A coil passing F6 and F7 whose numbers vary with `n`.
inline CoilIn MakeCoil(const std::string& coil_id,
                       const std::string& campaign_id, int seq, int n = 0) {
  static const char* kGrades[] = {"S235", "S355", "DP600", "API-X70"};
  CoilIn c;
  c.coil_id = coil_id;
  c.campaign_id = campaign_id;
  c.seq = seq;
  c.rolled_at = 1'770'000'000 + 120 * n;
  c.grade = kGrades[n % 4];
  for (int stand : {6, 7}) {
    PassIn p;
    p.stand = stand;
    p.force_kn = 15000 + 37.25 * (n % 97) + 1000 * (stand - 6);
    p.width_mm = 1000 + 3.5 * (n % 151);
    p.length_m = 600 + 1.7 * (n % 211) + 300 * (stand - 6);
    p.entry_thickness_mm = 5.0 - 1.2 * (stand - 6) + 0.01 * (n % 13);
    p.exit_thickness_mm = p.entry_thickness_mm * 0.78;
    p.temperature_c = 950 - 10 * (stand - 6);
    p.speed_mps = 8 + stand - 6;
    p.lubrication = n % 2 == 0;
    p.shift_mm = (n % 7) * 5.0 - 15;
    c.passes.push_back(p);
  }
  return c;
}

// Opens campaign "OPEN" (rolls of MakeRollChange, started 1.9e9) and adds
// `coils` coils to it, named prefix0, prefix1, ...: an open campaign whose
// rolls are re-predicted when the model changes. Fails the test (callers
// check HasFatalFailure) when a write is refused.
inline void OpenCampaignWithCoils(MillStore* store, const std::string& prefix,
                                  int coils) {
  ASSERT_TRUE(
      store->ApplyRollChange(MakeRollChange("OPEN", 1'900'000'000)).ok());
  for (int i = 0; i < coils; ++i) {
    ASSERT_TRUE(
        store->AddCoil(MakeCoil(prefix + std::to_string(i), "OPEN", i + 1, i))
            .ok());
  }
}

inline MeasurementIn MakeMeasurement(const std::string& campaign_id, int stand,
                                     Position p, const std::string& roll_id,
                                     double wear_um) {
  MeasurementIn m;
  m.campaign_id = campaign_id;
  m.stand = stand;
  m.position = p;
  m.roll_id = roll_id;
  m.measured_at = 1'780'000'000;
  m.wear_center_um = wear_um;
  return m;
}

inline double RelDiff(double a, double b) {
  return std::abs(a - b) / std::max({std::abs(a), std::abs(b), 1e-300});
}

inline void ExpectSameExtras(const ExtraColumns& a, const ExtraColumns& b,
                             const char* what) {
  SCOPED_TRACE(what);
  EXPECT_EQ(a.numeric_names, b.numeric_names);
  ASSERT_EQ(a.numeric.size(), b.numeric.size());
  for (size_t c = 0; c < a.numeric.size(); ++c) {
    ASSERT_EQ(a.numeric[c].size(), b.numeric[c].size());
    for (size_t r = 0; r < a.numeric[c].size(); ++r) {
      const double x = a.numeric[c][r], y = b.numeric[c][r];
      EXPECT_TRUE(x == y || (std::isnan(x) && std::isnan(y)))
          << a.numeric_names[c] << " row " << r << ": " << x << " vs " << y;
    }
  }
  EXPECT_EQ(a.factor_names, b.factor_names);
  EXPECT_EQ(a.factor, b.factor);
  EXPECT_EQ(a.factor_levels, b.factor_levels);
}

// Field-by-field equality of two datasets (labels, indices, numbers
// exactly, extra columns).
inline void ExpectSameDataset(const Dataset& a, const Dataset& b) {
  ASSERT_EQ(a.campaigns.size(), b.campaigns.size());
  for (size_t i = 0; i < a.campaigns.size(); ++i) {
    EXPECT_EQ(a.campaigns[i].id, b.campaigns[i].id) << i;
    EXPECT_EQ(a.campaigns[i].started_at, b.campaigns[i].started_at) << i;
    EXPECT_EQ(a.campaigns[i].ended_at, b.campaigns[i].ended_at) << i;
  }
  ASSERT_EQ(a.mounts.size(), b.mounts.size());
  for (size_t i = 0; i < a.mounts.size(); ++i) {
    const Mount &x = a.mounts[i], &y = b.mounts[i];
    EXPECT_EQ(x.campaign, y.campaign) << i;
    EXPECT_EQ(x.stand, y.stand) << i;
    EXPECT_EQ(x.position, y.position) << i;
    EXPECT_EQ(x.roll_id, y.roll_id) << i;
    EXPECT_EQ(x.roll_type, y.roll_type) << i;
    EXPECT_EQ(x.diameter_mm, y.diameter_mm) << i;
    EXPECT_EQ(x.hardness_hb, y.hardness_hb) << i;
  }
  ASSERT_EQ(a.passes.size(), b.passes.size());
  for (size_t i = 0; i < a.passes.size(); ++i) {
    const Pass &x = a.passes[i], &y = b.passes[i];
    EXPECT_EQ(x.campaign, y.campaign) << i;
    EXPECT_EQ(x.coil, y.coil) << i;
    EXPECT_EQ(x.seq, y.seq) << i;
    EXPECT_EQ(x.rolled_at, y.rolled_at) << i;
    EXPECT_EQ(x.grade, y.grade) << i;
    EXPECT_EQ(x.stand, y.stand) << i;
    EXPECT_EQ(x.force_kn, y.force_kn) << i;
    EXPECT_EQ(x.width_mm, y.width_mm) << i;
    EXPECT_EQ(x.length_m, y.length_m) << i;
    EXPECT_EQ(x.entry_thickness_mm, y.entry_thickness_mm) << i;
    EXPECT_EQ(x.exit_thickness_mm, y.exit_thickness_mm) << i;
    EXPECT_EQ(x.temperature_c, y.temperature_c) << i;
    EXPECT_EQ(x.speed_mps, y.speed_mps) << i;
    EXPECT_EQ(x.lubrication, y.lubrication) << i;
    EXPECT_EQ(x.shift_mm, y.shift_mm) << i;
  }
  ASSERT_EQ(a.measurements.size(), b.measurements.size());
  for (size_t i = 0; i < a.measurements.size(); ++i) {
    const Measurement &x = a.measurements[i], &y = b.measurements[i];
    EXPECT_EQ(x.campaign, y.campaign) << i;
    EXPECT_EQ(x.stand, y.stand) << i;
    EXPECT_EQ(x.position, y.position) << i;
    EXPECT_EQ(x.roll_id, y.roll_id) << i;
    EXPECT_EQ(x.measured_at, y.measured_at) << i;
    EXPECT_EQ(x.wear_center_um, y.wear_center_um) << i;
  }
  EXPECT_EQ(a.grades, b.grades);
  EXPECT_EQ(a.roll_types, b.roll_types);
  EXPECT_EQ(a.coil_ids, b.coil_ids);
  ExpectSameExtras(a.campaign_extra, b.campaign_extra, "campaign extras");
  ExpectSameExtras(a.mount_extra, b.mount_extra, "mount extras");
  ExpectSameExtras(a.pass_extra, b.pass_extra, "pass extras");
  ExpectSameExtras(a.measurement_extra, b.measurement_extra,
                   "measurement extras");
}

// The store's live wear of the open campaign equals the offline batch
// prediction (core PredictObservation on the exported data, active model
// over the data's levels) to `tol` relative.
void ExpectWearMatchesBatch(const MillStore& store, double tol = 1e-9);

// A simulated mill (core/sim/simulator.h): `campaigns` campaigns of `coils`
// coils with the named concealed effects; an empty dataset and a test
// failure when the simulator refuses.
Dataset SimulatedMill(uint64_t seed, int campaigns, int coils,
                      const std::vector<std::string>& effects = {});

}  // namespace testing
}  // namespace rollwear::storage

#endif  // ROLLWEAR_TESTS_STORAGE_STORE_TEST_UTIL_H_
