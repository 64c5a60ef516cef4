// Test helpers for the dataset reader tests: the checked-in tiny dataset
// (tests/data/tiny) as editable text, small CSV line editors, reading four
// texts through ReadDatasetStreams, a field-by-field Dataset comparison and
// a scratch directory unique to the test process.
//
// Thread-safety: plain functions over values; tests use them from one
// thread.
#ifndef ROLLWEAR_TESTS_CORE_DATASET_TEST_UTIL_H_
#define ROLLWEAR_TESTS_CORE_DATASET_TEST_UTIL_H_

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/dataset/dataset.h"
#include "core/dataset/dataset_io.h"

namespace rollwear::dataset_test {

inline std::string TinyDir() {
  return std::string(ROLLWEAR_TEST_DATA_DIR) + "/tiny";
}

// A scratch directory path under the system's temp directory, unique to
// this test process: ctest runs each test of a suite as its own process,
// in parallel, so a fixed name lets one test remove the files another is
// reading (session 29's CI failure of
// LargeDatasetRead.ABrokenFieldInTheSecondHalfIsReportedAtItsLine).
inline std::string ScratchDir(const std::string& prefix) {
  return (std::filesystem::temp_directory_path() /
          (prefix + "_" + std::to_string(::getpid())))
      .string();
}

// The four files of a dataset as text.
struct DatasetTexts {
  std::string campaigns;
  std::string mounts;
  std::string coils;
  std::string measurements;
};

inline std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline DatasetTexts TinyTexts() {
  const std::string dir = TinyDir();
  return {ReadText(dir + "/campaigns.csv"), ReadText(dir + "/mounts.csv"),
          ReadText(dir + "/coils.csv"), ReadText(dir + "/measurements.csv")};
}

inline StatusOr<Dataset> ReadTexts(const DatasetTexts& t) {
  std::istringstream c(t.campaigns), m(t.mounts), p(t.coils), s(t.measurements);
  return ReadDatasetStreams({&c, &m, &p, &s});
}

// Splits single-line CSV text into lines (no line break inside quotes).
inline std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::string cur;
  std::istringstream in(text);
  while (std::getline(in, cur)) lines.push_back(cur);
  return lines;
}

inline std::string JoinLines(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  return out;
}

// Raw fields of one CSV line, quotes kept (a quoted field never holds a
// line break in the files these helpers edit).
inline std::vector<std::string> SplitRaw(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (char c : line) {
    if (c == '"') quoted = !quoted;
    if (c == ',' && !quoted) {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

inline std::string JoinRaw(const std::vector<std::string>& fields) {
  std::string out;
  for (size_t i = 0; i < fields.size(); ++i) {
    if (i > 0) out += ',';
    out += fields[i];
  }
  return out;
}

// Sets the raw text of `column` on physical line `line` (1 = header).
inline void SetField(std::string* text, int line, const std::string& column,
                     const std::string& raw) {
  std::vector<std::string> lines = Lines(*text);
  const std::vector<std::string> header = SplitRaw(lines.at(0));
  size_t c = 0;
  while (c < header.size() && header[c] != column) ++c;
  ASSERT_LT(c, header.size()) << "no column " << column;
  std::vector<std::string> fields = SplitRaw(lines.at(line - 1));
  fields.at(c) = raw;
  lines[line - 1] = JoinRaw(fields);
  *text = JoinLines(lines);
}

// Replaces physical line `line` (1 = header) with `content`.
inline void SetLine(std::string* text, int line, const std::string& content) {
  std::vector<std::string> lines = Lines(*text);
  lines.at(line - 1) = content;
  *text = JoinLines(lines);
}

inline void AppendLine(std::string* text, const std::string& content) {
  std::vector<std::string> lines = Lines(*text);
  lines.push_back(content);
  *text = JoinLines(lines);
}

inline void EraseLine(std::string* text, int line) {
  std::vector<std::string> lines = Lines(*text);
  lines.erase(lines.begin() + (line - 1));
  *text = JoinLines(lines);
}

// Physical line `line` (1 = header) of `text`.
inline std::string LineOf(const std::string& text, int line) {
  return Lines(text).at(line - 1);
}

// Removes `column` from every line.
inline void DropColumn(std::string* text, const std::string& column) {
  std::vector<std::string> lines = Lines(*text);
  const std::vector<std::string> header = SplitRaw(lines.at(0));
  size_t c = 0;
  while (c < header.size() && header[c] != column) ++c;
  ASSERT_LT(c, header.size()) << "no column " << column;
  for (std::string& l : lines) {
    std::vector<std::string> fields = SplitRaw(l);
    fields.erase(fields.begin() + c);
    l = JoinRaw(fields);
  }
  *text = JoinLines(lines);
}

inline bool SameDouble(double a, double b) {
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

inline void ExpectSameExtra(const ExtraColumns& a, const ExtraColumns& b) {
  EXPECT_EQ(a.numeric_names, b.numeric_names);
  ASSERT_EQ(a.numeric.size(), b.numeric.size());
  for (size_t c = 0; c < a.numeric.size(); ++c) {
    ASSERT_EQ(a.numeric[c].size(), b.numeric[c].size());
    for (size_t r = 0; r < a.numeric[c].size(); ++r) {
      EXPECT_TRUE(SameDouble(a.numeric[c][r], b.numeric[c][r]))
          << a.numeric_names[c] << " row " << r;
    }
  }
  EXPECT_EQ(a.factor_names, b.factor_names);
  EXPECT_EQ(a.factor, b.factor);
  EXPECT_EQ(a.factor_levels, b.factor_levels);
}

// Field-by-field equality of two datasets (exact doubles).
inline void ExpectSameDataset(const Dataset& a, const Dataset& b) {
  ASSERT_EQ(a.campaigns.size(), b.campaigns.size());
  for (size_t i = 0; i < a.campaigns.size(); ++i) {
    EXPECT_EQ(a.campaigns[i].id, b.campaigns[i].id);
    EXPECT_EQ(a.campaigns[i].started_at, b.campaigns[i].started_at);
    EXPECT_EQ(a.campaigns[i].ended_at, b.campaigns[i].ended_at);
  }
  ASSERT_EQ(a.mounts.size(), b.mounts.size());
  for (size_t i = 0; i < a.mounts.size(); ++i) {
    const Mount& x = a.mounts[i];
    const Mount& y = b.mounts[i];
    EXPECT_EQ(x.campaign, y.campaign);
    EXPECT_EQ(x.stand, y.stand);
    EXPECT_EQ(x.position, y.position);
    EXPECT_EQ(x.roll_id, y.roll_id);
    EXPECT_EQ(x.roll_type, y.roll_type);
    EXPECT_EQ(x.diameter_mm, y.diameter_mm);
    EXPECT_EQ(x.hardness_hb, y.hardness_hb);
  }
  ASSERT_EQ(a.passes.size(), b.passes.size());
  for (size_t i = 0; i < a.passes.size(); ++i) {
    const Pass& x = a.passes[i];
    const Pass& y = b.passes[i];
    EXPECT_EQ(x.campaign, y.campaign) << "pass " << i;
    EXPECT_EQ(x.coil, y.coil) << "pass " << i;
    EXPECT_EQ(x.seq, y.seq) << "pass " << i;
    EXPECT_EQ(x.rolled_at, y.rolled_at) << "pass " << i;
    EXPECT_EQ(x.grade, y.grade) << "pass " << i;
    EXPECT_EQ(x.stand, y.stand) << "pass " << i;
    EXPECT_EQ(x.force_kn, y.force_kn) << "pass " << i;
    EXPECT_EQ(x.width_mm, y.width_mm) << "pass " << i;
    EXPECT_EQ(x.length_m, y.length_m) << "pass " << i;
    EXPECT_EQ(x.entry_thickness_mm, y.entry_thickness_mm) << "pass " << i;
    EXPECT_EQ(x.exit_thickness_mm, y.exit_thickness_mm) << "pass " << i;
    EXPECT_EQ(x.temperature_c, y.temperature_c) << "pass " << i;
    EXPECT_EQ(x.speed_mps, y.speed_mps) << "pass " << i;
    EXPECT_EQ(x.lubrication, y.lubrication) << "pass " << i;
    EXPECT_EQ(x.shift_mm, y.shift_mm) << "pass " << i;
  }
  ASSERT_EQ(a.measurements.size(), b.measurements.size());
  for (size_t i = 0; i < a.measurements.size(); ++i) {
    const Measurement& x = a.measurements[i];
    const Measurement& y = b.measurements[i];
    EXPECT_EQ(x.campaign, y.campaign);
    EXPECT_EQ(x.stand, y.stand);
    EXPECT_EQ(x.position, y.position);
    EXPECT_EQ(x.roll_id, y.roll_id);
    EXPECT_EQ(x.measured_at, y.measured_at);
    EXPECT_EQ(x.wear_center_um, y.wear_center_um);
  }
  EXPECT_EQ(a.grades, b.grades);
  EXPECT_EQ(a.roll_types, b.roll_types);
  EXPECT_EQ(a.coil_ids, b.coil_ids);
  ExpectSameExtra(a.campaign_extra, b.campaign_extra);
  ExpectSameExtra(a.mount_extra, b.mount_extra);
  ExpectSameExtra(a.pass_extra, b.pass_extra);
  ExpectSameExtra(a.measurement_extra, b.measurement_extra);
}

}  // namespace rollwear::dataset_test

#endif  // ROLLWEAR_TESTS_CORE_DATASET_TEST_UTIL_H_
