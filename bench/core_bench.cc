// Core figures: loading + aggregating the paper-size dataset and fitting
// Wang option 1 / option 2, on the paper-size dataset and on one with 10x
// the strips (same campaigns, 10x coils per campaign). Fit time must not
// grow with the strip count (sufficient statistics), and option 2 should fit
// in under 20 ms on paper size.
//
// Run: ./build/bench/core_bench   (prints a Google Benchmark table)
#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>

#include "core/aggregation.h"
#include "core/calibration.h"
#include "core/dataset_io.h"
#include "core/metrics.h"
#include "core/simulator.h"

namespace rollwear {
namespace {

// Simulated datasets written once to a temporary folder, by strip factor.
const std::string& DatasetDir(int strip_factor) {
  static std::map<int, std::string> dirs;
  auto it = dirs.find(strip_factor);
  if (it != dirs.end()) return it->second;
  SimulatorOptions o;
  o.seed = 2;
  o.coils_per_campaign *= strip_factor;
  StatusOr<Simulation> sim = Simulate(o);
  if (!sim.ok()) std::abort();
  const std::string dir = (std::filesystem::temp_directory_path() /
                           ("rollwear_bench_x" + std::to_string(strip_factor)))
                              .string();
  if (!WriteDataset(sim->data, dir).ok()) std::abort();
  return dirs[strip_factor] = dir;
}

void BM_LoadAndAggregate(benchmark::State& state) {
  const std::string& dir = DatasetDir(static_cast<int>(state.range(0)));
  size_t rows = 0;
  for (auto _ : state) {
    StatusOr<Dataset> data = ReadDataset(dir);
    if (!data.ok()) state.SkipWithError(data.status().ToString().c_str());
    const DatasetIndex index(*data);
    StatusOr<WearStatistics> st = Aggregate(*data, index, WearLaw::kWang);
    benchmark::DoNotOptimize(st);
    rows = data->passes.size();
  }
  state.counters["pass_rows"] = static_cast<double>(rows);
  state.SetLabel(state.range(0) == 1 ? "paper size" : "10x strips");
}
BENCHMARK(BM_LoadAndAggregate)->Arg(1)->Arg(10)->Unit(benchmark::kMillisecond);

void BM_FitWang(benchmark::State& state) {
  const int factor = static_cast<int>(state.range(0));
  const int option = static_cast<int>(state.range(1));
  StatusOr<Dataset> data = ReadDataset(DatasetDir(factor));
  const DatasetIndex index(*data);
  StatusOr<WearStatistics> st = Aggregate(*data, index, WearLaw::kWang);
  const CampaignSplit split = SplitCampaigns(*st);
  const std::vector<int> train = st->MeasuredObservations(split.train);
  CalibrationOptions o;
  o.option = option;
  int iterations = 0;
  for (auto _ : state) {
    StatusOr<CalibrationResult> r = Calibrate(*st, train, o);
    if (!r.ok() || !r->summary.usable) state.SkipWithError("calibration failed");
    iterations = r->summary.iterations;
  }
  state.counters["lm_iterations"] = iterations;
  state.counters["observations"] = static_cast<double>(train.size());
  state.counters["pass_rows"] = static_cast<double>(data->passes.size());
  state.SetLabel(std::string(factor == 1 ? "paper size" : "10x strips") +
                 ", option " + std::to_string(option));
}
BENCHMARK(BM_FitWang)
    ->Args({1, 1})
    ->Args({1, 2})
    ->Args({10, 1})
    ->Args({10, 2})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rollwear

BENCHMARK_MAIN();
