// Dataset reader on bad input: one test per rule of the format's bad-input
// section. Each starts from the valid tiny dataset (tests/data/tiny), breaks
// one thing, and checks the status code and the
// "<file>:<line>:<column> <field>: <rule>" message.
//
// Column numbers of the tiny files (1-based):
//   campaigns.csv    campaign_id 1, started_at 2, ended_at 3
//   mounts.csv       roll_id 1, campaign_id 2, position 3, stand 4,
//                    diameter_mm 5, hardness_hb 6, roll_type 7
//   coils.csv        campaign_id 1, coil_id 2, seq 3, rolled_at 4, grade 5,
//                    stand 6, force_kn 7, width_mm 8, length_m 9,
//                    entry_thickness_mm 10, exit_thickness_mm 11,
//                    temperature_c 12, speed_mps 13, lubrication 14,
//                    shift_mm 15, water_flow_m3h 16, operator_note 17
//   measurements.csv campaign_id 1, stand 2, position 3, roll_id 4,
//                    measured_at 5, wear_center_um 6
#include <unistd.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "core/dataset/dataset.h"
#include "core/dataset/dataset_io.h"
#include "tests/core/dataset_test_util.h"

namespace rollwear {
namespace {

using dataset_test::AppendLine;
using dataset_test::DatasetTexts;
using dataset_test::DropColumn;
using dataset_test::EraseLine;
using dataset_test::LineOf;
using dataset_test::ReadTexts;
using dataset_test::SetField;
using dataset_test::SetLine;
using dataset_test::TinyDir;
using dataset_test::TinyTexts;

// Expects `r` to be an kInvalidArgument error whose message contains every
// one of `pieces`.
void ExpectRejected(const StatusOr<Dataset>& r,
                    std::initializer_list<std::string> pieces) {
  ASSERT_FALSE(r.ok()) << "dataset was accepted";
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument)
      << r.status().ToString();
  for (const std::string& piece : pieces) {
    EXPECT_NE(r.status().message().find(piece), std::string::npos)
        << "message: " << r.status().message() << "\nmissing: " << piece;
  }
}

class DatasetRejects : public ::testing::Test {
 protected:
  void SetUp() override {
    t_ = TinyTexts();
    StatusOr<Dataset> r = ReadTexts(t_);
    ASSERT_TRUE(r.ok()) << r.status().ToString();
  }
  void Expect(std::initializer_list<std::string> pieces) {
    ExpectRejected(ReadTexts(t_), pieces);
  }
  void ExpectAccepted() {
    StatusOr<Dataset> r = ReadTexts(t_);
    EXPECT_TRUE(r.ok()) << r.status().ToString();
  }
  DatasetTexts t_;
};

TEST_F(DatasetRejects, MissingFile) {
  const std::string dir =
      (std::filesystem::temp_directory_path() /
       ("rollwear_missing_file_" + std::to_string(::getpid())))
          .string();
  std::filesystem::create_directories(dir);
  for (const char* f : {"campaigns.csv", "mounts.csv", "measurements.csv"}) {
    std::filesystem::copy_file(TinyDir() + "/" + f, dir + "/" + f);
  }
  StatusOr<Dataset> r = ReadDataset(dir);
  std::filesystem::remove_all(dir);
  ExpectRejected(r, {"coils.csv:0:0", "missing file"});

  std::istringstream c(t_.campaigns), m(t_.mounts), s(t_.measurements);
  ExpectRejected(ReadDatasetStreams({&c, &m, nullptr, &s}),
                 {"coils.csv:0:0", "missing file"});
}

TEST_F(DatasetRejects, MissingRequiredColumn) {
  DropColumn(&t_.coils, "force_kn");
  Expect({"coils.csv:1:0 force_kn: missing required column 'force_kn'"});
}

TEST_F(DatasetRejects, EmptyFileSaysItIsEmpty) {
  t_.campaigns = "";
  Expect(
      {"campaigns.csv:1:1 file: the file is empty; want a header row "
       "(campaign_id,started_at,ended_at)"});
  t_ = TinyTexts();
  t_.measurements = "\n\n";
  Expect({"measurements.csv:1:1 file: the file is empty"});
}

// A European spreadsheet export: ';' between fields, decimal commas.
std::string AsSpreadsheetExport(std::string text) {
  for (char& c : text) {
    if (c == ',') {
      c = ';';
    } else if (c == '.') {
      c = ',';
    }
  }
  return text;
}

TEST_F(DatasetRejects, SpreadsheetExportIsNamed) {
  t_.mounts = AsSpreadsheetExport(t_.mounts);
  Expect(
      {"mounts.csv:1:1 file: looks like a spreadsheet export with ';' and "
       "decimal commas: export as CSV with ',' and '.'"});
  // Without a decimal in the file, only the separator is named.
  t_ = TinyTexts();
  t_.campaigns = AsSpreadsheetExport(t_.campaigns);
  Expect(
      {"campaigns.csv:1:1 file: looks like a spreadsheet export with ';': "
       "export as CSV with ',' and '.'"});
}

TEST_F(DatasetRejects, DecimalCommaIsNamed) {
  SetField(&t_.coils, 2, "width_mm", "\"1250,5\"");
  Expect(
      {"coils.csv:2:8 width_mm: unparsable number '1250,5': decimal comma; "
       "write numbers with '.'"});
}

TEST_F(DatasetRejects, DuplicateColumnName) {
  SetField(&t_.coils, 1, "water_flow_m3h", "force_kn");
  Expect({"coils.csv:1:16 force_kn: duplicate column name"});
}

TEST_F(DatasetRejects, WrongFieldCount) {
  const std::string line3 = LineOf(t_.coils, 3);
  SetLine(&t_.coils, 3, line3 + ",surplus");
  Expect({"coils.csv:3:18 (extra field): wrong field count", "18 fields",
          "header has 17"});
  SetLine(&t_.coils, 3, line3.substr(0, line3.rfind(',')));
  Expect({"coils.csv:3:17 operator_note: wrong field count", "16 fields"});
}

TEST_F(DatasetRejects, EmptyRequiredField) {
  SetField(&t_.coils, 3, "grade", "");
  Expect({"coils.csv:3:5 grade: required field is empty"});
  t_ = TinyTexts();
  SetField(&t_.mounts, 4, "diameter_mm", " ");
  Expect({"mounts.csv:4:5 diameter_mm: required field is empty"});
}

TEST_F(DatasetRejects, UnparsableNumber) {
  SetField(&t_.coils, 6, "width_mm", "14O0");
  Expect({"coils.csv:6:8 width_mm: unparsable number '14O0'"});
  t_ = TinyTexts();
  SetField(&t_.measurements, 2, "wear_center_um", "152,4");  // unquoted
  Expect({"measurements.csv:2:", "wrong field count"});
  t_ = TinyTexts();
  SetField(&t_.measurements, 2, "wear_center_um", "\"152,4\"");
  Expect({"measurements.csv:2:6 wear_center_um: unparsable number"});
}

TEST_F(DatasetRejects, UnparsableInteger) {
  SetField(&t_.coils, 5, "seq", "2.0");
  Expect({"coils.csv:5:3 seq: unparsable integer '2.0'"});
}

TEST_F(DatasetRejects, UnparsableTimestamp) {
  SetField(&t_.coils, 2, "rolled_at", "2026-03-01T06:10:00");  // no offset
  Expect({"coils.csv:2:4 rolled_at: unparsable timestamp"});
  t_ = TinyTexts();
  SetField(&t_.campaigns, 3, "started_at", "2026-03-01 15:00:00+01:00");
  Expect({"campaigns.csv:3:2 started_at: unparsable timestamp"});
  t_ = TinyTexts();
  SetField(&t_.measurements, 7, "measured_at", "yesterday");
  Expect({"measurements.csv:7:5 measured_at: unparsable timestamp"});
}

// force_kn, width_mm, length_m, entry/exit thickness, speed_mps,
// diameter_mm and hardness_hb must be > 0.
struct PositiveCase {
  const char* name;
  const char* file;  // "coils" or "mounts"
  int line;
  const char* column;
  const char* value;
  const char* expected;
};

class DatasetRejectsNonPositive
    : public DatasetRejects,
      public ::testing::WithParamInterface<PositiveCase> {};

TEST_P(DatasetRejectsNonPositive, MustBeGreaterThanZero) {
  const PositiveCase& c = GetParam();
  std::string* text = std::string(c.file) == "coils" ? &t_.coils : &t_.mounts;
  SetField(text, c.line, c.column, c.value);
  Expect({c.expected, "must be > 0"});
}

INSTANTIATE_TEST_SUITE_P(
    Dataset, DatasetRejectsNonPositive,
    ::testing::Values(PositiveCase{"force", "coils", 2, "force_kn", "0",
                                   "coils.csv:2:7 force_kn:"},
                      PositiveCase{"width", "coils", 3, "width_mm", "-1250",
                                   "coils.csv:3:8 width_mm:"},
                      PositiveCase{"length", "coils", 4, "length_m", "0.0",
                                   "coils.csv:4:9 length_m:"},
                      PositiveCase{"entry", "coils", 5, "entry_thickness_mm",
                                   "-4.8",
                                   "coils.csv:5:10 entry_thickness_mm:"},
                      PositiveCase{"exit", "coils", 6, "exit_thickness_mm", "0",
                                   "coils.csv:6:11 exit_thickness_mm:"},
                      PositiveCase{"speed", "coils", 7, "speed_mps", "-0",
                                   "coils.csv:7:13 speed_mps:"},
                      PositiveCase{"diameter", "mounts", 3, "diameter_mm", "0",
                                   "mounts.csv:3:5 diameter_mm:"},
                      PositiveCase{"hardness", "mounts", 9, "hardness_hb",
                                   "-541", "mounts.csv:9:6 hardness_hb:"}),
    [](const ::testing::TestParamInfo<PositiveCase>& info) {
      return std::string(info.param.name);
    });

TEST_F(DatasetRejects, ExitNotBelowEntry) {
  SetField(&t_.coils, 4, "exit_thickness_mm", "5.5");  // == entry
  Expect({"coils.csv:4:11 exit_thickness_mm: must be < entry_thickness_mm"});
  t_ = TinyTexts();
  SetField(&t_.coils, 9, "exit_thickness_mm", "3.01");  // > entry 3
  Expect({"coils.csv:9:11 exit_thickness_mm: must be < entry_thickness_mm"});
}

TEST_F(DatasetRejects, SeqBelowOne) {
  SetField(&t_.coils, 2, "seq", "0");
  Expect({"coils.csv:2:3 seq: must be an integer >= 1"});
  t_ = TinyTexts();
  SetField(&t_.coils, 8, "seq", "-1");
  Expect({"coils.csv:8:3 seq: must be an integer >= 1"});
}

TEST_F(DatasetRejects, LubricationNotZeroOrOne) {
  for (const char* bad : {"2", "yes", "1.0", "-1", "true"}) {
    t_ = TinyTexts();
    SetField(&t_.coils, 7, "lubrication", bad);
    SCOPED_TRACE(bad);
    Expect({"coils.csv:7:14 lubrication: must be 0 or 1"});
  }
}

// A finite reading below the gauge's noise is read and flagged as suspect
// (data_quality_test.cc), not refused; only a non-number is refused.
TEST_F(DatasetRejects, WearBelowGrinderNoiseIsReadForTheQualityCheck) {
  SetField(&t_.measurements, 5, "wear_center_um", "-50");
  ExpectAccepted();
  SetField(&t_.measurements, 5, "wear_center_um", "-62.6");
  ExpectAccepted();
  SetField(&t_.measurements, 5, "wear_center_um", "-inf");
  Expect({"measurements.csv:5:6 wear_center_um: must be a finite number"});
}

TEST_F(DatasetRejects, NanAndInfinityEverywhere) {
  struct Case {
    std::string* text;
    int line;
    const char* column;
    const char* value;
    const char* expected;
  };
  const Case cases[] = {
      {&t_.coils, 2, "temperature_c", "nan", "coils.csv:2:12 temperature_c:"},
      {&t_.coils, 3, "shift_mm", "inf", "coils.csv:3:15 shift_mm:"},
      {&t_.coils, 4, "force_kn", "-inf", "coils.csv:4:7 force_kn:"},
      {&t_.coils, 5, "length_m", "Infinity", "coils.csv:5:9 length_m:"},
      {&t_.mounts, 2, "diameter_mm", "NaN", "mounts.csv:2:5 diameter_mm:"},
      {&t_.measurements, 3, "wear_center_um", "inf",
       "measurements.csv:3:6 wear_center_um:"},
  };
  for (const Case& c : cases) {
    const DatasetTexts saved = t_;
    SetField(c.text, c.line, c.column, c.value);
    SCOPED_TRACE(c.expected);
    Expect({c.expected, "must be a finite number"});
    t_ = saved;
  }
  SetField(&t_.coils, 6, "width_mm", "1e999");
  Expect({"coils.csv:6:8 width_mm: number out of range"});
}

TEST_F(DatasetRejects, UnknownStand) {
  SetField(&t_.coils, 2, "stand", "F8");
  Expect({"coils.csv:2:6 stand: unknown stand 'F8'"});
  t_ = TinyTexts();
  SetField(&t_.mounts, 5, "stand", "F0");
  Expect({"mounts.csv:5:4 stand: unknown stand"});
  t_ = TinyTexts();
  SetField(&t_.measurements, 4, "stand", "f7");
  Expect({"measurements.csv:4:2 stand: unknown stand"});
}

TEST_F(DatasetRejects, UnknownPosition) {
  SetField(&t_.mounts, 2, "position", "middle");
  Expect({"mounts.csv:2:3 position: unknown position 'middle'"});
  t_ = TinyTexts();
  SetField(&t_.measurements, 6, "position", "Top");
  Expect({"measurements.csv:6:3 position: unknown position"});
}

TEST_F(DatasetRejects, DuplicateCampaignId) {
  AppendLine(&t_.campaigns, "C1,2026-03-05T06:00:00Z,2026-03-05T14:00:00Z");
  Expect(
      {"campaigns.csv:4:1 campaign_id: duplicate campaign_id 'C1'", "line 2"});
}

TEST_F(DatasetRejects, EndedBeforeStarted) {
  // C2 starts 2026-03-01T14:00:00Z; ending at the same instant is fine.
  SetField(&t_.campaigns, 3, "ended_at", "2026-03-01T14:00:00Z");
  ExpectAccepted();
  SetField(&t_.campaigns, 3, "ended_at", "2026-03-01T14:59:59+01:00");
  Expect(
      {"campaigns.csv:3:3 ended_at: must not be before started_at "
       "(2026-03-01T14:00:00Z), got '2026-03-01T14:59:59+01:00'"});
}

TEST_F(DatasetRejects, UnknownCampaign) {
  SetField(&t_.mounts, 4, "campaign_id", "C9");
  Expect({"mounts.csv:4:2 campaign_id: unknown campaign 'C9'"});
  t_ = TinyTexts();
  SetField(&t_.coils, 8, "campaign_id", "C3");
  Expect({"coils.csv:8:1 campaign_id: unknown campaign 'C3'"});
  t_ = TinyTexts();
  SetField(&t_.measurements, 7, "campaign_id", "c2");
  Expect({"measurements.csv:7:1 campaign_id: unknown campaign 'c2'"});
}

TEST_F(DatasetRejects, DuplicateMountKey) {
  AppendLine(&t_.mounts, "R999,C1,top,F6,700,520,ICDP-S3");
  Expect(
      {"mounts.csv:10:2 campaign_id: duplicate key (campaign_id, stand, "
       "position)",
       "F6/top", "line 2"});
}

TEST_F(DatasetRejects, DuplicateCoilKey) {
  AppendLine(&t_.coils, LineOf(t_.coils, 4));
  Expect({"coils.csv:12:2 coil_id: duplicate key (coil_id, stand)", "K1003",
          "line 4"});
}

TEST_F(DatasetRejects, DuplicateMeasurementKey) {
  AppendLine(&t_.measurements, LineOf(t_.measurements, 3));
  Expect(
      {"measurements.csv:8:1 campaign_id: duplicate key (campaign_id, "
       "stand, position)",
       "F6/bottom", "line 3"});
}

TEST_F(DatasetRejects, CoilDisagreesAcrossStands) {
  SetField(&t_.coils, 3, "campaign_id", "C2");
  Expect({"coils.csv:3:1 campaign_id: coil has campaign_id 'C1' on line 2"});
  t_ = TinyTexts();
  SetField(&t_.coils, 3, "seq", "4");
  Expect({"coils.csv:3:3 seq: coil has seq 1 on line 2"});
  t_ = TinyTexts();
  SetField(&t_.coils, 11, "grade", "S235");
  Expect({"coils.csv:11:5 grade: coil has grade 'DP600' on line 10"});
}

TEST_F(DatasetRejects, SeqUsedByAnotherCoil) {
  AppendLine(&t_.coils,
             "C1,K1009,2,2026-03-01T06:40:00Z,S235,F6,18000,1250,800,4,3,950,"
             "8.5,1,0,120,normal");
  Expect(
      {"coils.csv:12:3 seq: seq 2 of campaign 'C1' is already used by "
       "coil_id 'K1002'"});
}

TEST_F(DatasetRejects, MeasurementWithoutMount) {
  EraseLine(&t_.mounts, 6);  // R603,C2,top,F6
  Expect({"measurements.csv:6:2 stand: no mount for F6/top of campaign 'C2'"});
}

TEST_F(DatasetRejects, MeasurementRollIdMismatch) {
  SetField(&t_.measurements, 3, "roll_id", "R699");
  Expect({"measurements.csv:3:4 roll_id: roll_id must match mounts.csv",
          "'R602'"});
}

// mounts.csv and measurements.csv name F5 where coils.csv names F7.
TEST_F(DatasetRejects, PassAtStandWithoutMountedRoll) {
  SetField(&t_.mounts, 4, "stand", "F5");  // R701,C1,top
  SetField(&t_.mounts, 5, "stand", "F5");  // R702,C1,bottom
  SetField(&t_.measurements, 4, "stand", "F5");
  SetField(&t_.measurements, 5, "stand", "F5");
  Expect(
      {"coils.csv:3:6 stand: no roll mounted at F7 in campaign C1; its "
       "rolls are at F5/top, F5/bottom, F6/top, F6/bottom"});
}

TEST_F(DatasetRejects, OneRollAtTheStandIsEnough) {
  EraseLine(&t_.mounts, 5);        // R702,C1,bottom,F7
  EraseLine(&t_.measurements, 5);  // its measurement
  ExpectAccepted();
  EraseLine(&t_.mounts, 4);  // R701,C1,top,F7: now none at F7
  EraseLine(&t_.measurements, 4);
  Expect({"coils.csv:3:6 stand: no roll mounted at F7 in campaign C1"});
}

TEST_F(DatasetRejects, MeasurementBeforeCampaignEnd) {
  // C1 ended at 2026-03-01T14:00:00Z; measured at its end is fine.
  SetField(&t_.measurements, 2, "measured_at", "2026-03-01T15:00:00+01:00");
  ExpectAccepted();
  SetField(&t_.measurements, 2, "measured_at", "2023-03-01T13:59:59Z");
  Expect(
      {"measurements.csv:2:5 measured_at: must not be before the end of "
       "campaign C1 (2026-03-01T14:00:00Z): a roll is measured after it "
       "is taken out, got '2023-03-01T13:59:59Z'"});
}

TEST_F(DatasetRejects, MalformedQuoting) {
  SetField(&t_.coils, 11, "operator_note", "\"night shift");
  Expect({"coils.csv:11:17 operator_note: unterminated quoted field"});
  t_ = TinyTexts();
  SetField(&t_.coils, 9, "grade", "\"DP\"600");
  Expect({"coils.csv:9:5 grade: unexpected character after closing quote"});
}

TEST_F(DatasetRejects, FirstErrorWinsAndNothingIsReturned) {
  SetField(&t_.mounts, 3, "stand", "F9");
  SetField(&t_.coils, 2, "force_kn", "-1");
  StatusOr<Dataset> r = ReadTexts(t_);
  ExpectRejected(r, {"mounts.csv:3:4 stand:"});
  EXPECT_EQ(r.status().message().find("coils.csv"), std::string::npos);
}

}  // namespace
}  // namespace rollwear
