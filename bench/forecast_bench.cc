// forecast_bench: POST /v1/forecast for a 200-coil schedule (target:
// milliseconds), in process on a real SQLite file with an open campaign of
// 500 stored coils on four rolls (F6/F7 top and bottom):
//   BM_ForecastRequest/200  the router's whole answer: decode the body
//                           (each coil as POST /v1/coils decodes it),
//                           check, predict every roll after each coil with
//                           its interval, encode
//   BM_ForecastStore/200    engine::MountedRolls::ForecastCoils alone (the
//                           store's checks and the engine's prediction)
// and, on the same mill, the wear profile across the barrel:
//   BM_WearProfileGet       GET /v1/wear/F6/top/profile through the router
//                           (201 slices, interval, JSON); p99_us is the
//                           99th percentile of the single requests
//                           (target < 1 ms)
//   BM_ProfilePassUpdate    one pass added to a roll state that tracks its
//                           profile (predictor.h): the per-coil cost per
//                           roll
// Figures only; nothing here passes or fails.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "api/router.h"
#include "core/model/predictor.h"
#include "engine/mounted_rolls.h"
#include "engine/wear_prediction.h"
#include "storage/mill_store.h"

namespace rollwear::bench {
namespace {

std::string CoilBody(int seq) {
  const double f = 8000 + 37.5 * (seq % 97);
  const double len = 480 + 1.3 * (seq % 151);
  char buf[1024];
  std::snprintf(
      buf, sizeof(buf),
      R"({"coil_id":"K%d","campaign_id":"C1","seq":%d,)"
      R"("rolled_at":"2030-01-01T06:00:00Z","grade":"%s","passes":[)"
      R"({"stand":"F6","force_kn":%.1f,"width_mm":1031,"length_m":%.1f,)"
      R"("entry_thickness_mm":5.81,"exit_thickness_mm":4.561,)"
      R"("temperature_c":946.3,"speed_mps":8.95,"lubrication":0,)"
      R"("shift_mm":37.8},)"
      R"({"stand":"F7","force_kn":%.1f,"width_mm":1031,"length_m":%.1f,)"
      R"("entry_thickness_mm":4.561,"exit_thickness_mm":4.075,)"
      R"("temperature_c":928.8,"speed_mps":10.176,"lubrication":0,)"
      R"("shift_mm":7.4}]})",
      seq, seq, seq % 3 == 0 ? "HSLA" : "CQ", f, len, 0.45 * f, len * 1.12);
  return buf;
}

// A store with campaign C1 open and 500 coils rolled, and its router.
struct Mill {
  std::filesystem::path dir;
  std::unique_ptr<storage::MillStore> store;
  std::unique_ptr<api::Router> router;

  Mill() {
    dir = std::filesystem::temp_directory_path() / "rollwear_forecast_bench";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    storage::StoreOptions options;
    options.wear_limit_um.fill(400);
    auto opened = engine::OpenStore((dir / "b.db").string(), options);
    if (!opened.ok()) Die(opened.status().ToString());
    store = std::move(opened).value();
    router = std::make_unique<api::Router>(store.get(), api::ApiOptions());
    Post(
        "/v1/roll-changes",
        R"({"campaign_id":"C1","started_at":"2030-01-01T05:00:00Z","rolls":[)"
        R"({"stand":"F6","position":"top","roll_id":"A","roll_type":"ICDP",)"
        R"("diameter_mm":700,"hardness_hb":550},)"
        R"({"stand":"F6","position":"bottom","roll_id":"B","roll_type":"ICDP",)"
        R"("diameter_mm":700,"hardness_hb":550},)"
        R"({"stand":"F7","position":"top","roll_id":"C","roll_type":"HSS",)"
        R"("diameter_mm":690,"hardness_hb":600},)"
        R"({"stand":"F7","position":"bottom","roll_id":"D","roll_type":"HSS",)"
        R"("diameter_mm":690,"hardness_hb":600}]})",
        201);
    for (int seq = 1; seq <= 500; ++seq) Post("/v1/coils", CoilBody(seq), 201);
  }
  ~Mill() {
    router.reset();
    store.reset();
    std::filesystem::remove_all(dir);
  }
  static void Die(const std::string& why) {
    std::fprintf(stderr, "forecast_bench: %s\n", why.c_str());
    std::abort();
  }
  api::HttpResponse Post(const std::string& path, std::string body, int want) {
    api::HttpRequest request;
    request.method = "POST";
    request.path = path;
    request.body = std::move(body);
    api::HttpResponse r = router->Handle(request);
    if (r.status != want) Die(path + ": " + r.body);
    return r;
  }
};

std::string ScheduleBody(int coils) {
  std::string body = R"({"coils":[)";
  for (int i = 0; i < coils; ++i) {
    if (i > 0) body += ',';
    body += CoilBody(501 + i);
  }
  return body + "]}";
}

void BM_ForecastRequest(benchmark::State& state) {
  Mill mill;
  const std::string body = ScheduleBody(static_cast<int>(state.range(0)));
  size_t bytes = 0;
  for (auto _ : state) {
    bytes = mill.Post("/v1/forecast", body, 200).body.size();
  }
  state.counters["request_bytes"] = static_cast<double>(body.size());
  state.counters["answer_bytes"] = static_cast<double>(bytes);
}
BENCHMARK(BM_ForecastRequest)->Arg(200)->Unit(benchmark::kMillisecond);

void BM_ForecastStore(benchmark::State& state) {
  Mill mill;
  std::vector<storage::CoilIn> coils;
  for (int i = 0; i < state.range(0); ++i) {
    storage::CoilIn c;
    c.coil_id = "P" + std::to_string(i);
    c.campaign_id = "C1";
    c.seq = 501 + i;
    c.rolled_at = 1'893'477'600;
    c.grade = i % 3 == 0 ? "HSLA" : "CQ";
    for (int stand : {6, 7}) {
      storage::PassIn p;
      p.stand = stand;
      p.force_kn = (stand == 6 ? 1.0 : 0.45) * (8000 + 37.5 * (i % 97));
      p.width_mm = 1031;
      p.length_m = 480 + 1.3 * (i % 151);
      p.entry_thickness_mm = stand == 6 ? 5.81 : 4.561;
      p.exit_thickness_mm = stand == 6 ? 4.561 : 4.075;
      p.temperature_c = 940;
      p.speed_mps = 9;
      p.shift_mm = 7.4;
      c.passes.push_back(p);
    }
    coils.push_back(std::move(c));
  }
  for (auto _ : state) {
    StatusOr<engine::Forecast> f =
        engine::MountedRolls(mill.store.get()).ForecastCoils(coils);
    if (!f.ok()) Mill::Die(f.status().ToString());
    benchmark::DoNotOptimize(f->positions.data());
  }
}
BENCHMARK(BM_ForecastStore)->Arg(200)->Unit(benchmark::kMillisecond);

void BM_WearProfileGet(benchmark::State& state) {
  Mill mill;
  api::HttpRequest request;
  request.method = "GET";
  request.path = "/v1/wear/F6/top/profile";
  std::vector<double> us;
  size_t bytes = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    api::HttpResponse r = mill.router->Handle(request);
    us.push_back(std::chrono::duration<double, std::micro>(
                     std::chrono::steady_clock::now() - t0)
                     .count());
    if (r.status != 200) Mill::Die(r.body);
    bytes = r.body.size();
  }
  std::sort(us.begin(), us.end());
  state.counters["p50_us"] = us[us.size() / 2];
  state.counters["p99_us"] = us[std::min(us.size() - 1, us.size() * 99 / 100)];
  state.counters["answer_bytes"] = static_cast<double>(bytes);
}
BENCHMARK(BM_WearProfileGet)->Unit(benchmark::kMicrosecond);

void BM_ProfilePassUpdate(benchmark::State& state) {
  Mill mill;
  StatusOr<storage::ModelVersion> model = mill.store->ActiveModel();
  if (!model.ok()) Mill::Die(model.status().ToString());
  const WearModel& m = model->wear_model;
  RollWearState roll = MountRoll(m, "F6/top", "ICDP", 700, 550);
  TrackProfile(&roll);
  PassInput pass;
  pass.grade = "CQ";
  pass.force_kn = 21000;
  pass.width_mm = 1250;
  pass.length_m = 820;
  pass.entry_thickness_mm = 5.81;
  pass.exit_thickness_mm = 4.561;
  pass.temperature_c = 940;
  pass.speed_mps = 9;
  int i = 0;
  for (auto _ : state) {
    pass.shift_mm = -100 + (i++ % 200);  // a shifting cycle
    benchmark::DoNotOptimize(AddPass(m, pass, &roll));
  }
}
BENCHMARK(BM_ProfilePassUpdate)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace rollwear::bench

BENCHMARK_MAIN();
