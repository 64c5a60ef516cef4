// kill -9 after acknowledged profile posts (docs/api.md, POST /v1/profiles):
// every profile the daemon answered 201 is complete in the database after a
// SIGKILL - posting it again to the restarted daemon is a 200 repeat, and
// export holds every point.
#include <string>

#include <gtest/gtest.h>

#include "core/dataset/dataset_io.h"
#include "core/dataset/timestamp.h"
#include "tests/e2e/e2e_util.h"

namespace rollwear::e2e {
namespace {

json ProfileJson(const Dataset& d, const Measurement& m) {
  json points = json::array();
  for (int k = -4; k <= 4; ++k) {
    points.push_back({{"x_mm", 150.0 * k},
                      {"wear_um", m.wear_center_um * (1 + 0.01 * k * k)}});
  }
  return {{"campaign_id", d.campaigns[m.campaign].id},
          {"stand", StandName(m.stand)},
          {"position", PositionName(m.position)},
          {"roll_id", m.roll_id},
          {"measured_at", FormatTimestamp(m.measured_at)},
          {"points", points}};
}

TEST(ProfileCrashTest, KillNineAfterAcknowledgedProfilesLosesNone) {
  TempDir dir;
  std::string error, output;
  ASSERT_TRUE(Simulate(dir / "data", 4, 3, &error)) << error;
  StatusOr<Dataset> data = ReadDataset(dir / "data");
  ASSERT_TRUE(data.ok());
  ASSERT_EQ(RunRollwear({"import", "--db", dir / "x.db", dir / "data"}, &output),
            0)
      << output;
  const size_t n = data->measurements.size();
  ASSERT_GT(n, 4u);
  {
    Daemon daemon(dir / "x.db", dir / "serve1.log");
    ASSERT_TRUE(daemon.Start(&error)) << error;
    for (const Measurement& m : data->measurements) {
      json answer;
      ASSERT_EQ(HttpPost(daemon.url(), "/v1/profiles",
                         ProfileJson(*data, m).dump(), &answer),
                201)
          << answer.dump();
    }
    daemon.Kill9();  // right after the last acknowledgement
  }
  Daemon daemon(dir / "x.db", dir / "serve2.log");
  ASSERT_TRUE(daemon.Start(&error)) << error;
  for (const Measurement& m : data->measurements) {
    json answer;
    EXPECT_EQ(HttpPost(daemon.url(), "/v1/profiles",
                       ProfileJson(*data, m).dump(), &answer),
              200)
        << answer.dump();
  }
  ASSERT_EQ(RunRollwear({"export", "--db", dir / "x.db", "--out", dir / "out"},
                        &output),
            0)
      << output;
  StatusOr<Dataset> back = ReadDataset(dir / "out");
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_EQ(back->profile_points.size(), 9 * n);
}

}  // namespace
}  // namespace rollwear::e2e
