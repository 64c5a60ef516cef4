// Tests of the reader's two-thread paths on files large enough to take
// them: csv::Table::Parse cuts a quote-free file of 1 MB or more at a line
// end near its middle (core/base/csv.h), and ReadDataset reads the
// row-local rules of a coils.csv of 16,384 rows or more in two halves
// (core/dataset/dataset_io.cc). Each must give what one thread gives: the
// same fields at the same physical lines, and the first broken rule of the
// file, whichever half it is in.
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/base/csv.h"
#include "core/dataset/dataset_io.h"
#include "core/sim/simulator.h"
#include "tests/core/dataset_test_util.h"

namespace rollwear {
namespace {

using dataset_test::DatasetTexts;
using dataset_test::ReadText;
using dataset_test::ReadTexts;
using dataset_test::SetField;

// The read fails with InvalidArgument and a message holding `piece`.
void ExpectReadFails(const StatusOr<Dataset>& r, const std::string& piece) {
  ASSERT_FALSE(r.ok()) << "dataset was accepted";
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(r.status().message().find(piece), std::string::npos)
      << "message: " << r.status().message() << "\nmissing: " << piece;
}

// ~1.2 MB of quote-free CSV with blank lines, CRLF and lone-CR line ends
// and fields of varying width, so the cut can land anywhere.
std::string LargeQuoteFreeCsv() {
  std::string text = "a,b,c\n\n";
  for (int r = 0; r < 80000; ++r) {
    text += std::to_string(r) + ",x" + std::string(r % 7, 'y') + "," +
            std::to_string(r * 31 % 1000);
    text += r % 5 == 0 ? "\r\n" : (r % 13 == 0 ? "\r" : "\n");
    if (r % 97 == 0) text += "\n";
    if (r % 301 == 0) text += "\r\n";
  }
  return text;
}

TEST(CsvTableTest, AQuoteFreeFileReadInTwoHalvesEqualsTheOneThreadRead) {
  const std::string text = LargeQuoteFreeCsv();
  ASSERT_GE(text.size(), size_t{1} << 20);
  // One quoted field on an extra last record makes the parser read the
  // whole file on one thread; every record before it must be the same.
  const std::string serial_text = text + "\"q\",1,2\n";
  StatusOr<csv::Table> halves = csv::Table::Parse(text, "big.csv");
  StatusOr<csv::Table> serial = csv::Table::Parse(serial_text, "big.csv");
  ASSERT_TRUE(halves.ok()) << halves.status().ToString();
  ASSERT_TRUE(serial.ok()) << serial.status().ToString();
  // The comparison means something only if the paths differ.
  ASSERT_TRUE(halves->read_in_halves());
  ASSERT_FALSE(serial->read_in_halves());
  ASSERT_EQ(halves->num_records(), 80000u);
  ASSERT_EQ(serial->num_records(), 80001u);
  EXPECT_EQ(halves->header(), serial->header());
  int mismatches = 0;
  for (size_t r = 0; r < halves->num_records(); ++r) {
    bool same = halves->line(r) == serial->line(r) &&
                halves->num_fields(r) == serial->num_fields(r);
    for (size_t c = 0; same && c < halves->num_fields(r); ++c) {
      same = halves->field(r, c) == serial->field(r, c);
    }
    if (!same && ++mismatches <= 3) {
      ADD_FAILURE() << "record " << r << ": line " << halves->line(r) << " vs "
                    << serial->line(r);
    }
  }
  EXPECT_EQ(mismatches, 0);
  // The last record's line counts every line end of the file before it.
  const size_t last = halves->num_records() - 1;
  EXPECT_EQ(halves->field(last, 0), "79999");
  EXPECT_EQ(serial->line(last + 1), serial->line(last) + 1);
}

// A simulated dataset of ~18,000 pass rows (two halves of over 8,192),
// its four files as text.
class LargeDatasetRead : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    SimulatorOptions o;
    o.seed = 5;
    o.num_campaigns = 70;
    StatusOr<Simulation> sim = Simulate(o);
    ASSERT_TRUE(sim.ok()) << sim.status().ToString();
    const std::string dir = dataset_test::ScratchDir("rollwear_large_read");
    ASSERT_TRUE(WriteDataset(sim->data, dir).ok());
    texts_ = new DatasetTexts{
        ReadText(dir + "/campaigns.csv"), ReadText(dir + "/mounts.csv"),
        ReadText(dir + "/coils.csv"), ReadText(dir + "/measurements.csv")};
    rows_ = static_cast<int>(sim->data.passes.size());
    std::filesystem::remove_all(dir);
  }
  static void TearDownTestSuite() { delete texts_; }

  static DatasetTexts* texts_;
  static int rows_;
};
DatasetTexts* LargeDatasetRead::texts_ = nullptr;
int LargeDatasetRead::rows_ = 0;

TEST_F(LargeDatasetRead, ReadsEveryRowInFileOrder) {
  ASSERT_GE(rows_, 16384);
  DatasetLines lines;
  std::istringstream c(texts_->campaigns), m(texts_->mounts), p(texts_->coils),
      s(texts_->measurements);
  StatusOr<Dataset> d = ReadDatasetStreams({&c, &m, &p, &s}, &lines);
  ASSERT_TRUE(d.ok()) << d.status().ToString();
  ASSERT_EQ(static_cast<int>(d->passes.size()), rows_);
  // Row r is physical line r + 2, in both halves.
  ASSERT_EQ(static_cast<int>(lines.passes.size()), rows_);
  EXPECT_EQ(lines.passes.front(), 2);
  EXPECT_EQ(lines.passes[rows_ / 2 + 1], rows_ / 2 + 3);
  EXPECT_EQ(lines.passes.back(), rows_ + 1);
}

TEST_F(LargeDatasetRead, ABrokenFieldInTheSecondHalfIsReportedAtItsLine) {
  DatasetTexts t = *texts_;
  const int line = rows_ - 10;  // in the second half
  SetField(&t.coils, line, "width_mm", "wide");
  ExpectReadFails(ReadTexts(t), "coils.csv:" + std::to_string(line) +
                                    ":8 width_mm: unparsable number");
}

TEST_F(LargeDatasetRead, TheFirstBrokenRuleOfTheFileWinsAcrossTheHalves) {
  DatasetTexts t = *texts_;
  // A field error late in the second half, an earlier one in the first
  // half: the first half's is reported.
  SetField(&t.coils, rows_ - 10, "width_mm", "wide");
  SetField(&t.coils, 500, "force_kn", "-1");
  ExpectReadFails(ReadTexts(t), "coils.csv:500:7 force_kn: must be > 0");
  // A key error (a coil that changes grade between its stands, a rule
  // across rows) before a field error of the second half: the key error.
  t = *texts_;
  SetField(&t.coils, rows_ - 10, "width_mm", "wide");
  const std::string other_grade =
      dataset_test::LineOf(t.coils, 3).find(",CQ,") != std::string::npos ? "DQ"
                                                                         : "CQ";
  SetField(&t.coils, 3, "grade", other_grade);
  ExpectReadFails(ReadTexts(t), "coils.csv:3:5 grade: coil has grade");
  // A field error in the second half before a key error later in it.
  t = *texts_;
  SetField(&t.coils, rows_ - 100, "speed_mps", "fast");
  SetField(&t.coils, rows_, "seq", "1");
  ExpectReadFails(ReadTexts(t), "coils.csv:" + std::to_string(rows_ - 100) +
                                    ":13 speed_mps: unparsable number");
}

}  // namespace
}  // namespace rollwear
