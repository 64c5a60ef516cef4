// The common footing through the binary: `calibrate --split FILE
// --predictions FILE` (plain, --per-roll and --terms) and `ann --split FILE
// --predictions FILE` on a split that puts the rolls of one campaign in
// both sets, and a bad split file refused with its line.
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/dataset/dataset_io.h"
#include "tests/e2e/e2e_util.h"

namespace rollwear::e2e {
namespace {

struct PredictionCsv {
  int rows = 0, train = 0, validation = 0;
  int without_interval = 0;  // rows with lo_um and hi_um empty
  double gap_val_um = 0;
  bool intervals_hold_predictions = true;
  std::map<std::string, std::string> set_of;  // "campaign/F6/top" -> set
};

PredictionCsv ReadPredictions(const std::string& path) {
  PredictionCsv p;
  std::istringstream in(ReadFile(path));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line,
            "campaign_id,stand,position,roll_id,set,measured_um,predicted_um,"
            "lo_um,hi_um");
  double sum = 0;
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    if (!line.empty() && line.back() == ',') f.emplace_back();  // getline drops it
    EXPECT_EQ(f.size(), 9u) << line;
    if (f.size() != 9) continue;
    ++p.rows;
    p.set_of[f[0] + "/" + f[1] + "/" + f[2]] = f[4];
    const double measured = std::stod(f[5]), predicted = std::stod(f[6]);
    if (f[7].empty() && f[8].empty()) {
      ++p.without_interval;
    } else {
      p.intervals_hold_predictions = p.intervals_hold_predictions &&
                                     std::stod(f[7]) < predicted &&
                                     predicted < std::stod(f[8]);
    }
    if (f[4] == "validation") {
      ++p.validation;
      sum += std::abs(measured - predicted);
    } else {
      ++p.train;
    }
  }
  p.gap_val_um = p.validation > 0 ? sum / p.validation : 0;
  return p;
}

TEST(CliSplitTest, AGivenSplitIsUsedReadingByReadingAndEachReadingIsWritten) {
  TempDir dir;
  std::string out, error;
  ASSERT_TRUE(Simulate(dir / "data", 60, 9, &error)) << error;
  StatusOr<Dataset> data = ReadDataset(dir / "data");
  ASSERT_TRUE(data.ok());
  // F6 rolls train, F7 rolls validation, one reading left out.
  std::map<std::string, std::string> expected;
  {
    std::ofstream split(dir / "split.csv");
    split << "campaign_id,stand,position,set\n";
    for (size_t i = 1; i < data->measurements.size(); ++i) {
      const Measurement& m = data->measurements[i];
      const std::string set = m.stand == 6 ? "train" : "validation";
      const std::string key = data->campaigns[m.campaign].id + "," +
                              StandName(m.stand) + "," +
                              PositionName(m.position);
      split << key << "," << set << "\n";
      expected[data->campaigns[m.campaign].id + "/" + StandName(m.stand) + "/" +
               PositionName(m.position)] = set;
    }
  }
  for (const std::vector<std::string>& extra :
       {std::vector<std::string>{}, std::vector<std::string>{"--per-roll"}}) {
    std::vector<std::string> args = {"calibrate",
                                     "--data",
                                     dir / "data",
                                     "--split",
                                     dir / "split.csv",
                                     "--predictions",
                                     dir / "p.csv",
                                     "--json",
                                     dir / "c.json",
                                     "--option",
                                     "3"};
    args.insert(args.end(), extra.begin(), extra.end());
    RunRollwear(args, &out);
    EXPECT_NE(out.find("measured readings not listed, not used"),
              std::string::npos)
        << out;
    const PredictionCsv p = ReadPredictions(dir / "p.csv");
    EXPECT_EQ(p.set_of, expected) << "every listed reading once, in its set";
    EXPECT_TRUE(p.intervals_hold_predictions);
    EXPECT_EQ(p.without_interval, 0);
    const nlohmann::json j = nlohmann::json::parse(ReadFile(dir / "c.json"));
    EXPECT_EQ(j["n_val"].get<int>(), p.validation);
    EXPECT_NEAR(j["gap_val_um"].get<double>(), p.gap_val_um, 0.02) << out;
    EXPECT_TRUE(j.contains("identification")) << j.dump();
  }
  // --terms on the same split (a model without terms refitted): same rows.
  { std::ofstream(dir / "none.json") << R"({"terms":[]})"; }
  ASSERT_EQ(RunRollwear({"calibrate", "--data", dir / "data", "--terms",
                         dir / "none.json", "--split", dir / "split.csv",
                         "--predictions", dir / "t.csv"},
                        &out),
            0)
      << out;
  EXPECT_EQ(ReadPredictions(dir / "t.csv").set_of, expected);

  // The network on the same split (one member, a few epochs: the rows, not
  // the network's quality, are checked): every reading once, in its set,
  // without an interval, and the validation gap of its JSON recomputed
  // from the rows.
  ASSERT_EQ(RunRollwear({"ann", "--data", dir / "data", "--split",
                         dir / "split.csv", "--predictions", dir / "a.csv",
                         "--json", dir / "a.json", "--seeds", "1",
                         "--max-epochs", "3", "--threads", "1"},
                        &out),
            0)
      << out;
  const PredictionCsv a = ReadPredictions(dir / "a.csv");
  EXPECT_EQ(a.set_of, expected);
  EXPECT_EQ(a.without_interval, a.rows);
  const nlohmann::json aj = nlohmann::json::parse(ReadFile(dir / "a.json"));
  EXPECT_EQ(aj["n_val"].get<int>(), a.validation);
  EXPECT_NEAR(aj["ann"]["gap_val_um"].get<double>(), a.gap_val_um, 0.02) << out;

  // A bad set is refused with the file and line.
  {
    std::ofstream(dir / "bad.csv")
        << "campaign_id,stand,position,set\nC0001,F6,top,dev\n";
  }
  EXPECT_EQ(RunRollwear({"calibrate", "--data", dir / "data", "--split",
                         dir / "bad.csv"},
                        &out),
            1);
  EXPECT_NE(out.find("bad.csv:2: set: must be train or validation, got 'dev'"),
            std::string::npos)
      << out;
}

}  // namespace
}  // namespace rollwear::e2e
