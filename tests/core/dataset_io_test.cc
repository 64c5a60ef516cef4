// Dataset reader/writer on valid input: the checked-in tiny dataset field by
// field, derived quantities and the index, CSV dialect details, round trip,
// timestamps and a ~100k-row synthetic dataset. Bad input is covered in
// dataset_validation_test.cc.
#include "core/dataset/dataset_io.h"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "core/base/csv.h"
#include "core/dataset/dataset.h"
#include "tests/core/dataset_test_util.h"

namespace rollwear {
namespace {

using dataset_test::AppendLine;
using dataset_test::DatasetTexts;
using dataset_test::ExpectSameDataset;
using dataset_test::ReadText;
using dataset_test::ReadTexts;
using dataset_test::SetLine;
using dataset_test::TinyDir;
using dataset_test::TinyTexts;

constexpr UnixSeconds k20260301 = 1772323200;  // 2026-03-01T00:00:00Z
constexpr UnixSeconds kHour = 3600;

// A fresh directory under the system temp dir, removed at scope exit.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = (std::filesystem::temp_directory_path() /
             ("rollwear_" + std::string(info->name()) + "_" +
              std::to_string(::getpid())))
                .string();
    std::filesystem::remove_all(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

TEST(DatasetNames, StandsPositionsAndInterning) {
  EXPECT_EQ(RollPositionName(6, Position::kTop), "F6/top");
  EXPECT_EQ(RollPositionName(7, Position::kBottom), "F7/bottom");
  EXPECT_STREQ(PositionName(Position::kBottom), "bottom");
  EXPECT_EQ(ParseStand("F1"), 1);
  EXPECT_EQ(ParseStand("F7"), 7);
  for (const char* bad : {"F0", "F8", "f6", "F", "F66", "6", "", " F6"}) {
    EXPECT_EQ(ParseStand(bad), 0) << bad;
  }
  Position p = Position::kTop;
  EXPECT_TRUE(ParsePosition("bottom", &p));
  EXPECT_EQ(p, Position::kBottom);
  EXPECT_TRUE(ParsePosition("top", &p));
  EXPECT_EQ(p, Position::kTop);
  EXPECT_FALSE(ParsePosition("Top", &p));
  EXPECT_FALSE(ParsePosition("middle", &p));
  EXPECT_EQ(RollPositionSlot(6, Position::kBottom), 11);
  EXPECT_EQ(SlotStand(11), 6);
  EXPECT_EQ(SlotPosition(11), Position::kBottom);

  std::vector<std::string> table;
  EXPECT_EQ(Dataset::Intern(&table, "S235"), 0);
  EXPECT_EQ(Dataset::Intern(&table, "S355"), 1);
  EXPECT_EQ(Dataset::Intern(&table, "S235"), 0);
  EXPECT_EQ(table, (std::vector<std::string>{"S235", "S355"}));
}

TEST(DatasetRead, TinyDatasetFieldByField) {
  StatusOr<Dataset> r = ReadDataset(TinyDir());
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const Dataset& d = *r;

  ASSERT_EQ(d.campaigns.size(), 2u);
  EXPECT_EQ(d.campaigns[0].id, "C1");
  EXPECT_EQ(d.campaigns[0].started_at, k20260301 + 6 * kHour);
  EXPECT_EQ(d.campaigns[0].ended_at, k20260301 + 14 * kHour);
  EXPECT_EQ(d.campaigns[1].id, "C2");
  // 15:00+01:00 and 02:30+01:00 the next day.
  EXPECT_EQ(d.campaigns[1].started_at, k20260301 + 14 * kHour);
  EXPECT_EQ(d.campaigns[1].ended_at, k20260301 + 25 * kHour + 1800);

  // mounts.csv has its columns in a different order than the format table.
  ASSERT_EQ(d.mounts.size(), 8u);
  EXPECT_EQ(d.roll_types,
            (std::vector<std::string>{"ICDP-S3", "HSS-S1", "ICDP-S2"}));
  const Mount& m0 = d.mounts[0];
  EXPECT_EQ(m0.campaign, 0);
  EXPECT_EQ(m0.stand, 6);
  EXPECT_EQ(m0.position, Position::kTop);
  EXPECT_EQ(m0.roll_id, "R601");
  EXPECT_EQ(m0.roll_type, 0);
  EXPECT_EQ(m0.diameter_mm, 702.5);
  EXPECT_EQ(m0.hardness_hb, 520);
  const Mount& m5 = d.mounts[5];  // R601 back after grinding
  EXPECT_EQ(m5.campaign, 1);
  EXPECT_EQ(m5.stand, 6);
  EXPECT_EQ(m5.position, Position::kBottom);
  EXPECT_EQ(m5.roll_id, "R601");
  EXPECT_EQ(m5.roll_type, 0);
  EXPECT_EQ(m5.diameter_mm, 700.5);
  EXPECT_EQ(m5.hardness_hb, 519);
  EXPECT_EQ(d.mounts[4].roll_type, 2);
  EXPECT_EQ(d.mounts[2].roll_type, 1);
  EXPECT_EQ(d.mounts[2].diameter_mm, 655.25);

  ASSERT_EQ(d.passes.size(), 10u);
  EXPECT_EQ(d.coil_ids, (std::vector<std::string>{"K1001", "K1003", "K1002",
                                                  "K2001", "K2002"}));
  EXPECT_EQ(d.grades,
            (std::vector<std::string>{"S235", "API-X70", "S355", "DP600"}));
  const Pass& p0 = d.passes[0];
  EXPECT_EQ(p0.campaign, 0);
  EXPECT_EQ(p0.coil, 0);
  EXPECT_EQ(p0.seq, 1);
  EXPECT_EQ(p0.rolled_at, k20260301 + 6 * kHour + 600);
  EXPECT_EQ(p0.grade, 0);
  EXPECT_EQ(p0.stand, 6);
  EXPECT_EQ(p0.force_kn, 18500);
  EXPECT_EQ(p0.width_mm, 1250);
  EXPECT_EQ(p0.length_m, 820.5);
  EXPECT_EQ(p0.entry_thickness_mm, 4.2);
  EXPECT_EQ(p0.exit_thickness_mm, 3.1);
  EXPECT_EQ(p0.temperature_c, 955);
  EXPECT_EQ(p0.speed_mps, 8.5);
  EXPECT_TRUE(p0.lubrication);
  EXPECT_EQ(p0.shift_mm, -25);
  const Pass& p3 = d.passes[3];  // K1002 at F6, rolled 07:20:00+01:00
  EXPECT_EQ(p3.coil, 2);
  EXPECT_EQ(p3.seq, 2);
  EXPECT_EQ(p3.rolled_at, k20260301 + 6 * kHour + 1200);
  EXPECT_EQ(p3.grade, 2);
  EXPECT_EQ(p3.shift_mm, 12.5);
  const Pass& p9 = d.passes[9];
  EXPECT_EQ(p9.campaign, 1);
  EXPECT_EQ(p9.coil, 4);
  EXPECT_EQ(p9.stand, 7);
  EXPECT_EQ(p9.grade, 3);
  EXPECT_FALSE(p9.lubrication);
  EXPECT_EQ(p9.length_m, 952.9);
  EXPECT_EQ(p9.exit_thickness_mm, 2.8);

  // Extra columns of coils.csv: one numeric (with an empty cell), one text.
  const ExtraColumns& x = d.pass_extra;
  ASSERT_EQ(x.numeric_names, (std::vector<std::string>{"water_flow_m3h"}));
  ASSERT_EQ(x.numeric.size(), 1u);
  ASSERT_EQ(x.numeric[0].size(), 10u);
  EXPECT_EQ(x.numeric[0][0], 120.5);
  EXPECT_TRUE(std::isnan(x.numeric[0][2]));
  EXPECT_EQ(x.numeric[0][8], 130.25);
  ASSERT_EQ(x.factor_names, (std::vector<std::string>{"operator_note"}));
  EXPECT_EQ(x.factor_levels[0],
            (std::vector<std::string>{"normal", "thick, hard", "said \"ok\"",
                                      "night shift"}));
  EXPECT_EQ(x.factor[0], (std::vector<int>{0, 0, 1, 2, 2, 0, 0, 0, 3, 3}));
  EXPECT_TRUE(d.campaign_extra.numeric_names.empty());
  EXPECT_TRUE(d.mount_extra.factor_names.empty());

  ASSERT_EQ(d.measurements.size(), 6u);
  const Measurement& s3 = d.measurements[3];
  EXPECT_EQ(s3.campaign, 0);
  EXPECT_EQ(s3.stand, 7);
  EXPECT_EQ(s3.position, Position::kBottom);
  EXPECT_EQ(s3.roll_id, "R702");
  EXPECT_EQ(s3.measured_at, k20260301 + 18 * kHour + 1800);
  EXPECT_EQ(s3.wear_center_um, -3.5);         // grinder noise, allowed
  const Measurement& s4 = d.measurements[4];  // 08:00:00+02:00 next day
  EXPECT_EQ(s4.campaign, 1);
  EXPECT_EQ(s4.measured_at, k20260301 + 30 * kHour);
  EXPECT_EQ(s4.wear_center_um, 120);
}

TEST(DatasetRead, IndexAndDerivedQuantities) {
  StatusOr<Dataset> r = ReadDataset(TinyDir());
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const Dataset& d = *r;
  const DatasetIndex index(d);

  // C1 at F6 is listed seq 1, 3, 2 in the file.
  EXPECT_EQ(index.PassesOf(0, 6), (std::vector<int>{0, 3, 2}));
  EXPECT_EQ(index.PassesOf(0, 7), (std::vector<int>{1, 4, 5}));
  EXPECT_EQ(index.PassesOf(1, 6), (std::vector<int>{6, 8}));
  EXPECT_TRUE(index.PassesOf(1, 5).empty());
  EXPECT_EQ(index.slots(), (std::vector<int>{10, 11, 12, 13}));
  EXPECT_EQ(index.MountOf(0, RollPositionSlot(6, Position::kTop)), 0);
  EXPECT_EQ(index.MountOf(1, RollPositionSlot(6, Position::kBottom)), 5);
  EXPECT_EQ(index.MountOf(1, RollPositionSlot(5, Position::kBottom)), -1);
  EXPECT_EQ(index.MeasurementOf(0, RollPositionSlot(7, Position::kBottom)), 3);
  EXPECT_EQ(index.MeasurementOf(1, RollPositionSlot(6, Position::kBottom)), -1);
  EXPECT_EQ(index.MeasurementOf(1, RollPositionSlot(7, Position::kBottom)), 5);

  const Pass& p = d.passes[0];
  EXPECT_DOUBLE_EQ(SpecificForce(p), 18500.0 / 1250.0);
  EXPECT_DOUBLE_EQ(ContactLength(p, 702.5), std::sqrt(702.5 / 2 * (4.2 - 3.1)));
  EXPECT_DOUBLE_EQ(Reduction(p), (4.2 - 3.1) / 4.2);
}

TEST(DatasetRead, RoundTripReadWriteRead) {
  StatusOr<Dataset> a = ReadDataset(TinyDir());
  ASSERT_TRUE(a.ok()) << a.status().ToString();
  TempDir dir;
  const std::string out = dir.path() + "/nested";
  Status w = WriteDataset(*a, out);
  ASSERT_TRUE(w.ok()) << w.ToString();
  StatusOr<Dataset> b = ReadDataset(out);
  ASSERT_TRUE(b.ok()) << b.status().ToString();
  ExpectSameDataset(*a, *b);

  // Canonical column order, timestamps in Z, extras after the format's
  // columns; writing again gives the same bytes.
  const std::string coils = ReadText(out + "/coils.csv");
  EXPECT_EQ(coils.substr(0, coils.find('\n')),
            "campaign_id,coil_id,seq,rolled_at,grade,stand,force_kn,width_mm,"
            "length_m,entry_thickness_mm,exit_thickness_mm,temperature_c,"
            "speed_mps,lubrication,shift_mm,water_flow_m3h,operator_note");
  EXPECT_NE(coils.find("C1,K1002,2,2026-03-01T06:20:00Z,S355,F6,19800,1400,"
                       "700,4.8,3.6,948,8,1,12.5,119,\"said \"\"ok\"\"\"\n"),
            std::string::npos)
      << coils;
  EXPECT_NE(coils.find(",0,0,,\"thick, hard\"\n"), std::string::npos);
  ASSERT_TRUE(WriteDataset(*b, out).ok());
  EXPECT_EQ(ReadText(out + "/coils.csv"), coils);
}

TEST(DatasetRead, RoundTripKeepsShortestDoubles) {
  StatusOr<Dataset> a = ReadDataset(TinyDir());
  ASSERT_TRUE(a.ok());
  a->passes[0].force_kn = 0.1 + 0.2;  // 0.30000000000000004
  a->passes[1].length_m = 1e-300;
  a->mounts[0].diameter_mm = 2.0 / 3.0;
  TempDir dir;
  ASSERT_TRUE(WriteDataset(*a, dir.path()).ok());
  StatusOr<Dataset> b = ReadDataset(dir.path());
  ASSERT_TRUE(b.ok()) << b.status().ToString();
  ExpectSameDataset(*a, *b);
}

TEST(DatasetRead, QuotedFieldsWithCommasQuotesAndNewlines) {
  DatasetTexts t = TinyTexts();
  SetLine(&t.coils, 2,
          "\"C1\",\"K1001\",\"1\",2026-03-01T06:10:00Z,S235,\"F6\",\"18500\","
          "1250,820.5,4.2,3.1,955,8.5,1,-25,120.5,\"first line\nsecond, "
          "\"\"quoted\"\" line\"");
  StatusOr<Dataset> r = ReadTexts(t);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_EQ(r->passes.size(), 10u);
  EXPECT_EQ(r->passes[0].force_kn, 18500);
  EXPECT_EQ(r->campaigns[r->passes[0].campaign].id, "C1");
  const ExtraColumns& x = r->pass_extra;
  ASSERT_EQ(x.factor_names.size(), 1u);
  EXPECT_EQ(x.factor_levels[0][x.factor[0][0]],
            "first line\nsecond, \"quoted\" line");
  EXPECT_EQ(x.factor_levels[0][x.factor[0][1]], "normal");
}

TEST(DatasetRead, LineNumbersStayPhysicalAfterMultilineField) {
  DatasetTexts t = TinyTexts();
  // Record 1 spans physical lines 2-4; a blank line 6 follows record 2.
  SetLine(&t.coils, 2,
          "C1,K1001,1,2026-03-01T06:10:00Z,S235,F6,18500,1250,820.5,4.2,3.1,"
          "955,8.5,1,-25,120.5,\"one\r\ntwo\nthree\"");
  std::string coils = t.coils;
  const size_t third = coils.find("C1,K1003,3,2026-03-01T06:30:00Z");
  coils.insert(third, "\n");
  t.coils = coils;
  ASSERT_TRUE(ReadTexts(t).ok()) << ReadTexts(t).status().ToString();

  // Break force_kn in the record after the blank line: file line 7.
  t.coils.replace(t.coils.find(",API-X70,F6,21000,"), 18,
                  ",API-X70,F6,-21000,");
  StatusOr<Dataset> r = ReadTexts(t);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(r.status().message().find("coils.csv:7:7 force_kn: must be > 0"),
            std::string::npos)
      << r.status().message();
}

TEST(DatasetRead, CrlfAndByteOrderMark) {
  DatasetTexts t = TinyTexts();
  for (std::string* s : {&t.campaigns, &t.mounts, &t.coils, &t.measurements}) {
    std::string crlf;
    for (char c : *s) {
      if (c == '\n') crlf += '\r';
      crlf += c;
    }
    *s = "\xEF\xBB\xBF" + crlf;
  }
  StatusOr<Dataset> a = ReadTexts(t);
  ASSERT_TRUE(a.ok()) << a.status().ToString();
  StatusOr<Dataset> b = ReadDataset(TinyDir());
  ASSERT_TRUE(b.ok());
  ExpectSameDataset(*a, *b);
}

TEST(DatasetRead, HeaderOnlyFilesAreValid) {
  DatasetTexts t = TinyTexts();
  t.measurements =
      "campaign_id,stand,position,roll_id,measured_at,"
      "wear_center_um\n";
  t.coils = t.coils.substr(0, t.coils.find('\n'));  // no final newline
  StatusOr<Dataset> r = ReadTexts(t);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  EXPECT_TRUE(r->measurements.empty());
  EXPECT_TRUE(r->passes.empty());
  EXPECT_EQ(r->mounts.size(), 8u);
  // The extra columns exist, with no rows.
  EXPECT_EQ(
      r->pass_extra.numeric_names.size() + r->pass_extra.factor_names.size(),
      2u);
}

TEST(DatasetRead, ColumnOrderIsFree) {
  DatasetTexts t = TinyTexts();
  // Reverse the columns of coils.csv.
  std::string reversed;
  for (const std::string& line : dataset_test::Lines(t.coils)) {
    std::vector<std::string> f = dataset_test::SplitRaw(line);
    std::reverse(f.begin(), f.end());
    reversed += dataset_test::JoinRaw(f) + "\n";
  }
  t.coils = reversed;
  StatusOr<Dataset> a = ReadTexts(t);
  ASSERT_TRUE(a.ok()) << a.status().ToString();
  StatusOr<Dataset> b = ReadDataset(TinyDir());
  ASSERT_TRUE(b.ok());
  // Extras come in file order, so only the format's fields are compared.
  a->pass_extra = b->pass_extra;
  ExpectSameDataset(*a, *b);
}

// Issue 16 made a pass at a stand without a mounted roll a rule break (it
// was kept and ignored by the index before): the whole dataset is refused.
TEST(DatasetRead, PassAtStandWithoutMountIsRejected) {
  DatasetTexts t = TinyTexts();
  AppendLine(&t.coils,
             "C1,K1001,1,2026-03-01T06:09:50Z,S235,F5,21000,1250,600,5.6,4.2,"
             "965,6.5,0,0,121,normal");
  StatusOr<Dataset> r = ReadTexts(t);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(r.status().message(),
            "coils.csv:12:6 stand: no roll mounted at F5 in campaign C1; its "
            "rolls are at F6/top, F6/bottom, F7/top, F7/bottom");
}

TEST(DatasetTimestamp, ParsesZuluAndOffsets) {
  UnixSeconds z = 0, t = 0;
  ASSERT_TRUE(ParseTimestamp("2026-03-01T06:12:00Z", &z));
  EXPECT_EQ(z, 1772345520);
  ASSERT_TRUE(ParseTimestamp("2026-03-01T07:12:00+01:00", &t));
  EXPECT_EQ(t, z);
  ASSERT_TRUE(ParseTimestamp("2026-03-01T07:12:00+0100", &t));
  EXPECT_EQ(t, z);
  ASSERT_TRUE(ParseTimestamp("2026-03-01T00:42:00-05:30", &t));
  EXPECT_EQ(t, z);
  ASSERT_TRUE(ParseTimestamp("2026-03-01T06:12:00.999Z", &t));
  EXPECT_EQ(t, z);  // fraction truncated
  ASSERT_TRUE(ParseTimestamp("2026-03-01T06:12:00.5+00:00", &t));
  EXPECT_EQ(t, z);
  ASSERT_TRUE(ParseTimestamp("2024-02-29T23:59:59Z", &t));
  EXPECT_EQ(t, 1709251199);
  ASSERT_TRUE(ParseTimestamp("1970-01-01T00:00:00Z", &t));
  EXPECT_EQ(t, 0);
  ASSERT_TRUE(ParseTimestamp("1969-12-31T23:59:59Z", &t));
  EXPECT_EQ(t, -1);
  ASSERT_TRUE(ParseTimestamp("2000-01-01T00:00:00+14:00", &t));
  EXPECT_EQ(t, 946684800 - 14 * kHour);
}

TEST(DatasetTimestamp, RejectsEverythingElse) {
  for (const char* bad : {
           "",
           "2026-03-01T06:12:00",       // no offset
           "2026-03-01 06:12:00Z",      // space separator
           "2026-03-01t06:12:00Z",      // lowercase t
           "2026-03-01T06:12:00z",      // lowercase z
           "2026-03-01",                // date only
           "2026-3-01T06:12:00Z",       // one-digit month
           "2026-03-01T6:12:00Z",       // one-digit hour
           "2026-03-01T06:12Z",         // no seconds
           "2026-13-01T06:12:00Z",      // month 13
           "2026-00-01T06:12:00Z",      // month 0
           "2026-02-29T06:12:00Z",      // not a leap year
           "2026-04-31T06:12:00Z",      // April has 30 days
           "2026-03-01T24:00:00Z",      // hour 24
           "2026-03-01T06:60:00Z",      // minute 60
           "2026-03-01T06:12:60Z",      // second 60
           "2026-03-01T06:12:00.Z",     // empty fraction
           "2026-03-01T06:12:00+01",    // offset without minutes
           "2026-03-01T06:12:00+1:00",  // one-digit offset hour
           "2026-03-01T06:12:00+01:00:00",
           "2026-03-01T06:12:00+01:60",
           "2026-03-01T06:12:00Zjunk",
           " 2026-03-01T06:12:00Z",
           "2026-03-01T06:12:00Z ",
           "1772345520",
       }) {
    UnixSeconds t = 42;
    EXPECT_FALSE(ParseTimestamp(bad, &t)) << "'" << bad << "'";
  }
}

TEST(DatasetTimestamp, FormatAndRoundTrip) {
  EXPECT_EQ(FormatTimestamp(1772345520), "2026-03-01T06:12:00Z");
  EXPECT_EQ(FormatTimestamp(0), "1970-01-01T00:00:00Z");
  EXPECT_EQ(FormatTimestamp(-1), "1969-12-31T23:59:59Z");
  EXPECT_EQ(FormatTimestamp(1709251199), "2024-02-29T23:59:59Z");
  // Every ~37 hours over 1900..2100 (plus a second offset to vary the time).
  for (UnixSeconds t = -2208988800; t < 4102444800; t += 133201) {
    UnixSeconds back = 0;
    ASSERT_TRUE(ParseTimestamp(FormatTimestamp(t), &back)) << t;
    ASSERT_EQ(back, t) << FormatTimestamp(t);
  }
}

// The reader's fast path for plain decimals must give exactly what
// std::from_chars gives.
TEST(DatasetCsv, NumbersMatchFromChars) {
  std::mt19937_64 rng(7);
  std::vector<std::string> texts = {"0",
                                    "-0",
                                    "0.1",
                                    "0.30000000000000004",
                                    "9007199254740993",
                                    ".5",
                                    "5.",
                                    "-.25",
                                    "123456789012345678",
                                    "1234567890123456789",
                                    "12345678901234567890",
                                    "0.0000000000000000000000123",
                                    "1e5",
                                    "+2.5",
                                    " 7.25\t",
                                    "4.2",
                                    "3.1",
                                    "1250",
                                    "820.5",
                                    "-12.5"};
  for (int i = 0; i < 20000; ++i) {
    const uint64_t m = rng() >> (rng() % 64);
    const int decimals = static_cast<int>(rng() % 25);
    std::string digits = std::to_string(m);
    if (decimals > 0) {
      while (static_cast<int>(digits.size()) <= decimals) digits.insert(0, "0");
      digits.insert(digits.size() - decimals, ".");
    }
    texts.push_back(rng() % 2 ? "-" + digits : digits);
  }
  for (const std::string& text : texts) {
    double fast = 0;
    ASSERT_EQ(csv::ParseDouble(text, &fast), csv::NumberResult::kOk) << text;
    std::string_view trimmed = csv::Trim(text);
    if (trimmed[0] == '+') trimmed.remove_prefix(1);
    double slow = 0;
    std::from_chars(trimmed.data(), trimmed.data() + trimmed.size(), slow);
    ASSERT_EQ(std::signbit(fast), std::signbit(slow)) << text;
    ASSERT_EQ(fast, slow) << text;
  }
  double v = 0;
  for (const char* bad : {"", "-", ".", "1.2.3", "1,5", "12.5kN", "--1", "+-1",
                          "0x10", "1e", "e5", "- 1"}) {
    EXPECT_EQ(csv::ParseDouble(bad, &v), csv::NumberResult::kInvalid) << bad;
  }
  EXPECT_EQ(csv::ParseDouble("1e999", &v), csv::NumberResult::kOutOfRange);
}

// Appends every part to *out.
template <typename... Parts>
void Append(std::string* out, const Parts&... parts) {
  (out->append(parts), ...);
}

// ~104,000 coil rows generated in memory: every row must land, in order.
TEST(DatasetRead, HundredThousandSyntheticCoils) {
  constexpr int kCampaigns = 400;
  constexpr int kCoils = 130;
  static const char* const kGrades[] = {
      "S235", "S355", "DP600", "API-X70", "DC01", "S420", "HSLA", "IF", "C45"};
  std::string campaigns = "campaign_id,started_at,ended_at\n";
  std::string mounts =
      "campaign_id,stand,position,roll_id,roll_type,diameter_mm,hardness_hb\n";
  std::string measurements =
      "campaign_id,stand,position,roll_id,measured_at,wear_center_um\n";
  std::string coils =
      "campaign_id,coil_id,seq,rolled_at,grade,stand,force_kn,width_mm,"
      "length_m,entry_thickness_mm,exit_thickness_mm,temperature_c,speed_mps,"
      "lubrication,shift_mm,tension_kn\n";
  coils.reserve(size_t{kCampaigns} * kCoils * 2 * 130);
  int expected_measurements = 0;
  for (int c = 0; c < kCampaigns; ++c) {
    const std::string id = "C" + std::to_string(c + 1);
    const UnixSeconds start = k20260301 + UnixSeconds{c} * 9 * kHour;
    Append(&campaigns, id, ",", FormatTimestamp(start), ",",
           FormatTimestamp(start + 8 * kHour), "\n");
    for (int stand : {6, 7}) {
      const std::string f = ",F" + std::to_string(stand) + ",";
      for (const char* pos : {"top", "bottom"}) {
        const std::string roll =
            "R" + std::to_string(stand) + pos[0] + std::to_string(c % 37);
        Append(&mounts, id, f, pos, ",", roll, ",ICDP-S", std::to_string(c % 8),
               ",700,520\n");
        if ((c + stand) % 5 != 0) {
          Append(&measurements, id, f, pos, ",", roll, ",",
                 FormatTimestamp(start + 10 * kHour), ",",
                 std::to_string(100 + c % 50), ".5\n");
          ++expected_measurements;
        }
      }
    }
    for (int k = 0; k < kCoils; ++k) {
      const std::string seq = std::to_string(k + 1);
      const std::string coil = std::to_string(c * 1000 + k);
      for (int stand : {6, 7}) {
        Append(&coils, id, ",K", coil, ",", seq, ",",
               FormatTimestamp(start + UnixSeconds{k} * 200 + stand), ",",
               kGrades[(c + k) % 9], ",F", std::to_string(stand), ",",
               std::to_string(15000 + k * 7), ".25,1250,812.5,4.2,3.1,950,8.5,",
               std::to_string(k % 2), ",-12.5,", std::to_string(k), "\n");
      }
    }
  }
  DatasetTexts t{campaigns, mounts, coils, measurements};
  StatusOr<Dataset> r = ReadTexts(t);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const Dataset& d = *r;
  EXPECT_EQ(d.campaigns.size(), static_cast<size_t>(kCampaigns));
  EXPECT_EQ(d.mounts.size(), static_cast<size_t>(kCampaigns * 4));
  ASSERT_EQ(d.passes.size(), static_cast<size_t>(kCampaigns * kCoils * 2));
  EXPECT_EQ(d.coil_ids.size(), static_cast<size_t>(kCampaigns * kCoils));
  EXPECT_EQ(d.grades.size(), 9u);
  EXPECT_EQ(d.roll_types.size(), 8u);
  EXPECT_EQ(d.measurements.size(), static_cast<size_t>(expected_measurements));
  ASSERT_EQ(d.pass_extra.numeric_names,
            (std::vector<std::string>{"tension_kn"}));
  EXPECT_EQ(d.pass_extra.numeric[0].back(), kCoils - 1);

  const DatasetIndex index(d);
  for (int c = 0; c < kCampaigns; ++c) {
    for (int stand : {6, 7}) {
      const std::vector<int>& list = index.PassesOf(c, stand);
      ASSERT_EQ(list.size(), static_cast<size_t>(kCoils));
      for (int k = 0; k < kCoils; ++k) {
        const Pass& p = d.passes[list[k]];
        ASSERT_EQ(p.seq, k + 1);
        ASSERT_EQ(p.stand, stand);
        ASSERT_EQ(p.force_kn, 15000 + k * 7 + 0.25);
        ASSERT_EQ(p.lubrication, k % 2 == 1);
      }
    }
  }
}

}  // namespace
}  // namespace rollwear
