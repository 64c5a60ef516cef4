// Disk-full and read-only database under the real HTTP server: a MillStore
// on a real SQLite file (through fault_vfs.h, which makes the file writes
// fail as ENOSPC / EROFS would), the Router and HttpServer on a loopback
// port, and an HTTP client. Writes must be answered 503 "unavailable" with
// a clear message while GETs keep being served; a failed write must leave
// nothing behind (posting it again later is 201, not 200); the daemon must
// resume by itself once writes work again; and the in-memory state must
// equal what a fresh process reads back from the file.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <memory>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sqlite3.h>

#include "api/http_client.h"
#include "api/http_server.h"
#include "api/router.h"
#include "engine/wear_prediction.h"
#include "storage/mill_store.h"
#include "storage/sqlite_db.h"
#include "tests/api/api_test_util.h"
#include "tests/e2e/e2e_util.h"
#include "tests/e2e/fault_vfs.h"

namespace rollwear::e2e {
namespace {

using api::testing::CoilBody;
using api::testing::MeasurementBody;
using api::testing::RollChangeBody;

// Coil k of campaign C1, rolled k seconds after 08:00.
json Coil(int k) {
  char at[32];
  std::snprintf(at, sizeof(at), "2026-03-01T08:%02d:%02dZ", k / 60, k % 60);
  return CoilBody("K" + std::to_string(k), "C1", k, at);
}

class FaultTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(InstallFaultVfs());
    SetFaultMode(FaultMode::kNone);
    Start();
    ASSERT_EQ(
        Post("/v1/roll-changes", RollChangeBody("C1", "2026-03-01T06:00:00Z")),
        201);
    for (int k = 1; k <= 5; ++k) ASSERT_EQ(PostCoil(k), 201) << k;
  }
  void TearDown() override {
    SetFaultMode(FaultMode::kNone);
    Stop();
  }

  void Start() {
    StatusOr<std::unique_ptr<storage::MillStore>> store =
        engine::OpenStore(dir_ / "fault.db");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(store).value();
    router_ = std::make_unique<api::Router>(store_.get(), api::ApiOptions());
    server_ = std::make_unique<api::HttpServer>(router_.get(),
                                                api::HttpServerOptions());
    ASSERT_TRUE(server_->Start().ok());
    url_ = "http://127.0.0.1:" + std::to_string(server_->port());
  }
  void Stop() {
    server_.reset();
    router_.reset();
    store_.reset();
  }

  int Post(const std::string& path, const json& body, json* answer = nullptr) {
    api::HttpClient client(url_);
    const api::HttpResult r = client.Post(path, body.dump());
    if (answer != nullptr) *answer = json::parse(r.body, nullptr, false);
    return r.status;
  }
  int PostCoil(int k, json* answer = nullptr) {
    return Post("/v1/coils", Coil(k), answer);
  }
  // GET /v1/wear plus the stored counts: the state a failed write must not
  // change.
  std::string State() {
    json wear;
    EXPECT_EQ(HttpGet(url_, "/v1/wear", &wear), 200);
    const std::map<std::string, double> m = ScrapeMetrics(url_);
    return wear.dump() + "|" + std::to_string(m.at("rollwear_coils_stored")) +
           "," + std::to_string(m.at("rollwear_campaigns_stored")) + "," +
           std::to_string(m.at("rollwear_measurements_stored"));
  }
  // A 503 with the contract's error body naming the cause.
  static void ExpectUnavailable(int status, const json& answer,
                                const std::string& cause) {
    EXPECT_EQ(status, 503) << answer.dump();
    ASSERT_TRUE(answer.is_object() && answer.contains("error"))
        << answer.dump();
    EXPECT_EQ(answer["error"].value("code", ""), "unavailable");
    const std::string message = answer["error"].value("message", "");
    EXPECT_NE(message.find("database not writable"), std::string::npos)
        << message;
    EXPECT_NE(message.find(cause), std::string::npos) << message;
    EXPECT_TRUE(answer["error"].contains("field"));
  }
  // The live state equals what a fresh store reads back from the file.
  void ExpectStateMatchesFile() {
    const std::string live = State();
    Stop();
    Start();
    EXPECT_EQ(State(), live) << "in-memory state diverged from the database";
  }

  TempDir dir_;
  std::unique_ptr<storage::MillStore> store_;
  std::unique_ptr<api::Router> router_;
  std::unique_ptr<api::HttpServer> server_;
  std::string url_;
};

TEST_F(FaultTest, DiskFullAnswers503KeepsServingReadsAndResumes) {
  const std::string before = State();
  SetFaultMode(FaultMode::kDiskFull);
  json answer;
  ExpectUnavailable(PostCoil(6, &answer), answer, "full");
  ExpectUnavailable(Post("/v1/campaigns/C1/end",
                         json{{"ended_at", "2026-03-01T14:00:00Z"}}, &answer),
                    answer, "full");
  // Reads keep working and show nothing of the failed writes.
  EXPECT_EQ(State(), before);
  json health;
  EXPECT_EQ(HttpGet(url_, "/healthz", &health), 200) << health.dump();
  // Idempotent repeats of stored writes need no disk: still 200.
  EXPECT_EQ(PostCoil(3), 200);

  SetFaultMode(FaultMode::kNone);
  // Nothing of the failed coil was stored: it is created now.
  EXPECT_EQ(PostCoil(6), 201);
  EXPECT_EQ(PostCoil(7), 201);
  // A measurement needs its campaign ended (a running one is 422 before any
  // disk write): end C1, then fill the disk again.
  ASSERT_EQ(
      Post("/v1/campaigns/C1/end", json{{"ended_at", "2026-03-01T14:00:00Z"}}),
      200);
  const std::string ended = State();
  SetFaultMode(FaultMode::kDiskFull);
  ExpectUnavailable(
      Post("/v1/measurements",
           MeasurementBody("C1", "F6", "top", "R-F6-top", 12.5), &answer),
      answer, "full");
  EXPECT_EQ(State(), ended);
  SetFaultMode(FaultMode::kNone);
  EXPECT_EQ(Post("/v1/measurements",
                 MeasurementBody("C1", "F6", "top", "R-F6-top", 12.5)),
            201);
  EXPECT_NE(State(), before);
  ExpectStateMatchesFile();
}

TEST_F(FaultTest, ReadOnlyFileSystemAnswers503AndResumes) {
  const std::string before = State();
  SetFaultMode(FaultMode::kReadOnly);
  json answer;
  ExpectUnavailable(PostCoil(6, &answer), answer, "I/O error");
  ExpectUnavailable(Post("/v1/roll-changes",
                         RollChangeBody("C2", "2026-03-01T15:00:00Z"), &answer),
                    answer, "I/O error");
  EXPECT_EQ(State(), before);
  SetFaultMode(FaultMode::kNone);
  EXPECT_EQ(PostCoil(6), 201);
  ExpectStateMatchesFile();
}

// A read-only database file (SQLITE_READONLY from SQLite itself, not from
// the file system) is the same 503 class: storage maps it to Unavailable.
TEST_F(FaultTest, ReadOnlyConnectionIsUnavailable) {
  storage::DbOptions o;
  o.read_only = true;
  StatusOr<std::unique_ptr<storage::Db>> db =
      storage::Db::Open(dir_ / "fault.db", o);
  ASSERT_TRUE(db.ok()) << db.status().ToString();
  const Status s = (*db)->Exec("DELETE FROM coils");
  EXPECT_EQ(s.code(), StatusCode::kUnavailable) << s.ToString();
  EXPECT_NE(s.message().find("read-only"), std::string::npos) << s.ToString();
  EXPECT_EQ(api::HttpStatusFor(s.code()), 503);
}

// Concurrent posters while the disk fills and frees again: every write is
// either acknowledged (and then stored) or refused with 503 (and then not
// stored, so a later repeat creates it); at the end the live state equals
// the file's.
TEST_F(FaultTest, ConcurrentWritesWhileDiskFlapsNeverDiverge) {
  constexpr int kClients = 4;
  constexpr int kCoilsPerClient = 40;
  std::atomic<bool> done{false};
  std::thread flapper([&] {
    bool full = false;
    while (!done.load()) {
      full = !full;
      SetFaultMode(full ? FaultMode::kDiskFull : FaultMode::kNone);
      std::this_thread::sleep_for(std::chrono::milliseconds(7));
    }
    SetFaultMode(FaultMode::kNone);
  });
  std::vector<std::vector<int>> acked(kClients), refused(kClients);
  std::vector<std::thread> clients;
  for (int c = 0; c < kClients; ++c) {
    clients.emplace_back([&, c] {
      api::HttpClient client(url_);
      for (int i = 0; i < kCoilsPerClient; ++i) {
        const int k = 100 + c * kCoilsPerClient + i;
        const api::HttpResult r = client.Post("/v1/coils", Coil(k).dump());
        if (r.status == 201) {
          acked[c].push_back(k);
        } else if (r.status == 503) {
          refused[c].push_back(k);
        } else {
          ADD_FAILURE() << "coil " << k << ": " << r.status << " " << r.body
                        << r.error;
        }
      }
    });
  }
  for (std::thread& t : clients) t.join();
  done = true;
  flapper.join();

  int n_acked = 0, n_refused = 0;
  for (int c = 0; c < kClients; ++c) {
    n_acked += static_cast<int>(acked[c].size());
    n_refused += static_cast<int>(refused[c].size());
  }
  std::printf(
      "flapping disk: %d coils acknowledged, %d refused, %ld writes "
      "faulted\n",
      n_acked, n_refused, FaultedWrites());
  EXPECT_GT(n_refused, 0) << "the disk never filled during a write";
  ExpectStateMatchesFile();
  const std::map<std::string, double> m = ScrapeMetrics(url_);
  EXPECT_EQ(m.at("rollwear_coils_stored"), 5.0 + n_acked);
  // Acknowledged coils are stored (repeat: 200); refused ones are not
  // (repeat: 201).
  for (int c = 0; c < kClients; ++c) {
    for (int k : acked[c]) EXPECT_EQ(PostCoil(k), 200) << k;
    for (int k : refused[c]) EXPECT_EQ(PostCoil(k), 201) << k;
  }
  ExpectStateMatchesFile();
}

}  // namespace
}  // namespace rollwear::e2e
