// Time of a full diagnosis (baseline, locate, candidate screening, refits,
// cross-validation, proxy guard, naming) on paper-size simulated data (395
// campaigns, the scorecard's first seed 101), on 2 threads: without an
// effect and for the slowest scorecard cases (docs/diagnosis.md,
// Scorecard: temperature, calendar drift, stoppages, supplier change and
// the temperature x speed interaction). Target: every case under 10 s on
// 2 cores. Each case prints its wall seconds and the seconds of each phase
// (counters <phase>_s, from DiagnosisReport::phase_seconds).
//
// Run: ./build/bench/diagnosis_bench
//      ./build/bench/diagnosis_bench --benchmark_filter='BM_Diagnose/3'
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "core/diagnosis/diagnosis.h"
#include "core/sim/simulator.h"

namespace rollwear {
namespace {

// The cases, by benchmark argument.
const std::vector<std::string>& Cases() {
  static const std::vector<std::string> cases = {
      "",         "campaign_growth", "temperature",      "calendar_drift",
      "stoppages", "supplier_change", "inexpressible_interaction"};
  return cases;
}

void BM_Diagnose(benchmark::State& state) {
  const std::string& effect = Cases()[state.range(0)];
  SimulatorOptions o;
  o.seed = 101;
  o.num_campaigns = 395;
  if (!effect.empty()) o.effects = {effect};
  StatusOr<Simulation> sim = Simulate(o);
  if (!sim.ok()) {
    state.SkipWithError("simulation failed");
    return;
  }
  DiagnosisOptions options;
  options.num_threads = 2;
  DiagnosisReport last;
  for (auto _ : state) {
    StatusOr<DiagnosisReport> r = Diagnose(sim->data, options);
    if (!r.ok()) {
      state.SkipWithError(r.status().ToString().c_str());
      return;
    }
    last = *r;
  }
  state.counters["seconds"] = last.seconds;
  state.counters["findings"] = static_cast<double>(last.findings.size());
  state.counters["pass_rows"] = static_cast<double>(sim->data.passes.size());
  for (const auto& [phase, seconds] : last.phase_seconds) state.counters[phase + "_s"] = seconds;
  state.SetLabel(effect.empty() ? "no effect" : effect);
}
BENCHMARK(BM_Diagnose)
    ->DenseRange(0, 6)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

}  // namespace
}  // namespace rollwear

BENCHMARK_MAIN();
