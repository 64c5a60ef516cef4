// ingest_bench: the cost of each step of POST /v1/coils without HTTP, so
// that load_bench's end-to-end figure can be read as a sum:
//   BM_DecodeCoil        request body -> storage::CoilIn (api/codec)
//   BM_EncodeCoilAnswer  CoilOutcome -> answer body (api/codec)
//   BM_StoreAddCoil      MillStore::AddCoil on a real SQLite file (WAL,
//                        synchronous=FULL), 1 and 16 calling threads: every
//                        call returns after its group commit. Real time;
//                        items/s is coils/s through the store alone.
//   BM_StoreRepeatCoil   AddCoil of an already stored coil (no commit).
// Figures only; nothing here passes or fails.
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "api/codec.h"
#include "engine/wear_prediction.h"
#include "storage/mill_store.h"

namespace rollwear::bench {
namespace {

// A two-pass coil as the mill's Level 2 posts it (the simulator's F6/F7
// finishing passes).
constexpr char kCoilBody[] =
    R"({"coil_id":"K1","campaign_id":"C1","seq":1,)"
    R"("rolled_at":"2030-01-01T06:00:00Z","grade":"CQ","passes":[)"
    R"({"stand":"F6","force_kn":8294.4,"width_mm":1031,"length_m":509.6,)"
    R"("entry_thickness_mm":5.81,"exit_thickness_mm":4.561,)"
    R"("temperature_c":946.3,"speed_mps":8.95,"lubrication":0,)"
    R"("shift_mm":37.8},)"
    R"({"stand":"F7","force_kn":3787.3,"width_mm":1031,"length_m":570.4,)"
    R"("entry_thickness_mm":4.561,"exit_thickness_mm":4.075,)"
    R"("temperature_c":928.8,"speed_mps":10.176,"lubrication":0,)"
    R"("shift_mm":7.4}]})";

storage::CoilIn SampleCoil() {
  storage::CoilIn in;
  api::ApiError error;
  if (!api::DecodeCoil(kCoilBody, 32, &in, &error)) {
    std::fprintf(stderr, "ingest_bench: sample coil refused: %s\n",
                 error.message.c_str());
    std::abort();
  }
  return in;
}

void BM_DecodeCoil(benchmark::State& state) {
  const std::string body = kCoilBody;
  for (auto _ : state) {
    storage::CoilIn in;
    api::ApiError error;
    benchmark::DoNotOptimize(api::DecodeCoil(body, 32, &in, &error));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_DecodeCoil);

void BM_EncodeCoilAnswer(benchmark::State& state) {
  const storage::CoilIn in = SampleCoil();
  storage::CoilOutcome out;
  for (const storage::PassIn& p : in.passes) {
    for (Position pos : {Position::kTop, Position::kBottom}) {
      out.added.push_back({p.stand, pos, "R-" + std::to_string(p.stand),
                           1.229920341416101, 123.4567890123});
    }
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(api::EncodeCoilAnswer(in, out, -1));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_EncodeCoilAnswer);

// One store for all runs of a benchmark (threads share it).
struct StoreFixture {
  std::string dir;
  std::unique_ptr<storage::MillStore> store;
  std::atomic<int> next_seq{1};
  storage::CoilIn coil = SampleCoil();

  StoreFixture() {
    dir = (std::filesystem::temp_directory_path() /
           ("rollwear_ingest_bench_" + std::to_string(::getpid())))
              .string();
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    auto opened = engine::OpenStore(dir + "/bench.db");
    if (!opened.ok()) {
      std::fprintf(stderr, "ingest_bench: %s\n",
                   opened.status().message().c_str());
      std::abort();
    }
    store = std::move(opened).value();
    storage::RollChangeIn rc;
    rc.campaign_id = "C1";
    rc.started_at = 1893456000;  // 2030-01-01
    for (int stand : {6, 7}) {
      for (Position pos : {Position::kTop, Position::kBottom}) {
        rc.rolls.push_back(
            {stand,
             pos,
             "R" + std::to_string(stand) + (pos == Position::kTop ? "T" : "B"),
             "HSS",
             700,
             700,
             {}});
      }
    }
    if (!store->ApplyRollChange(rc).ok()) std::abort();
  }
  ~StoreFixture() {
    store.reset();
    std::filesystem::remove_all(dir);
  }
};

StoreFixture* Fixture() {
  static StoreFixture* fixture = new StoreFixture();  // lives to exit
  return fixture;
}

void BM_StoreAddCoil(benchmark::State& state) {
  StoreFixture* f = Fixture();
  storage::CoilIn coil = f->coil;
  int64_t refused = 0;
  for (auto _ : state) {
    const int seq = f->next_seq.fetch_add(1);
    coil.seq = seq;
    coil.coil_id = std::string("B").append(std::to_string(seq));
    if (!f->store->AddCoil(coil).ok()) ++refused;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["refused"] = static_cast<double>(refused);
  if (state.thread_index() == 0) {
    state.counters["commits"] =
        static_cast<double>(f->store->Counters().commits);
  }
}
BENCHMARK(BM_StoreAddCoil)->Threads(1)->Threads(16)->UseRealTime();

void BM_StoreRepeatCoil(benchmark::State& state) {
  StoreFixture* f = Fixture();
  storage::CoilIn coil = f->coil;
  coil.seq = f->next_seq.fetch_add(1);
  coil.coil_id = "REPEAT" + std::to_string(coil.seq);
  if (!f->store->AddCoil(coil).ok()) std::abort();
  for (auto _ : state) {
    benchmark::DoNotOptimize(f->store->AddCoil(coil));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_StoreRepeatCoil)->Threads(1)->Threads(16)->UseRealTime();

}  // namespace
}  // namespace rollwear::bench

BENCHMARK_MAIN();
