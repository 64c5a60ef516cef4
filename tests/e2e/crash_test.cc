// The kill -9 test: during a replay the daemon is killed with SIGKILL five
// times at random moments and restarted on the same port and database;
// `rollwear replay` re-posts whatever was not acknowledged (connection
// errors are retried; idempotency keys make repeats harmless). The final
// state - GET /v1/wear and the stored counts - must equal an uninterrupted
// run of the same data: nothing acknowledged is lost, nothing is counted
// twice.
#include <chrono>
#include <cstdlib>
#include <map>
#include <random>
#include <thread>

#include <gtest/gtest.h>

#include "core/dataset/dataset_io.h"
#include "tests/e2e/e2e_util.h"

namespace rollwear::e2e {
namespace {

constexpr int kKills = 5;

struct FinalState {
  json wear;
  std::map<std::string, double> metrics;
};

FinalState Capture(const std::string& url) {
  FinalState s;
  HttpGet(url, "/v1/wear", &s.wear);
  s.metrics = ScrapeMetrics(url);
  return s;
}

TEST(CrashTest, KillNineDuringReplayLosesNothingAndCountsNothingTwice) {
  TempDir dir;
  std::string error;
  ASSERT_TRUE(Simulate(dir / "data", 24, 11, &error)) << error;
  StatusOr<Dataset> data = ReadDataset(dir / "data");
  ASSERT_TRUE(data.ok()) << data.status().ToString();

  // Reference: an uninterrupted run.
  FinalState reference;
  {
    Daemon daemon(dir / "reference.db", dir / "reference.log");
    ASSERT_TRUE(daemon.Start(&error)) << error;
    std::string output;
    ASSERT_EQ(
        RunRollwear({"replay", "--data", dir / "data", "--url", daemon.url(),
                     "--clients", "4", "--leave-last-open", "--quiet"},
                    &output),
        0)
        << output;
    reference = Capture(daemon.url());
    EXPECT_EQ(daemon.Terminate(), 0);
  }

  // The same data, paced to last about 12 s, with five SIGKILLs within the
  // first ~7 s.
  UnixSeconds first = INT64_MAX, last = 0;
  for (const Campaign& c : data->campaigns) {
    first = std::min(first, c.started_at);
    last = std::max(last, c.ended_at);
  }
  for (const Measurement& m : data->measurements) {
    last = std::max(last, m.measured_at);
  }
  const double speed = static_cast<double>(last - first) / 12.0;
  Daemon daemon(dir / "crash.db", dir / "crash.log");
  ASSERT_TRUE(daemon.Start(&error)) << error;
  const int port = daemon.port();
  Subprocess replay(
      {ROLLWEAR_BINARY, "replay", "--data", dir / "data", "--url", daemon.url(),
       "--clients", "4", "--speed", std::to_string(speed), "--retry-for", "120",
       "--leave-last-open"},
      dir / "replay.log");
  std::mt19937 rng(20260301);
  std::uniform_int_distribution<int> wait_ms(200, 800);
  // The first kill waits for the replay's first stored coil (a sanitized
  // replay may take longer to make its first request than the first wait:
  // it then met a refused connection before any answer and stopped).
  for (int waited_ms = 0; waited_ms < 60'000; waited_ms += 50) {
    const std::map<std::string, double> m = ScrapeMetrics(daemon.url());
    auto it = m.find("rollwear_coils_stored");
    if (it != m.end() && it->second > 0) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  int kills_during_replay = 0;
  std::unique_ptr<Daemon> current;
  Daemon* running = &daemon;
  for (int i = 0; i < kKills; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms(rng)));
    if (replay.Running()) ++kills_during_replay;
    running->Kill9();
    std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms(rng) / 10));
    current =
        std::make_unique<Daemon>(dir / "crash.db", dir / "crash.log", port);
    ASSERT_TRUE(current->Start(&error)) << error;
    running = current.get();
  }
  const int replay_code = replay.Wait(300);
  EXPECT_EQ(replay_code, 0) << ReadFile(dir / "replay.log");
  EXPECT_EQ(kills_during_replay, kKills)
      << "the replay finished before all kills; slow it down";

  const FinalState crashed = Capture(running->url());
  for (const char* name : {"rollwear_coils_stored", "rollwear_campaigns_stored",
                           "rollwear_measurements_stored"}) {
    ASSERT_TRUE(crashed.metrics.count(name)) << name;
    EXPECT_EQ(crashed.metrics.at(name), reference.metrics.at(name)) << name;
  }
  EXPECT_EQ(crashed.metrics.at("rollwear_coils_stored"),
            static_cast<double>(data->coil_ids.size()));
  ASSERT_EQ(crashed.wear["positions"].size(), 4u) << crashed.wear.dump();
  ASSERT_EQ(crashed.wear["positions"].size(),
            reference.wear["positions"].size());
  for (size_t i = 0; i < reference.wear["positions"].size(); ++i) {
    const json& a = crashed.wear["positions"][i];
    const json& b = reference.wear["positions"][i];
    EXPECT_EQ(a["roll_id"], b["roll_id"]);
    EXPECT_EQ(a["campaign_id"], b["campaign_id"]);
    EXPECT_EQ(a["coils"], b["coils"]);
    EXPECT_NEAR(a["rolled_length_m"].get<double>(),
                b["rolled_length_m"].get<double>(), 1e-6);
    EXPECT_NEAR(a["predicted_wear_um"].get<double>(),
                b["predicted_wear_um"].get<double>(),
                1e-9 * std::max(1.0, b["predicted_wear_um"].get<double>()));
  }
  const std::string log = ReadFile(dir / "replay.log");
  EXPECT_NE(log.find(" 0 conflicts, 0 errors"), std::string::npos) << log;
  // The kills did cut requests off: the replay had to retry.
  const size_t at = log.rfind(" errors, ");
  ASSERT_NE(at, std::string::npos) << log;
  EXPECT_GT(std::strtol(log.c_str() + at + 9, nullptr, 10), 0) << log;

  // Every coil is stored exactly as sent: posting them all again is
  // answered 200 each (a lost one would be 201, a damaged one 409).
  std::string output;
  EXPECT_EQ(
      RunRollwear({"replay", "--data", dir / "data", "--url", running->url(),
                   "--clients", "4", "--leave-last-open", "--quiet"},
                  &output),
      0)
      << output;
  const std::string n = std::to_string(data->coil_ids.size());
  EXPECT_NE(output.find("replay: " + n + " coils (" + n + " repeated)"),
            std::string::npos)
      << output;
  EXPECT_EQ(running->Terminate(), 0);
}

}  // namespace
}  // namespace rollwear::e2e
