// `rollwear import --db FILE DIR`: a dataset folder goes in all-or-nothing;
// a broken one is refused with file:line:column and changes nothing; the
// daemon then serves what was imported.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/dataset/dataset_io.h"
#include "tests/e2e/e2e_util.h"

namespace rollwear::e2e {
namespace {

// Copies the dataset folder `from` to `to`, setting force_kn of the first
// data row of coils.csv to -5.
void WriteBrokenCopy(const std::string& from, const std::string& to) {
  std::filesystem::create_directories(to);
  for (const char* name :
       {"campaigns.csv", "mounts.csv", "coils.csv", "measurements.csv"}) {
    std::string text = ReadFile(from + "/" + name);
    if (std::string(name) == "coils.csv") {
      std::istringstream in(text);
      std::string header, row, rest, line;
      std::getline(in, header);
      std::getline(in, row);
      while (std::getline(in, line)) rest += line + "\n";
      std::vector<std::string> columns, fields;
      std::stringstream h(header), r(row);
      for (std::string f; std::getline(h, f, ',');) columns.push_back(f);
      for (std::string f; std::getline(r, f, ',');) fields.push_back(f);
      for (size_t i = 0; i < columns.size() && i < fields.size(); ++i) {
        if (columns[i] == "force_kn") fields[i] = "-5";
      }
      row.clear();
      for (size_t i = 0; i < fields.size(); ++i) {
        row += (i ? "," : "") + fields[i];
      }
      text = header + "\n" + row + "\n" + rest;
    }
    std::ofstream(to + "/" + name, std::ios::binary) << text;
  }
}

TEST(ImportTest, AllOrNothingThenServed) {
  TempDir dir;
  std::string error, output;
  ASSERT_TRUE(Simulate(dir / "data", 6, 2, &error)) << error;
  StatusOr<Dataset> data = ReadDataset(dir / "data");
  ASSERT_TRUE(data.ok());
  WriteBrokenCopy(dir / "data", dir / "bad");

  // A broken dataset: exit 1, file:line:column and the rule, nothing stored.
  EXPECT_EQ(RunRollwear({"import", "--db", dir / "x.db", dir / "bad"}, &output),
            1);
  EXPECT_NE(output.find("coils.csv:2:"), std::string::npos) << output;
  EXPECT_NE(output.find("force_kn"), std::string::npos) << output;
  EXPECT_NE(output.find("nothing imported"), std::string::npos) << output;

  EXPECT_EQ(
      RunRollwear({"import", "--db", dir / "x.db", dir / "data"}, &output), 0)
      << output;
  EXPECT_NE(output.find("imported"), std::string::npos) << output;
  EXPECT_EQ(RunRollwear({"import", "--db", dir / "x.db"}, &output), 2);

  Daemon daemon(dir / "x.db", dir / "serve.log");
  ASSERT_TRUE(daemon.Start(&error)) << error;
  const auto metrics = ScrapeMetrics(daemon.url());
  EXPECT_EQ(metrics.at("rollwear_coils_stored"),
            static_cast<double>(data->coil_ids.size()));
  EXPECT_EQ(metrics.at("rollwear_campaigns_stored"), 6);
  EXPECT_EQ(metrics.at("rollwear_measurements_stored"),
            static_cast<double>(data->measurements.size()));
  // Imported coils are stored keys: posting one again is a repeat.
  json answer;
  EXPECT_EQ(
      HttpPost(daemon.url(), "/v1/coils", CoilJson(*data, 0).dump(), &answer),
      200)
      << answer.dump();
}

}  // namespace
}  // namespace rollwear::e2e
