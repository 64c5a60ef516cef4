// Time of a full diagnosis (baseline, locate, candidate screening, refits,
// cross-validation, naming) on paper-size simulated data, without and with
// a concealed effect. Target: under 10 s on 2 cores.
//
// Run: ./build/bench/diagnosis_bench
#include <benchmark/benchmark.h>

#include "core/diagnosis/diagnosis.h"
#include "core/sim/simulator.h"

namespace rollwear {
namespace {

void BM_Diagnose(benchmark::State& state) {
  SimulatorOptions o;
  o.seed = 4;
  if (state.range(0) == 1) o.effects = {"campaign_growth"};
  if (state.range(0) == 2) o.effects = {"campaign_growth", "lubrication"};
  StatusOr<Simulation> sim = Simulate(o);
  if (!sim.ok()) {
    state.SkipWithError("simulation failed");
    return;
  }
  DiagnosisReport last;
  for (auto _ : state) {
    StatusOr<DiagnosisReport> r = Diagnose(sim->data, DiagnosisOptions{});
    if (!r.ok()) state.SkipWithError(r.status().ToString().c_str());
    last = *r;
  }
  state.counters["findings"] = static_cast<double>(last.findings.size());
  state.counters["pass_rows"] = static_cast<double>(sim->data.passes.size());
  for (const auto& [phase, seconds] : last.phase_seconds) state.counters[phase + "_s"] = seconds;
  state.SetLabel(state.range(0) == 0 ? "no effect"
                                     : (state.range(0) == 1 ? "campaign_growth"
                                                            : "campaign_growth+lubrication"));
}
BENCHMARK(BM_Diagnose)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
}  // namespace rollwear

BENCHMARK_MAIN();
