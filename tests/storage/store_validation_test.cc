// Every rule of api.md / data-format.md a write must pass: the error code,
// the message naming the field, and that a rejected write changed nothing.
#include <functional>
#include <limits>

#include <gtest/gtest.h>

#include "engine/calibration_runs.h"
#include "storage/mill_store.h"
#include "tests/storage/store_test_util.h"

namespace rollwear::storage {
namespace {

using testing::MakeCoil;
using testing::MakeMeasurement;
using testing::MakeRollChange;
using testing::Mounted;
using testing::OpenStore;
using testing::TempDir;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

struct Case {
  const char* name;
  std::function<Status(MillStore*)> write;
  StatusCode code;
  const char* message_prefix;  // the message starts with this
};

template <typename T>
Status StatusOf(const StatusOr<T>& s) {
  return s.status();
}

Status RollChange(MillStore* s,
                  const std::function<void(RollChangeIn*)>& edit) {
  RollChangeIn in = MakeRollChange("C2", 2000, "n");
  edit(&in);
  return s->ApplyRollChange(in).status();
}

Status Coil(MillStore* s, const std::function<void(CoilIn*)>& edit) {
  CoilIn in = MakeCoil("KX", "C1", 99, 3);
  edit(&in);
  return s->AddCoil(in).status();
}

Status Measure(MillStore* s, const std::function<void(MeasurementIn*)>& edit) {
  MeasurementIn in = MakeMeasurement("C0", 6, Position::kTop, "R6T0", 100);
  edit(&in);
  return s->AddMeasurement(in).status();
}

class StoreValidationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = OpenStore(dir_.File("mill.db"));
    ASSERT_NE(store_, nullptr);
    // C0 (ended by C1's roll change, measurable), C1 open with two coils.
    ASSERT_TRUE(store_->ApplyRollChange(MakeRollChange("C0", 500, "0")).ok());
    ASSERT_TRUE(store_->ApplyRollChange(MakeRollChange("C1", 1000)).ok());
    ASSERT_TRUE(store_->AddCoil(MakeCoil("K1", "C1", 1, 1)).ok());
    ASSERT_TRUE(store_->AddCoil(MakeCoil("K2", "C1", 2, 2)).ok());
  }

  void Check(const Case& c) {
    SCOPED_TRACE(c.name);
    const StoreCounters before = store_->Counters();
    const WearSnapshot wear_before = Mounted(*store_).Wear();
    StatusOr<Dataset> data_before = store_->ExportDataset();
    ASSERT_TRUE(data_before.ok());

    const Status s = c.write(store_.get());
    EXPECT_EQ(s.code(), c.code) << s.ToString();
    EXPECT_EQ(s.message().rfind(c.message_prefix, 0), 0u)
        << "message: " << s.message() << "\nwant prefix: " << c.message_prefix;

    const StoreCounters after = store_->Counters();
    EXPECT_EQ(after.coils, before.coils);
    EXPECT_EQ(after.campaigns, before.campaigns);
    EXPECT_EQ(after.measurements, before.measurements);
    EXPECT_EQ(after.commits, before.commits);  // nothing was written
    const WearSnapshot wear_after = Mounted(*store_).Wear();
    ASSERT_EQ(wear_after.positions.size(), wear_before.positions.size());
    for (size_t i = 0; i < wear_after.positions.size(); ++i) {
      EXPECT_EQ(wear_after.positions[i].predicted_wear_um,
                wear_before.positions[i].predicted_wear_um);
      EXPECT_EQ(wear_after.positions[i].coils, wear_before.positions[i].coils);
    }
    StatusOr<Dataset> data_after = store_->ExportDataset();
    ASSERT_TRUE(data_after.ok());
    testing::ExpectSameDataset(*data_before, *data_after);
  }

  TempDir dir_;
  std::unique_ptr<MillStore> store_;
};

TEST_F(StoreValidationTest, RollChangeRules) {
  const Case cases[] = {
      {"empty id",
       [](MillStore* s) {
         return RollChange(s, [](RollChangeIn* in) { in->campaign_id = ""; });
       },
       StatusCode::kInvalidArgument, "campaign_id: must not be empty"},
      {"no rolls",
       [](MillStore* s) {
         return RollChange(s, [](RollChangeIn* in) { in->rolls.clear(); });
       },
       StatusCode::kInvalidArgument, "rolls: must not be empty"},
      {"stand",
       [](MillStore* s) {
         return RollChange(s, [](RollChangeIn* in) { in->rolls[1].stand = 9; });
       },
       StatusCode::kInvalidArgument, "rolls[1].stand: unknown stand 9"},
      {"diameter",
       [](MillStore* s) {
         return RollChange(
             s, [](RollChangeIn* in) { in->rolls[2].diameter_mm = 0; });
       },
       StatusCode::kInvalidArgument, "rolls[2].diameter_mm: must be > 0"},
      {"hardness",
       [](MillStore* s) {
         return RollChange(
             s, [](RollChangeIn* in) { in->rolls[0].hardness_hb = kNaN; });
       },
       StatusCode::kInvalidArgument, "rolls[0].hardness_hb: must be > 0"},
      {"roll id",
       [](MillStore* s) {
         return RollChange(s,
                           [](RollChangeIn* in) { in->rolls[3].roll_id = ""; });
       },
       StatusCode::kInvalidArgument, "rolls[3].roll_id: must not be empty"},
      {"roll type",
       [](MillStore* s) {
         return RollChange(
             s, [](RollChangeIn* in) { in->rolls[0].roll_type = ""; });
       },
       StatusCode::kInvalidArgument, "rolls[0].roll_type: must not be empty"},
      {"duplicate position",
       [](MillStore* s) {
         return RollChange(s, [](RollChangeIn* in) {
           in->rolls[3].stand = 6;
           in->rolls[3].position = Position::kTop;
         });
       },
       StatusCode::kInvalidArgument,
       "rolls[3].stand: duplicate roll position F6/top (also rolls[0])"},
      {"before open start",
       [](MillStore* s) {
         return RollChange(s, [](RollChangeIn* in) { in->started_at = 999; });
       },
       StatusCode::kFailedPrecondition, "started_at: "},
  };
  for (const Case& c : cases) Check(c);
}

TEST_F(StoreValidationTest, EndCampaignRules) {
  const Case cases[] = {
      {"empty id", [](MillStore* s) { return StatusOf(s->EndCampaign("", 5)); },
       StatusCode::kInvalidArgument, "campaign_id: must not be empty"},
      {"unknown",
       [](MillStore* s) { return StatusOf(s->EndCampaign("C9", 5000)); },
       StatusCode::kNotFound, "campaign_id: unknown campaign C9"},
      {"before start",
       [](MillStore* s) { return StatusOf(s->EndCampaign("C1", 999)); },
       StatusCode::kInvalidArgument, "ended_at: must not be before started_at"},
  };
  for (const Case& c : cases) Check(c);
}

TEST_F(StoreValidationTest, CoilRules) {
  const Case cases[] = {
      {"coil id",
       [](MillStore* s) {
         return Coil(s, [](CoilIn* in) { in->coil_id = ""; });
       },
       StatusCode::kInvalidArgument, "coil_id: must not be empty"},
      {"campaign id",
       [](MillStore* s) {
         return Coil(s, [](CoilIn* in) { in->campaign_id = ""; });
       },
       StatusCode::kInvalidArgument, "campaign_id: must not be empty"},
      {"seq",
       [](MillStore* s) { return Coil(s, [](CoilIn* in) { in->seq = 0; }); },
       StatusCode::kInvalidArgument, "seq: must be an integer >= 1"},
      {"grade",
       [](MillStore* s) { return Coil(s, [](CoilIn* in) { in->grade = ""; }); },
       StatusCode::kInvalidArgument, "grade: must not be empty"},
      {"no passes",
       [](MillStore* s) {
         return Coil(s, [](CoilIn* in) { in->passes.clear(); });
       },
       StatusCode::kInvalidArgument, "passes: must not be empty"},
      {"force",
       [](MillStore* s) {
         return Coil(s, [](CoilIn* in) { in->passes[1].force_kn = -3; });
       },
       StatusCode::kInvalidArgument, "passes[1].force_kn: must be > 0, got -3"},
      {"exit >= entry",
       [](MillStore* s) {
         return Coil(s, [](CoilIn* in) {
           in->passes[0].exit_thickness_mm = in->passes[0].entry_thickness_mm;
         });
       },
       StatusCode::kInvalidArgument,
       "passes[0].exit_thickness_mm: must be < entry_thickness_mm"},
      {"width",
       [](MillStore* s) {
         return Coil(s, [](CoilIn* in) { in->passes[0].width_mm = 0; });
       },
       StatusCode::kInvalidArgument, "passes[0].width_mm: must be > 0"},
      {"length",
       [](MillStore* s) {
         return Coil(s, [](CoilIn* in) { in->passes[1].length_m = kInf; });
       },
       StatusCode::kInvalidArgument, "passes[1].length_m: must be > 0"},
      {"entry",
       [](MillStore* s) {
         return Coil(s,
                     [](CoilIn* in) { in->passes[1].entry_thickness_mm = -1; });
       },
       StatusCode::kInvalidArgument,
       "passes[1].entry_thickness_mm: must be > 0"},
      {"speed",
       [](MillStore* s) {
         return Coil(s, [](CoilIn* in) { in->passes[0].speed_mps = 0; });
       },
       StatusCode::kInvalidArgument, "passes[0].speed_mps: must be > 0"},
      {"temperature",
       [](MillStore* s) {
         return Coil(s, [](CoilIn* in) { in->passes[0].temperature_c = kNaN; });
       },
       StatusCode::kInvalidArgument,
       "passes[0].temperature_c: must be a finite number"},
      {"shift",
       [](MillStore* s) {
         return Coil(s, [](CoilIn* in) { in->passes[1].shift_mm = -kInf; });
       },
       StatusCode::kInvalidArgument,
       "passes[1].shift_mm: must be a finite number"},
      {"stand",
       [](MillStore* s) {
         return Coil(s, [](CoilIn* in) { in->passes[1].stand = 8; });
       },
       StatusCode::kInvalidArgument, "passes[1].stand: unknown stand 8"},
      {"duplicate stand",
       [](MillStore* s) {
         return Coil(s, [](CoilIn* in) { in->passes[1].stand = 6; });
       },
       StatusCode::kInvalidArgument,
       "passes[1].stand: duplicate stand F6 (also passes[0])"},
      {"unknown campaign",
       [](MillStore* s) {
         return Coil(s, [](CoilIn* in) { in->campaign_id = "C9"; });
       },
       StatusCode::kNotFound, "campaign_id: unknown campaign C9"},
      {"ended campaign",
       [](MillStore* s) {
         return Coil(s, [](CoilIn* in) { in->campaign_id = "C0"; });
       },
       StatusCode::kFailedPrecondition, "campaign_id: campaign C0 has ended"},
      {"no roll at stand",
       [](MillStore* s) {
         return Coil(s, [](CoilIn* in) {
           PassIn p = in->passes[0];
           p.stand = 5;
           in->passes.push_back(p);
         });
       },
       StatusCode::kFailedPrecondition,
       "passes[2].stand: no roll mounted at F5 in campaign C1; its rolls are "
       "at F6/top, F6/bottom, F7/top, F7/bottom"},
      {"seq taken",
       [](MillStore* s) { return Coil(s, [](CoilIn* in) { in->seq = 2; }); },
       StatusCode::kFailedPrecondition,
       "seq: seq 2 of campaign C1 is already used by coil K2"},
  };
  for (const Case& c : cases) Check(c);
}

TEST_F(StoreValidationTest, MeasurementRules) {
  const Case cases[] = {
      {"campaign id",
       [](MillStore* s) {
         return Measure(s, [](MeasurementIn* in) { in->campaign_id = ""; });
       },
       StatusCode::kInvalidArgument, "campaign_id: must not be empty"},
      {"stand",
       [](MillStore* s) {
         return Measure(s, [](MeasurementIn* in) { in->stand = 0; });
       },
       StatusCode::kInvalidArgument, "stand: unknown stand 0"},
      {"roll id",
       [](MillStore* s) {
         return Measure(s, [](MeasurementIn* in) { in->roll_id = ""; });
       },
       StatusCode::kInvalidArgument, "roll_id: must not be empty"},
      {"wear nan",
       [](MillStore* s) {
         return Measure(s,
                        [](MeasurementIn* in) { in->wear_center_um = kNaN; });
       },
       StatusCode::kInvalidArgument, "wear_center_um: must be a finite number"},
      {"unknown campaign",
       [](MillStore* s) {
         return Measure(s, [](MeasurementIn* in) { in->campaign_id = "C9"; });
       },
       StatusCode::kNotFound, "campaign_id: unknown campaign C9"},
      {"no roll there",
       [](MillStore* s) {
         return Measure(s, [](MeasurementIn* in) { in->stand = 5; });
       },
       StatusCode::kFailedPrecondition,
       "stand: no roll mounted at F5/top in campaign C0"},
      {"other roll",
       [](MillStore* s) {
         return Measure(s, [](MeasurementIn* in) { in->roll_id = "R6B0"; });
       },
       StatusCode::kFailedPrecondition,
       "roll_id: roll R6B0 was not mounted at F6/top in campaign C0 (mounted: "
       "R6T0)"},
      {"campaign still running",
       [](MillStore* s) {
         return Measure(s, [](MeasurementIn* in) {
           in->campaign_id = "C1";
           in->roll_id = "R6T";
         });
       },
       StatusCode::kFailedPrecondition,
       "campaign_id: campaign C1 has not ended: a roll is measured after its "
       "campaign (end it first)"},
      {"before the campaign ended",  // C0 ended at 1000 (C1's roll change)
       [](MillStore* s) {
         return Measure(s, [](MeasurementIn* in) { in->measured_at = 999; });
       },
       StatusCode::kFailedPrecondition,
       "measured_at: must not be before the end of campaign C0 "
       "(1970-01-01T00:16:40Z): a roll is measured after it is taken out, got "
       "1970-01-01T00:16:39Z"},
  };
  for (const Case& c : cases) Check(c);
}

TEST_F(StoreValidationTest, WearAtRules) {
  EXPECT_EQ(Mounted(*store_).WearAt(0, Position::kTop).status().code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(Mounted(*store_).WearAt(5, Position::kTop).status().code(),
            StatusCode::kNotFound);
  EXPECT_TRUE(Mounted(*store_).WearAt(6, Position::kTop).ok());
}

TEST_F(StoreValidationTest, CalibrationRequestRules) {
  StatusOr<int64_t> id = store_->EnqueueCalibration("api", WearLaw::kWang, 4);
  EXPECT_EQ(id.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(id.status().message().rfind("option: must be 1, 2 or 3", 0), 0u);
  EXPECT_EQ(store_->GetCalibration(12345).status().code(),
            StatusCode::kNotFound);
  EXPECT_EQ(engine::CalibrationRuns(&*store_).Run(12345).code(),
            StatusCode::kNotFound);
}

}  // namespace
}  // namespace rollwear::storage
