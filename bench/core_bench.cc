// Core figures: loading + aggregating the paper-size dataset and fitting
// Wang option 1 / option 2, on the paper-size dataset and on one with 10x
// the strips: every pass of the paper-size dataset cut into 10 strips of a
// tenth of its length (same campaigns, same physics, 10x pass rows). Fit
// time must not grow with the strip count (sufficient statistics), and
// option 2 should fit in under 20 ms on paper size. The fit is timed with
// and without the covariance (standard errors) step.
//
// Run: ./build/bench/core_bench   (prints a Google Benchmark table)
#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>

#include "core/model/aggregation.h"
#include "core/fit/calibration.h"
#include "core/dataset/dataset_io.h"
#include "core/model/metrics.h"
#include "core/sim/simulator.h"

namespace rollwear {
namespace {

// Every pass cut into `factor` strips of 1/factor of its length (coil ids
// get a suffix, seq is renumbered): the same wear, factor x the rows.
Dataset SplitStrips(const Dataset& in, int factor) {
  if (factor == 1) return in;
  Dataset out = in;
  out.passes.clear();
  out.coil_ids.clear();
  std::map<std::pair<int, int>, int> coil_map;  // (old coil, piece) -> new
  for (const Pass& p : in.passes) {
    for (int k = 0; k < factor; ++k) {
      Pass q = p;
      q.length_m = p.length_m / factor;
      q.seq = (p.seq - 1) * factor + k + 1;
      auto [it, inserted] = coil_map.try_emplace({p.coil, k}, static_cast<int>(out.coil_ids.size()));
      if (inserted) out.coil_ids.push_back(in.coil_ids[p.coil] + "-" + std::to_string(k));
      q.coil = it->second;
      out.passes.push_back(q);
    }
  }
  out.pass_extra = ExtraColumns{};
  return out;
}

// Simulated datasets written once to a temporary folder, by strip factor.
const std::string& DatasetDir(int strip_factor) {
  static std::map<int, std::string> dirs;
  auto it = dirs.find(strip_factor);
  if (it != dirs.end()) return it->second;
  SimulatorOptions o;
  o.seed = 2;
  StatusOr<Simulation> sim = Simulate(o);
  if (!sim.ok()) std::abort();
  const std::string dir = (std::filesystem::temp_directory_path() /
                           ("rollwear_bench_x" + std::to_string(strip_factor)))
                              .string();
  if (!WriteDataset(SplitStrips(sim->data, strip_factor), dir).ok()) std::abort();
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
  const bool covariance = state.range(2) != 0;
  StatusOr<Dataset> data = ReadDataset(DatasetDir(factor));
  const DatasetIndex index(*data);
  StatusOr<WearStatistics> st = Aggregate(*data, index, WearLaw::kWang);
  const CampaignSplit split = SplitCampaigns(*st);
  const std::vector<int> train = st->MeasuredObservations(split.train);
  CalibrationOptions o;
  o.option = option;
  o.compute_covariance = covariance;
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
                 ", option " + std::to_string(option) +
                 (covariance ? ", with std. errors" : ", LM only"));
}
BENCHMARK(BM_FitWang)
    ->ArgsProduct({{1, 10}, {1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rollwear

BENCHMARK_MAIN();
