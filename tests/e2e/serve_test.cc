// End-to-end tests of `rollwear serve` as a subprocess on loopback with a
// real SQLite file: a simulated dataset replayed through the API gives the
// offline batch prediction; concurrent duplicate posts count once; a
// calibration through the API is promoted; SIGTERM stops cleanly; the
// environment's token wins over the config file's.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <fstream>
#include <random>
#include <thread>

#include <gtest/gtest.h>

#include "api/http_client.h"
#include "core/dataset/dataset_io.h"
#include "tests/e2e/e2e_util.h"

namespace rollwear::e2e {
namespace {

void ExpectWearEqualsOffline(const json& wear,
                             const std::map<std::string, double>& offline) {
  const std::map<std::string, double> online = WearByKey(wear);
  ASSERT_FALSE(online.empty()) << wear.dump();
  for (const auto& [key, value] : online) {
    auto it = offline.find(key);
    ASSERT_NE(it, offline.end()) << "no offline prediction for " << key;
    EXPECT_NEAR(value, it->second, 1e-9 * std::max(1.0, std::abs(it->second)))
        << key;
  }
}

class ServeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    ASSERT_TRUE(Simulate(dir_ / "data", 12, 5, &error)) << error;
    StatusOr<Dataset> data = ReadDataset(dir_ / "data");
    ASSERT_TRUE(data.ok()) << data.status().ToString();
    data_ = std::move(data).value();
    daemon_ =
        std::make_unique<Daemon>(dir_ / "rollwear.db", dir_ / "serve.log");
    ASSERT_TRUE(daemon_->Start(&error)) << error;
  }

  // Replays the dataset; the last campaign stays open, so that its rolls
  // are mounted and GET /v1/wear shows them.
  void Replay(int clients) {
    std::string output;
    const int code = RunRollwear(
        {"replay", "--data", dir_ / "data", "--url", daemon_->url(),
         "--clients", std::to_string(clients), "--leave-last-open", "--quiet"},
        &output);
    ASSERT_EQ(code, 0) << output;
    EXPECT_NE(output.find(" 0 conflicts, 0 errors"), std::string::npos)
        << output;
  }

  TempDir dir_;
  Dataset data_;
  std::unique_ptr<Daemon> daemon_;
};

TEST_F(ServeTest, ReplayedWearEqualsTheOfflineBatchPrediction) {
  Replay(8);
  json wear, model;
  ASSERT_EQ(HttpGet(daemon_->url(), "/v1/wear", &wear), 200);
  ASSERT_EQ(HttpGet(daemon_->url(), "/v1/models/active", &model), 200);
  ExpectWearEqualsOffline(wear, OfflinePrediction(data_, model));
  // The last campaign's rolls: coil counts and rolled length.
  ASSERT_EQ(wear["positions"].size(), 4u) << wear.dump();
  for (const json& p : wear["positions"]) {
    EXPECT_EQ(p["campaign_id"], data_.campaigns.back().id);
    EXPECT_GT(p["coils"].get<int>(), 0) << p.dump();
    EXPECT_GT(p["rolled_length_m"].get<double>(), 0) << p.dump();
  }
  const auto metrics = ScrapeMetrics(daemon_->url());
  EXPECT_EQ(metrics.at("rollwear_coils_stored"),
            static_cast<double>(data_.coil_ids.size()));
  EXPECT_EQ(metrics.at("rollwear_campaigns_stored"), 12);
  int last_campaign_measurements = 0;
  for (const Measurement& m : data_.measurements) {
    if (m.campaign == static_cast<int>(data_.campaigns.size()) - 1) {
      ++last_campaign_measurements;
    }
  }
  EXPECT_EQ(metrics.at("rollwear_measurements_stored"),
            static_cast<double>(data_.measurements.size() -
                                last_campaign_measurements));
  EXPECT_EQ(metrics.at("rollwear_coils_ingested_total"),
            static_cast<double>(data_.coil_ids.size()));
  EXPECT_GE(metrics.at("rollwear_group_commits_total"), 1);

  // Replaying everything again changes nothing: every key is stored.
  Replay(4);
  json again;
  ASSERT_EQ(HttpGet(daemon_->url(), "/v1/wear", &again), 200);
  EXPECT_EQ(again, wear);
  EXPECT_EQ(ScrapeMetrics(daemon_->url()).at("rollwear_coils_stored"),
            static_cast<double>(data_.coil_ids.size()));
}

// Campaign by campaign through the API, coils from 8 concurrent clients:
// after each campaign's coils, GET /v1/wear equals the offline batch
// prediction of that campaign.
TEST_F(ServeTest, EveryCampaignsWearEqualsTheOfflineBatchPrediction) {
  json model;
  ASSERT_EQ(HttpGet(daemon_->url(), "/v1/models/active", &model), 200);
  const std::map<std::string, double> offline = OfflinePrediction(data_, model);
  for (int c = 0; c < static_cast<int>(data_.campaigns.size()); ++c) {
    ASSERT_EQ(HttpPost(daemon_->url(), "/v1/roll-changes",
                       RollChangeJson(data_, c).dump(), nullptr),
              201);
    const std::vector<int> coils = CoilsOf(data_, c);
    std::atomic<size_t> next{0};
    std::atomic<int> failures{0};
    std::vector<std::thread> clients;
    for (int t = 0; t < 8; ++t) {
      clients.emplace_back([&] {
        api::HttpClient client(daemon_->url());
        for (size_t i = next++; i < coils.size(); i = next++) {
          if (client.Post("/v1/coils", CoilJson(data_, coils[i]).dump())
                  .status != 201) {
            ++failures;
          }
        }
      });
    }
    for (auto& t : clients) t.join();
    ASSERT_EQ(failures.load(), 0);
    json wear;
    ASSERT_EQ(HttpGet(daemon_->url(), "/v1/wear", &wear), 200);
    ASSERT_FALSE(wear["positions"].empty()) << "campaign " << c;
    ExpectWearEqualsOffline(wear, offline);
    const std::string end = "{\"ended_at\":\"" +
                            FormatTimestamp(data_.campaigns[c].ended_at) +
                            "\"}";
    ASSERT_EQ(HttpPost(daemon_->url(),
                       "/v1/campaigns/" + data_.campaigns[c].id + "/end", end,
                       nullptr),
              200);
  }
}

TEST_F(ServeTest, EightClientsPostingTheSameCoilsCountEachOnce) {
  ASSERT_EQ(HttpPost(daemon_->url(), "/v1/roll-changes",
                     RollChangeJson(data_, 0).dump(), nullptr),
            201);
  const std::vector<int> coils = CoilsOf(data_, 0);
  ASSERT_FALSE(coils.empty());
  std::vector<std::string> bodies;
  for (int k : coils) bodies.push_back(CoilJson(data_, k).dump());

  std::atomic<int> created{0}, repeated{0}, other{0};
  std::vector<std::thread> clients;
  for (int t = 0; t < 8; ++t) {
    clients.emplace_back([&, t] {
      std::vector<size_t> order(bodies.size());
      for (size_t i = 0; i < order.size(); ++i) order[i] = i;
      std::shuffle(order.begin(), order.end(), std::mt19937(t));
      api::HttpClient client(daemon_->url());
      for (size_t i : order) {
        const int status = client.Post("/v1/coils", bodies[i]).status;
        (status == 201 ? created : status == 200 ? repeated : other)++;
      }
    });
  }
  for (auto& c : clients) c.join();
  EXPECT_EQ(created.load(), static_cast<int>(coils.size()));
  EXPECT_EQ(repeated.load(), static_cast<int>(7 * coils.size()));
  EXPECT_EQ(other.load(), 0);

  const auto metrics = ScrapeMetrics(daemon_->url());
  EXPECT_EQ(metrics.at("rollwear_coils_stored"),
            static_cast<double>(coils.size()));
  EXPECT_EQ(metrics.at("rollwear_coils_ingested_total"),
            static_cast<double>(coils.size()));
  json wear, model;
  ASSERT_EQ(HttpGet(daemon_->url(), "/v1/wear", &wear), 200);
  ASSERT_EQ(HttpGet(daemon_->url(), "/v1/models/active", &model), 200);
  // Campaign 0 is still open with all its coils: the batch prediction of
  // the whole campaign.
  ExpectWearEqualsOffline(wear, OfflinePrediction(data_, model));
  for (const json& p : wear["positions"]) {
    EXPECT_EQ(p["campaign_id"], data_.campaigns[0].id);
  }
}

TEST_F(ServeTest, CalibrationThroughTheApiIsPromoted) {
  Replay(8);
  json queued;
  ASSERT_EQ(HttpPost(daemon_->url(), "/v1/calibrations", "{}", &queued), 202)
      << queued.dump();
  const int64_t id = queued["id"].get<int64_t>();
  json record;
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::seconds(300);
  for (;;) {
    ASSERT_EQ(HttpGet(daemon_->url(), "/v1/calibrations/" + std::to_string(id),
                      &record),
              200);
    const std::string status = record.value("status", "");
    if (status == "done" || status == "failed") break;
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << record.dump();
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_EQ(record["status"], "done") << record.dump();
  EXPECT_TRUE(record["promoted"].get<bool>()) << record.dump();
  EXPECT_GT(record["gap_val_um"].get<double>(), 0);
  EXPECT_FALSE(record["coefficients"].empty());
  const int64_t version = record["model_version"].get<int64_t>();
  EXPECT_GT(version, 0);

  json model;
  ASSERT_EQ(HttpGet(daemon_->url(), "/v1/models/active", &model), 200);
  EXPECT_EQ(model["version"], version) << model.dump();
  EXPECT_EQ(model["model"], "wang");
  json models;
  ASSERT_EQ(HttpGet(daemon_->url(), "/v1/models", &models), 200);
  EXPECT_GE(models["models"].size(), 1u);
  // Open predictions were re-made with the promoted model.
  json wear;
  ASSERT_EQ(HttpGet(daemon_->url(), "/v1/wear", &wear), 200);
  EXPECT_EQ(wear["model_version"], version);
  const std::map<std::string, double> offline = OfflinePrediction(data_, model);
  ASSERT_EQ(wear["positions"].size(), 4u) << wear.dump();
  for (const auto& [key, value] : WearByKey(wear)) {
    ASSERT_TRUE(offline.count(key)) << key;
    EXPECT_NEAR(value, offline.at(key), 1e-6 * std::max(1.0, value)) << key;
  }
  const auto metrics = ScrapeMetrics(daemon_->url());
  EXPECT_NEAR(metrics.at("rollwear_validation_gap_um"),
              record["gap_val_um"].get<double>(), 1e-9);
  EXPECT_EQ(metrics.at("rollwear_model_version"), version);
}

TEST_F(ServeTest, SigtermStopsCleanlyAndTheStateSurvivesARestart) {
  Replay(8);
  json wear;
  ASSERT_EQ(HttpGet(daemon_->url(), "/v1/wear", &wear), 200);
  const auto before = ScrapeMetrics(daemon_->url());
  EXPECT_EQ(daemon_->Terminate(), 0);
  const std::string log = ReadFile(dir_ / "serve.log");
  EXPECT_NE(log.find("received SIGTERM"), std::string::npos) << log;
  EXPECT_NE(log.find("database closed"), std::string::npos) << log;

  Daemon restarted(dir_ / "rollwear.db", dir_ / "serve.log");
  std::string error;
  ASSERT_TRUE(restarted.Start(&error)) << error;
  json after;
  ASSERT_EQ(HttpGet(restarted.url(), "/v1/wear", &after), 200);
  EXPECT_EQ(after, wear);
  const auto metrics = ScrapeMetrics(restarted.url());
  for (const char* name : {"rollwear_coils_stored", "rollwear_campaigns_stored",
                           "rollwear_measurements_stored"}) {
    EXPECT_EQ(metrics.at(name), before.at(name)) << name;
  }
  json health;
  EXPECT_EQ(HttpGet(restarted.url(), "/healthz", &health), 200);
  EXPECT_EQ(health["status"], "ok");
}

TEST(ServeConfigTest, EnvironmentTokenWinsOverTheConfigFile) {
  TempDir dir;
  {
    std::ofstream conf(dir / "rollwear.conf");
    conf << "# test config\nport = 0\ntoken = from-file   # overridden\n"
            "recalibration_time = off\nthreads = 4\n";
  }
  Daemon daemon(dir / "rollwear.db", dir / "serve.log", 0,
                {"--config", dir / "rollwear.conf"},
                {"ROLLWEAR_TOKEN=from-env"});
  std::string error;
  ASSERT_TRUE(daemon.Start(&error)) << error;
  const std::string body =
      R"({"campaign_id":"C1","started_at":"2026-03-01T06:00:00Z","rolls":[)"
      R"({"stand":"F6","position":"top","roll_id":"R1","roll_type":"T",)"
      R"("diameter_mm":700,"hardness_hb":550}]})";
  json answer;
  EXPECT_EQ(HttpPost(daemon.url(), "/v1/roll-changes", body, &answer), 401);
  EXPECT_EQ(answer["error"]["code"], "unauthorized");
  EXPECT_EQ(
      HttpPost(daemon.url(), "/v1/roll-changes", body, &answer, "from-file"),
      401);
  EXPECT_EQ(
      HttpPost(daemon.url(), "/v1/roll-changes", body, &answer, "from-env"),
      201);
  EXPECT_EQ(HttpGet(daemon.url(), "/v1/wear", &answer), 200);
}

TEST(ServeConfigTest, BadConfigFileNamesFileLineAndKey) {
  TempDir dir;
  {
    std::ofstream conf(dir / "rollwear.conf");
    conf << "port = 8080\n\nrecalibration_time = 25:00\n";
  }
  std::string output;
  const int code = RunRollwear(
      {"serve", "--db", dir / "x.db", "--config", dir / "rollwear.conf"},
      &output);
  EXPECT_EQ(code, 2);
  EXPECT_NE(output.find("rollwear.conf:3: recalibration_time:"),
            std::string::npos)
      << output;
}

TEST(ServeHttpTest, OversizeBodyIs413AndUnknownRoute404OverHttp) {
  TempDir dir;
  Daemon daemon(dir / "rollwear.db", dir / "serve.log");
  std::string error;
  ASSERT_TRUE(daemon.Start(&error)) << error;
  api::HttpClient client(daemon.url());
  const api::HttpResult big =
      client.Post("/v1/coils", "{\"x\":\"" + std::string(2 << 20, 'x') + "\"}");
  EXPECT_EQ(big.status, 413);
  const json e = json::parse(big.body, nullptr, false);
  ASSERT_TRUE(e.is_object()) << big.body;
  EXPECT_EQ(e["error"]["code"], "payload_too_large");
  const api::HttpResult missing = client.Get("/nothing");
  EXPECT_EQ(missing.status, 404);
  EXPECT_EQ(json::parse(missing.body)["error"]["code"], "not_found");
}

}  // namespace
}  // namespace rollwear::e2e
