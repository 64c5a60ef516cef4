// Recurrent K-estimator figures on a paper-size simulated mill (395
// campaigns, ~51,700 coils, seed 2): the whole Table 4 comparison (classical
// calibration + training the 5-member ANN ensemble on 2 threads; target
// < 60 s), one training epoch of one member, and the incremental coil-by-
// coil prediction the daemon does per pass (target: microseconds).
//
// Run: ./build/bench/ann_bench   (prints figures; no assertions)
#include <cstdlib>
#include <numeric>

#include <benchmark/benchmark.h>

#include "core/model/aggregation.h"
#include "core/ann/ann_bptt.h"
#include "core/ann/ann_data.h"
#include "core/ann/ann_study.h"
#include "core/ann/ann_train.h"
#include "core/sim/simulator.h"

namespace rollwear {
namespace {

const Simulation& PaperMill(bool growth) {
  static Simulation* sims[2] = {nullptr, nullptr};
  Simulation*& s = sims[growth ? 1 : 0];
  if (s == nullptr) {
    SimulatorOptions o;
    o.seed = 2;
    if (growth) o.effects = {"campaign_growth"};
    StatusOr<Simulation> sim = Simulate(o);
    if (!sim.ok()) std::abort();
    s = new Simulation(std::move(sim).value());
  }
  return *s;
}

// The full comparison as `rollwear ann` runs it (5 members, 2 threads).
void BM_AnnTable4PaperSize(benchmark::State& state) {
  const bool growth = state.range(0) != 0;
  const Simulation& sim = PaperMill(growth);
  AnnComparisonOptions o;
  for (auto _ : state) {
    StatusOr<AnnComparison> c = CompareAnnWithClassical(sim.data, o);
    if (!c.ok()) {
      state.SkipWithError(c.status().ToString().c_str());
      return;
    }
    int epochs = 0;
    for (const AnnMemberFigures& f : c->members) epochs += f.training.epochs;
    state.counters["ann_train_s"] = c->ann_seconds;
    state.counters["epochs"] = epochs;
    state.counters["classical_val_um"] = c->classical_val.gap_um;
    state.counters["ann_val_um"] = c->ann_val.gap_um;
    state.counters["ann_train_um"] = c->ann_train.gap_um;
  }
  state.SetLabel(growth ? "395 campaigns, campaign_growth"
                        : "395 campaigns, no concealed effect");
}
BENCHMARK(BM_AnnTable4PaperSize)
    ->Arg(0)
    ->Arg(1)
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

struct Prepared {
  AnnModel model;
  AnnInputs inputs;
  std::vector<int> train;
  Dataset data;
};

const Prepared& PaperInputs() {
  static Prepared* p = [] {
    auto* out = new Prepared;
    out->data = PaperMill(false).data;
    const DatasetIndex index(out->data);
    StatusOr<WearStatistics> st = Aggregate(out->data, index, WearLaw::kWang);
    const CampaignSplit split = SplitCampaigns(*st);
    out->train = st->MeasuredObservations(split.train);
    out->model = *FitAnnScaling(out->data, index, *st, split.train, 10, 10);
    out->inputs = BuildAnnInputs(out->model, out->data, index, *st);
    out->model.members.push_back(InitialAnnNetwork(out->model, 1, -1.0));
    return out;
  }();
  return *p;
}

// Forward + BPTT over every training campaign once (one epoch's gradient
// work for one member, without the holdout evaluation).
void BM_AnnEpochGradient(benchmark::State& state) {
  const Prepared& p = PaperInputs();
  const std::vector<double> w(p.train.size(), 1e-4);
  AnnNetwork grad;
  long passes = 0;
  for (int s : p.train) {
    passes += p.inputs.sequences[s].end - p.inputs.sequences[s].begin;
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        AnnObjective(p.model, p.model.members[0], p.inputs, p.train, w, &grad));
  }
  state.counters["passes"] = static_cast<double>(passes);
  state.counters["ns_per_pass"] =
      benchmark::Counter(static_cast<double>(passes),
                         benchmark::Counter::kIsIterationInvariantRate |
                             benchmark::Counter::kInvert);
}
BENCHMARK(BM_AnnEpochGradient)->Unit(benchmark::kMillisecond);

// One incremental AddPass on a mounted roll (5-member model).
void BM_AnnAddPass(benchmark::State& state) {
  const Prepared& p = PaperInputs();
  AnnModel model = p.model;
  for (uint64_t s = 2; s <= 5; ++s) {
    model.members.push_back(InitialAnnNetwork(model, s, -1.0));
  }
  const PassInput pass = PassInputOf(p.data, p.data.passes[0]);
  AnnRollState roll =
      MountRoll(model, model.positions[0], model.roll_types[0], 700, 560);
  for (auto _ : state) {
    benchmark::DoNotOptimize(AddPass(model, pass, &roll));
    if (roll.coils >= 200) {
      state.PauseTiming();
      roll =
          MountRoll(model, model.positions[0], model.roll_types[0], 700, 560);
      state.ResumeTiming();
    }
  }
  state.SetLabel("5 members");
}
BENCHMARK(BM_AnnAddPass)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace rollwear

BENCHMARK_MAIN();
