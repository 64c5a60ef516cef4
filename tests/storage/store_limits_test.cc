// Wear limits, remaining life and the forecast on a real SQLite file:
// limits set through the store survive a reopen and win over the
// configuration's; GET /v1/wear's remaining life follows the campaign's
// mix; a forecast equals posting the same coils (1e-9) and stores nothing.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "storage/schema.h"
#include "storage/sqlite_db.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage::testing {
namespace {

const PositionWear* Find(const WearSnapshot& s, int stand, Position p) {
  for (const PositionWear& w : s.positions) {
    if (w.stand == stand && w.position == p) return &w;
  }
  return nullptr;
}

TEST(StoreLimits, ConfigLimitsThenApiLimitWinsAndSurvivesReopen) {
  TempDir dir;
  StoreOptions options;
  options.wear_limit_um.fill(300);
  options.wear_limit_um[RollPositionSlot(7, Position::kBottom)] = 250;
  {
    auto store = OpenStore(dir.File("m.db"), options);
    ASSERT_NE(store, nullptr);
    std::vector<WearLimit> limits = store->WearLimits();
    ASSERT_EQ(limits.size(), 14u);
    EXPECT_EQ(limits[RollPositionSlot(7, Position::kBottom)].limit_um, 250);
    EXPECT_EQ(limits[RollPositionSlot(7, Position::kBottom)].source, "config");
    EXPECT_EQ(limits[0].limit_um, 300);

    WearLimitIn in{6, Position::kTop, 180.5, "ground last week"};
    StatusOr<WearLimit> set = store->SetWearLimit(in);
    ASSERT_TRUE(set.ok()) << set.status().ToString();
    EXPECT_EQ(set->source, "api");
    EXPECT_GT(set->set_at, 1'700'000'000);
    for (double bad : {0.0, -5.0, 5000.5, std::nan("")}) {
      in.limit_um = bad;
      const StatusOr<WearLimit> r = store->SetWearLimit(in);
      ASSERT_FALSE(r.ok()) << bad;
      EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
      EXPECT_EQ(r.status().message().rfind("limit_um: ", 0), 0u)
          << r.status().message();
    }
    EXPECT_EQ(store->WearLimits()[RollPositionSlot(6, Position::kTop)].limit_um,
              180.5);
  }
  // Reopened without any configured limit: the API's limit is still there.
  auto store = OpenStore(dir.File("m.db"));
  ASSERT_NE(store, nullptr);
  const WearLimit l = store->WearLimits()[RollPositionSlot(6, Position::kTop)];
  EXPECT_EQ(l.limit_um, 180.5);
  EXPECT_EQ(l.source, "api");
  EXPECT_EQ(l.reason, "ground last week");
  EXPECT_FALSE(store->WearLimits()[RollPositionSlot(7, Position::kTop)]
                   .limit_um.has_value());
}

// A version-4 file (before wear limits) is migrated on open: it gains the
// empty wear_limits table, and a limit set then is stored in it.
TEST(StoreLimits, VersionFourFileGainsTheTable) {
  TempDir dir;
  const std::string path = dir.File("v4.db");
  {
    StatusOr<std::unique_ptr<Db>> db = Db::Open(path);
    ASSERT_TRUE(db.ok()) << db.status().ToString();
    std::vector<Migration> upto4(SchemaMigrations().begin(),
                                 SchemaMigrations().begin() + 4);
    ASSERT_TRUE(MigrateSchema(db->get(), upto4).ok());
    StatusOr<int> version = ReadSchemaVersion(db->get());
    ASSERT_TRUE(version.ok());
    ASSERT_EQ(*version, 4);
  }
  {
    auto store = OpenStore(path);
    ASSERT_NE(store, nullptr);
    EXPECT_FALSE(store->WearLimits()[0].limit_um.has_value());
    ASSERT_TRUE(store->SetWearLimit({1, Position::kBottom, 42, "x"}).ok());
  }
  StatusOr<std::unique_ptr<Db>> db = Db::Open(path);
  ASSERT_TRUE(db.ok());
  StatusOr<int> version = ReadSchemaVersion(db->get());
  ASSERT_TRUE(version.ok());
  EXPECT_EQ(*version, kSchemaVersion);
  StatusOr<Statement> st = (*db)->Prepare(
      "SELECT stand || '/' || position || ' ' || limit_um || ' ' || reason "
      "FROM wear_limits");
  ASSERT_TRUE(st.ok());
  StatusOr<bool> row = st->Step();
  ASSERT_TRUE(row.ok() && *row);
  EXPECT_EQ(st->ColumnText(0), "F1/bottom 42.0 x");
}

TEST(StoreLimits, WearAnswersRemainingLifeAtTheCampaignsMix) {
  TempDir dir;
  StoreOptions options;
  options.wear_limit_um.fill(0);
  options.wear_limit_um[RollPositionSlot(6, Position::kTop)] = 400;
  auto store = OpenStore(dir.File("m.db"), options);
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1'769'990'000)).ok());
  // No coils yet: a limit but no remaining life.
  EXPECT_FALSE(
      Find(Mounted(*store).Wear(), 6, Position::kTop)->remaining.has_value());
  for (int i = 0; i < 40; ++i) {
    ASSERT_TRUE(
        store->AddCoil(MakeCoil("K" + std::to_string(i), "C1", i + 1, i)).ok());
  }
  const WearSnapshot s = Mounted(*store).Wear();
  const PositionWear* w = Find(s, 6, Position::kTop);
  ASSERT_NE(w, nullptr);
  ASSERT_EQ(w->wear_limit_um, 400);
  ASSERT_TRUE(w->remaining.has_value());
  ASSERT_LT(w->predicted_wear_um, 400);
  const double per_m = w->predicted_wear_um / w->rolled_length_m;
  EXPECT_NEAR(w->remaining->length_m, (400 - w->predicted_wear_um) / per_m,
              1e-9 * w->remaining->length_m);
  EXPECT_NEAR(w->remaining->coils,
              (400 - w->predicted_wear_um) / (w->predicted_wear_um / 40),
              1e-9 * w->remaining->coils);
  EXPECT_LE(w->remaining->length_lo_m, w->remaining->length_m);
  ASSERT_TRUE(w->remaining->length_hi_m.has_value());
  EXPECT_GE(*w->remaining->length_hi_m, w->remaining->length_m);
  // No limit at F7/top: null remaining life.
  const PositionWear* other = Find(s, 7, Position::kTop);
  EXPECT_FALSE(other->wear_limit_um.has_value());
  EXPECT_FALSE(other->remaining.has_value());
}

TEST(StoreForecast, EqualsPostingTheSameCoilsAndStoresNothing) {
  TempDir dir;
  StoreOptions options;
  options.wear_limit_um.fill(0);
  auto store = OpenStore(dir.File("m.db"), options);
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1'769'990'000)).ok());
  for (int i = 0; i < 10; ++i) {
    ASSERT_TRUE(
        store->AddCoil(MakeCoil("K" + std::to_string(i), "C1", i + 1, i)).ok());
  }
  std::vector<CoilIn> plan;
  for (int i = 10; i < 60; ++i) {
    plan.push_back(MakeCoil("K" + std::to_string(i), "C1", i + 1, i * 7));
  }
  // A limit the schedule crosses at F6/top: set it between two steps.
  StatusOr<Forecast> first = Mounted(*store).ForecastCoils(plan);
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  const double mid = first->positions[0].predicted_wear_um[24];
  const double before = first->positions[0].predicted_wear_um[23];
  ASSERT_TRUE(
      store->SetWearLimit({6, Position::kTop, 0.5 * (mid + before), ""}).ok());
  const StoreCounters counters = store->Counters();
  StatusOr<Forecast> f = Mounted(*store).ForecastCoils(plan);
  ASSERT_TRUE(f.ok()) << f.status().ToString();
  EXPECT_EQ(store->Counters().coils, counters.coils);
  ASSERT_EQ(f->positions.size(), 4u);
  EXPECT_EQ(f->positions[0].first_crossing, 24);
  for (size_t i = 1; i < 4; ++i) EXPECT_EQ(f->positions[i].first_crossing, -1);

  // Post the coils one by one; after each, every position's wear and
  // interval equal the forecast's at that step.
  for (size_t i = 0; i < plan.size(); ++i) {
    ASSERT_TRUE(store->AddCoil(plan[i]).ok());
    if (i % 7 != 6 && i + 1 != plan.size()) continue;
    const WearSnapshot s = Mounted(*store).Wear();
    ASSERT_EQ(s.positions.size(), f->positions.size());
    for (size_t p = 0; p < s.positions.size(); ++p) {
      const ForecastPosition& fp = f->positions[p];
      EXPECT_EQ(s.positions[p].roll_id, fp.roll_id);
      EXPECT_LE(
          RelDiff(s.positions[p].predicted_wear_um, fp.predicted_wear_um[i]),
          1e-9)
          << p << " " << i;
      EXPECT_LE(RelDiff(s.positions[p].interval_lo_um, fp.interval_um[i].first),
                1e-9);
      EXPECT_LE(
          RelDiff(s.positions[p].interval_hi_um, fp.interval_um[i].second),
          1e-9);
    }
  }
}

TEST(StoreForecast, RefusesWhatAddCoilRefusesNamingTheCoil) {
  TempDir dir;
  auto store = OpenStore(dir.File("m.db"));
  ASSERT_NE(store, nullptr);
  ASSERT_TRUE(store->ApplyRollChange(MakeRollChange("C1", 1'769'990'000)).ok());
  std::vector<CoilIn> plan = {MakeCoil("A", "C1", 1), MakeCoil("B", "C1", 2)};
  plan[1].passes[1].force_kn = -3;
  StatusOr<Forecast> f = Mounted(*store).ForecastCoils(plan);
  ASSERT_FALSE(f.ok());
  EXPECT_EQ(f.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(f.status().message().rfind("coils[1].passes[1].force_kn: ", 0), 0u)
      << f.status().message();

  plan[1] = MakeCoil("B", "C0", 2);  // not the running campaign
  f = Mounted(*store).ForecastCoils(plan);
  ASSERT_FALSE(f.ok());
  EXPECT_EQ(f.status().code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(f.status().message().rfind("coils[1].campaign_id: ", 0), 0u);

  plan[1] = MakeCoil("B", "C1", 2);
  plan[1].passes[0].stand = 3;  // no roll mounted at F3
  f = Mounted(*store).ForecastCoils(plan);
  ASSERT_FALSE(f.ok());
  EXPECT_EQ(f.status().code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(f.status().message().rfind("coils[1].passes[0]", 0), 0u)
      << f.status().message();

  // A stored coil is refused (posting it again would add nothing), so is a
  // coil planned twice; a stored seq may be planned again.
  ASSERT_TRUE(store->AddCoil(MakeCoil("A", "C1", 1)).ok());
  plan[1] = MakeCoil("B", "C1", 1);
  f = Mounted(*store).ForecastCoils(plan);
  ASSERT_FALSE(f.ok());
  EXPECT_EQ(f.status().code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(f.status().message().rfind("coils[0].coil_id: ", 0), 0u)
      << f.status().message();
  plan[0] = MakeCoil("A2", "C1", 1);
  EXPECT_TRUE(Mounted(*store).ForecastCoils(plan).ok());
  plan[1] = MakeCoil("A2", "C1", 2);
  f = Mounted(*store).ForecastCoils(plan);
  ASSERT_FALSE(f.ok());
  EXPECT_EQ(f.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(f.status().message().rfind("coils[1].coil_id: ", 0), 0u)
      << f.status().message();
}

}  // namespace
}  // namespace rollwear::storage::testing
