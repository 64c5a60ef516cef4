// Crash-consistency soak: a dataset is posted by four concurrent writer
// clients (plus a reader polling GET /v1/wear) while the daemon is killed
// with SIGKILL at random moments and restarted on the same port and
// database. Writers retry until they get an answer (every POST has an
// idempotency key). At the end:
//   - acknowledged coils lost: every coil that was ever answered 2xx must be
//     in the database (must be 0);
//   - state diff: the stored dataset (exported, canonically sorted), the
//     counts and GET /v1/wear must equal those of an uninterrupted run of
//     the same data (must be empty).
// Kills: ROLLWEAR_SOAK_KILLS (default 20, what CTest and CI run). The full
// soak of docs/development.md is
//   ROLLWEAR_SOAK_KILLS=100 ./build/tests/e2e_test --gtest_filter='Soak*'
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "api/http_client.h"
#include "api/request_encode.h"
#include "core/dataset/dataset_io.h"
#include "engine/wear_prediction.h"
#include "storage/mill_store.h"
#include "tests/e2e/e2e_util.h"

namespace rollwear::e2e {
namespace {

constexpr int kWriters = 4;

int SoakKills() {
  const char* env = std::getenv("ROLLWEAR_SOAK_KILLS");
  const int n = env != nullptr ? std::atoi(env) : 0;
  return n > 0 ? n : 20;
}

// The dataset as request bodies, in the order a mill produces them.
struct Plan {
  std::vector<std::string> roll_changes;               // by campaign
  std::vector<std::vector<std::string>> coils;         // [campaign] bodies
  std::vector<std::vector<std::string>> coil_ids;      // [campaign]
  std::vector<std::string> ends;                       // by campaign
  std::vector<std::vector<std::string>> measurements;  // [campaign]
  std::vector<std::string> campaign_ids;
  size_t num_coils = 0;
};

Plan MakePlan(const Dataset& d) {
  Plan p;
  const size_t n = d.campaigns.size();
  p.coils.resize(n);
  p.coil_ids.resize(n);
  p.measurements.resize(n);
  // One pass over the passes and mounts (per-coil scans would be
  // quadratic).
  std::vector<std::vector<int>> passes_of(d.coil_ids.size());
  for (size_t i = 0; i < d.passes.size(); ++i) {
    passes_of[d.passes[i].coil].push_back(static_cast<int>(i));
  }
  std::vector<std::vector<int>> mounts_of(n);
  for (size_t i = 0; i < d.mounts.size(); ++i) {
    mounts_of[d.mounts[i].campaign].push_back(static_cast<int>(i));
  }
  for (size_t c = 0; c < n; ++c) {
    const int ci = static_cast<int>(c);
    p.campaign_ids.push_back(d.campaigns[c].id);
    p.roll_changes.push_back(api::RollChangeRequest(d, ci, mounts_of[c]));
    for (int k : CoilsOf(d, ci)) {
      p.coils[c].push_back(api::CoilRequest(d, passes_of[k]));
      p.coil_ids[c].push_back(d.coil_ids[k]);
    }
    p.num_coils += p.coils[c].size();
    p.ends.push_back(api::CampaignEndRequest(d, ci));
  }
  for (size_t i = 0; i < d.measurements.size(); ++i) {
    p.measurements[d.measurements[i].campaign].push_back(
        api::MeasurementRequest(d, static_cast<int>(i)));
  }
  return p;
}

// Posts until answered; true on 2xx. Connection errors (the daemon is
// down) and 503 are retried for up to two minutes.
bool PostUntilAnswered(api::HttpClient* client, const std::string& path,
                       const std::string& body, std::string* error) {
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::seconds(120);
  std::string last;
  while (std::chrono::steady_clock::now() < deadline) {
    const api::HttpResult r = client->Post(path, body);
    if (r.status >= 200 && r.status < 300) return true;
    if (r.answered() && r.status != 503) {
      *error = path + ": " + std::to_string(r.status) + " " + r.body;
      return false;
    }
    last = std::to_string(r.status) + " " + r.body + r.error;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  *error = path + ": no 2xx for 120 s; last answer: " + last;
  return false;
}

// Posts the whole plan: per campaign the roll change, its coils on
// kWriters concurrent clients (paced by `coil_delay`), the campaign end
// and its measurements; the last campaign stays open. Every coil answered
// 2xx is added to *acked.
bool Drive(const std::string& url, const Plan& plan,
           std::chrono::microseconds coil_delay, std::set<std::string>* acked,
           std::mutex* acked_mu, std::string* error) {
  api::HttpClient control(url);
  const size_t n = plan.roll_changes.size();
  for (size_t c = 0; c < n; ++c) {
    if (!PostUntilAnswered(&control, "/v1/roll-changes", plan.roll_changes[c],
                           error)) {
      return false;
    }
    std::atomic<size_t> next{0};
    std::atomic<bool> failed{false};
    std::mutex error_mu;
    std::vector<std::thread> writers;
    for (int w = 0; w < kWriters; ++w) {
      writers.emplace_back([&] {
        api::HttpClient client(url);
        for (size_t i = next++; i < plan.coils[c].size() && !failed;
             i = next++) {
          std::string e;
          if (!PostUntilAnswered(&client, "/v1/coils", plan.coils[c][i], &e)) {
            std::lock_guard<std::mutex> lock(error_mu);
            *error = e;
            failed = true;
            return;
          }
          {
            std::lock_guard<std::mutex> lock(*acked_mu);
            acked->insert(plan.coil_ids[c][i]);
          }
          std::this_thread::sleep_for(coil_delay);
        }
      });
    }
    for (std::thread& t : writers) t.join();
    if (failed) return false;
    if (c + 1 == n) break;  // leave the last campaign open
    if (!PostUntilAnswered(&control,
                           "/v1/campaigns/" + plan.campaign_ids[c] + "/end",
                           plan.ends[c], error)) {
      return false;
    }
    for (const std::string& m : plan.measurements[c]) {
      if (!PostUntilAnswered(&control, "/v1/measurements", m, error)) {
        return false;
      }
    }
  }
  return true;
}

// Everything stored in `db`, schema-independent: the exported dataset's
// four CSV files with their rows sorted (insertion order differs between
// runs with concurrent clients; content must not).
std::string CanonicalDump(const std::string& db, const std::string& out_dir,
                          std::set<std::string>* coil_ids) {
  StatusOr<std::unique_ptr<storage::MillStore>> store = engine::OpenStore(db);
  if (!store.ok()) return "open failed: " + store.status().ToString();
  StatusOr<Dataset> data = (*store)->ExportDataset();
  if (!data.ok()) return "export failed: " + data.status().ToString();
  coil_ids->insert(data->coil_ids.begin(), data->coil_ids.end());
  const Status written = WriteDataset(*data, out_dir);
  if (!written.ok()) return "write failed: " + written.ToString();
  std::string dump;
  for (const char* file :
       {"campaigns.csv", "mounts.csv", "coils.csv", "measurements.csv"}) {
    std::istringstream in(ReadFile(out_dir + "/" + file));
    std::string header, line;
    std::getline(in, header);
    std::vector<std::string> rows;
    while (std::getline(in, line)) rows.push_back(line);
    std::sort(rows.begin(), rows.end());
    dump += std::string("== ") + file + "\n" + header + "\n";
    for (const std::string& r : rows) dump += r + "\n";
  }
  return dump;
}

// Lines of `a` and `b` that differ, at most `max` of them.
std::string Diff(const std::string& a, const std::string& b, int max = 10) {
  std::istringstream x(a), y(b);
  std::string l, r, out;
  int shown = 0, line = 0;
  while (shown < max && (std::getline(x, l) ? 1 : (l.clear(), 0)) |
                            (std::getline(y, r) ? 1 : (r.clear(), 0))) {
    ++line;
    if (l != r) {
      out += "line " + std::to_string(line) + ": uninterrupted '" + l +
             "' vs killed '" + r + "'\n";
      ++shown;
    }
  }
  return out;
}

// Differences between two GET /v1/wear answers. Concurrent writers commit
// coils in a different order in every run, so sums differ in the last bits:
// numbers are compared to 1e-9 relative, everything else exactly.
std::string WearDiff(const json& want, const json& got) {
  if (!want.contains("positions") || !got.contains("positions") ||
      want["positions"].size() != got["positions"].size()) {
    return "positions differ: " + want.dump() + " vs " + got.dump();
  }
  std::string out;
  for (size_t i = 0; i < want["positions"].size(); ++i) {
    const json& a = want["positions"][i];
    const json& b = got["positions"][i];
    for (const char* key :
         {"stand", "position", "roll_id", "campaign_id", "coils"}) {
      if (a.value(key, json()) != b.value(key, json())) {
        out += std::string(key) + " of position " + std::to_string(i) + "\n";
      }
    }
    for (const char* key : {"rolled_length_m", "predicted_wear_um"}) {
      const double x = a.value(key, 0.0), y = b.value(key, 0.0);
      if (std::abs(x - y) > 1e-9 * std::max(1.0, std::abs(x))) {
        out += std::string(key) + " of position " + std::to_string(i) + ": " +
               std::to_string(x) + " vs " + std::to_string(y) + "\n";
      }
    }
  }
  return out;
}

TEST(SoakTest, KillNineDuringConcurrentPostsLosesNoAcknowledgedCoil) {
  const int kills = SoakKills();
  TempDir dir;
  std::string error;
  // About 40 coils per kill at the pace below, so the load outlasts them.
  const int campaigns = std::max(8, kills / 2);
  ASSERT_TRUE(Simulate(dir / "data", campaigns, 7, &error)) << error;
  StatusOr<Dataset> data = ReadDataset(dir / "data");
  ASSERT_TRUE(data.ok()) << data.status().ToString();
  const Plan plan = MakePlan(*data);

  // Reference: the same requests, no kills.
  json reference_wear;
  std::set<std::string> unused;
  std::mutex unused_mu;
  {
    Daemon daemon(dir / "reference.db", dir / "reference.log");
    ASSERT_TRUE(daemon.Start(&error)) << error;
    ASSERT_TRUE(Drive(daemon.url(), plan, std::chrono::microseconds(0), &unused,
                      &unused_mu, &error))
        << error;
    ASSERT_EQ(HttpGet(daemon.url(), "/v1/wear", &reference_wear), 200);
    ASSERT_EQ(daemon.Terminate(), 0);
  }

  // Paced so that the load lasts about kills x 0.45 s.
  const double seconds = kills * 0.45;
  const auto coil_delay = std::chrono::microseconds(static_cast<int64_t>(
      seconds * 1e6 * kWriters / static_cast<double>(plan.num_coils)));
  auto daemon = std::make_unique<Daemon>(dir / "soak.db", dir / "soak.log");
  ASSERT_TRUE(daemon->Start(&error)) << error;
  const int port = daemon->port();
  const std::string url = daemon->url();

  std::set<std::string> acked;
  std::mutex acked_mu;
  std::atomic<bool> driving{true};
  bool drove = false;
  std::string drive_error;
  std::thread driver([&] {
    drove = Drive(url, plan, coil_delay, &acked, &acked_mu, &drive_error);
    driving = false;
  });
  std::atomic<long> reads{0};
  std::thread reader([&] {
    while (driving) {
      json wear;
      if (HttpGet(url, "/v1/wear", &wear) == 200) ++reads;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  });

  std::mt19937 rng(20260301);
  std::uniform_int_distribution<int> wait_ms(100, 600);
  int kills_under_load = 0, restarts_failed = 0;
  for (int i = 0; i < kills; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms(rng)));
    if (driving) ++kills_under_load;
    daemon->Kill9();
    daemon = std::make_unique<Daemon>(dir / "soak.db", dir / "soak.log", port);
    // The port may still be held for a moment by the killed process.
    std::string e;
    bool started = false;
    for (int attempt = 0; attempt < 20 && !started; ++attempt) {
      started = daemon->Start(&e);
      if (!started) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        daemon =
            std::make_unique<Daemon>(dir / "soak.db", dir / "soak.log", port);
      }
    }
    if (!started) {
      ++restarts_failed;
      ADD_FAILURE() << "restart " << i << " failed: " << e;
      break;
    }
  }
  driver.join();
  reader.join();
  // A daemon that died by itself (a crash, a sanitizer report) is a
  // failure, shown with the end of its log.
  const std::string daemon_log = ReadFile(dir / "soak.log");
  const bool sanitizer_report =
      daemon_log.find("Sanitizer") != std::string::npos ||
      daemon_log.find("runtime error:") != std::string::npos;
  const std::string log_tail = daemon_log.substr(
      daemon_log.size() > 6000 ? daemon_log.size() - 6000 : 0);
  size_t report = daemon_log.find("==================\nWARNING:");
  if (report == std::string::npos) report = daemon_log.find("==ERROR:");
  EXPECT_FALSE(sanitizer_report)
      << (report != std::string::npos ? daemon_log.substr(report, 12000)
                                      : log_tail);
  ASSERT_TRUE(drove) << drive_error
                     << "\ndaemon running: " << daemon->process()->Running()
                     << "\n"
                     << log_tail;
  json soak_wear;
  ASSERT_EQ(HttpGet(url, "/v1/wear", &soak_wear), 200);
  ASSERT_EQ(daemon->Terminate(), 0);

  std::set<std::string> stored_reference, stored_soak;
  const std::string want = CanonicalDump(
      dir / "reference.db", dir / "export_reference", &stored_reference);
  const std::string got =
      CanonicalDump(dir / "soak.db", dir / "export_soak", &stored_soak);
  int lost = 0;
  for (const std::string& id : acked) lost += stored_soak.count(id) == 0;
  const std::string diff =
      Diff(want, got) + WearDiff(reference_wear, soak_wear);
  std::printf(
      "soak: %d kills (%d under load), %zu coils acknowledged, %d lost, "
      "%ld reads served, state diff vs uninterrupted run: %s\n",
      kills, kills_under_load, acked.size(), lost, reads.load(),
      diff.empty() ? "empty" : "NOT EMPTY");
  EXPECT_EQ(lost, 0) << "acknowledged coils lost";
  EXPECT_EQ(acked.size(), plan.num_coils);
  EXPECT_EQ(stored_soak, stored_reference);
  EXPECT_TRUE(diff.empty()) << diff;
  EXPECT_EQ(restarts_failed, 0);
  EXPECT_GE(kills_under_load, kills * 9 / 10)
      << "the load finished before the kills; slow it down";
}

}  // namespace
}  // namespace rollwear::e2e
