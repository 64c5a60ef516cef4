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

// Copies the dataset folder `from` to `to`, setting `column` of data row
// `row` (1 = the first after the header) of `file` to `value`.
void WriteEditedCopy(const std::string& from, const std::string& to,
                     const std::string& file, int row,
                     const std::string& column, const std::string& value) {
  std::filesystem::create_directories(to);
  for (const char* name :
       {"campaigns.csv", "mounts.csv", "coils.csv", "measurements.csv"}) {
    std::string text = ReadFile(from + "/" + name);
    if (name == file) {
      std::istringstream in(text);
      std::vector<std::string> lines;
      for (std::string line; std::getline(in, line);) lines.push_back(line);
      std::vector<std::string> columns, fields;
      std::stringstream h(lines.at(0)), r(lines.at(row));
      for (std::string f; std::getline(h, f, ',');) columns.push_back(f);
      for (std::string f; std::getline(r, f, ',');) fields.push_back(f);
      for (size_t i = 0; i < columns.size() && i < fields.size(); ++i) {
        if (columns[i] == column) fields[i] = value;
      }
      lines[row].clear();
      for (size_t i = 0; i < fields.size(); ++i) {
        lines[row] += (i ? "," : "") + fields[i];
      }
      text.clear();
      for (const std::string& line : lines) text += line + "\n";
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
  WriteEditedCopy(dir / "data", dir / "bad", "coils.csv", 1, "force_kn", "-5");

  // A broken dataset: exit 1, file:line:column and the rule, nothing stored.
  EXPECT_EQ(RunRollwear({"import", "--db", dir / "x.db", dir / "bad"}, &output),
            1);
  EXPECT_NE(output.find("coils.csv:2:"), std::string::npos) << output;
  EXPECT_NE(output.find("force_kn"), std::string::npos) << output;
  EXPECT_NE(output.find("nothing imported"), std::string::npos) << output;

  EXPECT_EQ(
      RunRollwear({"import", "--db", dir / "x.db", dir / "data"}, &output), 0)
      << output;
  const std::string n_coils = std::to_string(data->coil_ids.size());
  const std::string n_meas = std::to_string(data->measurements.size());
  EXPECT_NE(output.find("campaigns 6 new, 0 unchanged; mounts 24 new, 0 "
                        "unchanged; coils " +
                        n_coils + " new, 0 unchanged; measurements " + n_meas +
                        " new, 0 unchanged"),
            std::string::npos)
      << output;
  // The same folder again: nothing new, every row unchanged.
  EXPECT_EQ(
      RunRollwear({"import", "--db", dir / "x.db", dir / "data"}, &output), 0)
      << output;
  EXPECT_NE(output.find("campaigns 0 new, 6 unchanged; mounts 0 new, 24 "
                        "unchanged; coils 0 new, " +
                        n_coils + " unchanged; measurements 0 new, " + n_meas +
                        " unchanged"),
            std::string::npos)
      << output;
  EXPECT_EQ(RunRollwear({"import", "--db", dir / "x.db"}, &output), 2);

  // A row that conflicts with what is stored is named by file and line.
  WriteEditedCopy(dir / "data", dir / "changed", "measurements.csv", 2,
                  "wear_center_um", "999.5");
  EXPECT_EQ(
      RunRollwear({"import", "--db", dir / "x.db", dir / "changed"}, &output),
      1);
  EXPECT_NE(output.find("measurements.csv:3 campaign_id: "), std::string::npos)
      << output;
  EXPECT_NE(output.find("is already measured with different content "
                        "(nothing imported)"),
            std::string::npos)
      << output;

  Daemon daemon(dir / "x.db", dir / "serve.log");
  ASSERT_TRUE(daemon.Start(&error)) << error;
  const auto metrics = ScrapeMetrics(daemon.url());
  EXPECT_EQ(metrics.at("rollwear_coils_stored"),
            static_cast<double>(data->coil_ids.size()));
  EXPECT_EQ(metrics.at("rollwear_campaigns_stored"), 6);
  EXPECT_EQ(metrics.at("rollwear_measurements_stored"),
            static_cast<double>(data->measurements.size()));
  // While the daemon holds the database, import is refused and stores
  // nothing: the daemon would not see rows written behind its back.
  ASSERT_TRUE(Simulate(dir / "more", 3, 5, &error)) << error;
  EXPECT_EQ(
      RunRollwear({"import", "--db", dir / "x.db", dir / "more"}, &output), 1);
  EXPECT_NE(output.find("rollwear import: database " + (dir / "x.db") +
                        " is in use by rollwear serve, pid "),
            std::string::npos)
      << output;
  EXPECT_NE(output.find("stop it first"), std::string::npos) << output;
  EXPECT_NE(output.find("(nothing imported)"), std::string::npos) << output;
  const auto after = ScrapeMetrics(daemon.url());
  for (const char* name : {"rollwear_coils_stored", "rollwear_campaigns_stored",
                           "rollwear_measurements_stored"}) {
    EXPECT_EQ(after.at(name), metrics.at(name)) << name;
  }
  // Imported coils are stored keys: posting one again is a repeat.
  json answer;
  EXPECT_EQ(
      HttpPost(daemon.url(), "/v1/coils", CoilJson(*data, 0).dump(), &answer),
      200)
      << answer.dump();
}

// profiles.csv is read, checked and stored with the folder (a broken point
// refuses the import, naming file and line); a second import of the same
// folder adds nothing, and export writes the points back.
TEST(ImportTest, ProfilesAreCheckedStoredAndExported) {
  TempDir dir;
  std::string error, output;
  ASSERT_TRUE(Simulate(dir / "data", 3, 2, &error)) << error;
  StatusOr<Dataset> data = ReadDataset(dir / "data");
  ASSERT_TRUE(data.ok());
  const Measurement& m = data->measurements.at(0);
  const std::string row = data->campaigns[m.campaign].id + "," +
                          StandName(m.stand) + "," + PositionName(m.position) +
                          "," + m.roll_id + "," +
                          FormatTimestamp(m.measured_at);
  const std::string header =
      "campaign_id,stand,position,roll_id,measured_at,x_mm,wear_um\n";
  std::ofstream(dir / "data/profiles.csv")
      << header << row << ",0,12.5\n" << row << ",100,13\n";
  EXPECT_EQ(RunRollwear({"import", "--db", dir / "x.db", dir / "data"}, &output),
            0)
      << output;
  EXPECT_NE(output.find("profiles.csv: 2 profile point(s) in 1 new and 0 "
                        "unchanged profile(s)"),
            std::string::npos)
      << output;
  EXPECT_EQ(RunRollwear({"import", "--db", dir / "x.db", dir / "data"}, &output),
            0)
      << output;
  EXPECT_NE(output.find("profiles 0 new, 1 unchanged"), std::string::npos)
      << output;
  ASSERT_EQ(RunRollwear({"export", "--db", dir / "x.db", "--out", dir / "out"},
                        &output),
            0)
      << output;
  StatusOr<Dataset> back = ReadDataset(dir / "out");
  ASSERT_TRUE(back.ok()) << back.status().message();
  ASSERT_EQ(back->profile_points.size(), 2u);
  EXPECT_EQ(back->profile_points[0].x_mm, 0);
  EXPECT_EQ(back->profile_points[0].wear_um, 12.5);
  EXPECT_EQ(back->profile_points[1].x_mm, 100);
  EXPECT_EQ(back->profile_points[1].wear_um, 13);
  EXPECT_EQ(back->profile_points[1].roll_id, m.roll_id);
  // Other points under the same key: a conflict, and nothing imported.
  std::ofstream(dir / "data/profiles.csv")
      << header << row << ",0,12.5\n" << row << ",100,14\n";
  EXPECT_EQ(RunRollwear({"import", "--db", dir / "x.db", dir / "data"}, &output),
            1);
  EXPECT_NE(output.find("profiles.csv:2 campaign_id: the profile of"),
            std::string::npos)
      << output;
  std::ofstream(dir / "data/profiles.csv")
      << header << row << ",0,12.5\n" << row << ",0,13\n";
  EXPECT_EQ(
      RunRollwear({"import", "--db", dir / "y.db", dir / "data"}, &output), 1);
  EXPECT_NE(output.find("profiles.csv:3:6 x_mm: duplicate key"),
            std::string::npos)
      << output;
  EXPECT_NE(output.find("nothing imported"), std::string::npos) << output;
}

}  // namespace
}  // namespace rollwear::e2e
