// roll_factor_bench: what keeping each roll's wear factor current costs the
// daemon (storage/store_roll_factors.cc). Not a pass/fail test: it prints
// figures, each with the same figure for a store whose active model has no
// roll-effect term, measured in the same run.
//
//   roll_factor_bench [--campaigns N]...   (default: 395 and 2000)
//
// For each N: a simulated mill of N campaigns with lifelong roll factors
// (sd 0.2) is imported into a fresh store (a real SQLite file under
// /tmp). Store "term": a model with a roll_effect term over every roll
// (the simulator's factors) is proposed and promoted through
// engine::CalibrationRuns; store "plain" keeps the prior. Then, on each:
//   reopen      MillStore::Open on the file (the served factors are
//               re-estimated from every stored reading with the term);
//   measurement AddMeasurement for the 4 rolls of a campaign just rolled
//               (each re-estimates that roll's factor with the term), the
//               mean of the 4, the next campaign open with the same rolls
//               (so the open campaign is replayed too).
// And the promotion of the term's model (once, with the term).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/sim/simulator.h"
#include "engine/calibration_runs.h"
#include "engine/wear_prediction.h"
#include "storage/mill_store.h"

namespace rollwear {
namespace {

using Clock = std::chrono::steady_clock;

double MsSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

std::unique_ptr<storage::MillStore> OpenStore(const std::string& path) {
  StatusOr<std::unique_ptr<storage::MillStore>> s = engine::OpenStore(path);
  if (!s.ok()) {
    std::fprintf(stderr, "open %s: %s\n", path.c_str(),
                 s.status().ToString().c_str());
    std::exit(1);
  }
  return std::move(s).value();
}

void Check(const Status& s, const char* what) {
  if (s.ok()) return;
  std::fprintf(stderr, "%s: %s\n", what, s.ToString().c_str());
  std::exit(1);
}

// The roll change of a new campaign `id` at `start` with the mounts of the
// data's last campaign.
storage::RollChangeIn NewCampaign(const Dataset& data, const std::string& id,
                                  UnixSeconds start) {
  storage::RollChangeIn rc;
  rc.campaign_id = id;
  rc.started_at = start;
  const int last = static_cast<int>(data.campaigns.size()) - 1;
  for (const Mount& m : data.mounts) {
    if (m.campaign != last) continue;
    storage::MountedRollIn r;
    r.stand = m.stand;
    r.position = m.position;
    r.roll_id = m.roll_id;
    r.roll_type = data.roll_types[m.roll_type];
    r.diameter_mm = m.diameter_mm;
    r.hardness_hb = m.hardness_hb;
    rc.rolls.push_back(r);
  }
  return rc;
}

// Rolls the last campaign's coils again in the open campaign `id`.
void RollCoils(const Dataset& data, const std::string& id, UnixSeconds start,
               storage::MillStore* store) {
  const int last = static_cast<int>(data.campaigns.size()) - 1;
  std::map<int, storage::CoilIn> coils;
  for (const Pass& p : data.passes) {
    if (p.campaign != last) continue;
    storage::CoilIn& c = coils[p.coil];
    c.coil_id = id + "-" + data.coil_ids[p.coil];
    c.campaign_id = id;
    c.seq = p.seq;
    c.rolled_at = start + 60 + 60 * p.seq;
    c.grade = data.grades[p.grade];
    storage::PassIn in;
    static_cast<PassMeasures&>(in) = p;
    c.passes.push_back(in);
  }
  for (const auto& [row, coil] : coils)
    Check(store->AddCoil(coil).status(), "coil");
}

struct Figures {
  double reopen_ms = 0, measurement_ms = 0, promotion_ms = 0;
};

Figures Run(const Simulation& sim, bool with_term, const std::string& dir) {
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/mill.db";
  Figures f;
  std::unique_ptr<storage::MillStore> store = OpenStore(path);
  Check(store->ImportDataset(sim.data), "import");
  if (with_term) {
    StatusOr<Dataset> data = store->ExportDataset();
    Check(data.status(), "export");
    WearModel model = store->ActiveModel()->wear_model;
    ModelTerm t;
    t.form = TermForm::kRollEffect;
    t.covariate = "roll_id";
    t.scale = 0.2;
    for (const auto& [id, factor] : sim.truth.roll_wear_factor) {
      t.levels.push_back(id);
      t.params.push_back(std::log(factor));
    }
    t.num_levels = static_cast<int>(t.levels.size());
    model.terms.push_back(t);
    const Clock::time_point t0 = Clock::now();
    StatusOr<storage::CalibrationRecord> run =
        engine::CalibrationRuns(store.get())
            .Propose("bench", "wang", 1, model, *data, 1);
    f.promotion_ms = MsSince(t0);
    Check(run.status(), "propose");
    if (!run->promoted)
      std::fprintf(stderr, "not promoted: %s\n", run->message.c_str());
  }
  store.reset();
  Clock::time_point t0 = Clock::now();
  store = OpenStore(path);
  f.reopen_ms = MsSince(t0);

  UnixSeconds start = 0;
  for (const Campaign& c : sim.data.campaigns)
    start = std::max({start, c.started_at, c.ended_at});
  start += 3600;
  const storage::RollChangeIn first = NewCampaign(sim.data, "X1", start);
  Check(store->ApplyRollChange(first).status(), "roll change");
  RollCoils(sim.data, "X1", start, store.get());
  const UnixSeconds next = start + 86400;
  Check(store->ApplyRollChange(NewCampaign(sim.data, "X2", next)).status(),
        "roll change");
  RollCoils(sim.data, "X2", next, store.get());
  double total = 0;
  for (const storage::MountedRollIn& m : first.rolls) {
    storage::MeasurementIn in;
    in.campaign_id = "X1";
    in.stand = m.stand;
    in.position = m.position;
    in.roll_id = m.roll_id;
    in.measured_at = next + 600;
    in.wear_center_um = 150;
    t0 = Clock::now();
    Check(store->AddMeasurement(in).status(), "measurement");
    total += MsSince(t0);
  }
  f.measurement_ms = total / static_cast<double>(first.rolls.size());
  store.reset();
  std::filesystem::remove_all(dir);
  return f;
}

}  // namespace
}  // namespace rollwear

int main(int argc, char** argv) {
  using namespace rollwear;
  std::vector<int> sizes;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::string(argv[i]) == "--campaigns")
      sizes.push_back(std::atoi(argv[i + 1]));
  }
  if (sizes.empty()) sizes = {395, 2000};
  std::printf(
      "| campaigns | passes | store | reopen ms | measurement ms | promotion "
      "ms |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (int n : sizes) {
    SimulatorOptions so;
    so.seed = 41;
    so.num_campaigns = n;
    so.roll_wear_factor_sd = 0.2;
    StatusOr<Simulation> sim = Simulate(so);
    Check(sim.status(), "simulate");
    for (bool term : {false, true}) {
      const Figures f =
          Run(*sim, term, "/tmp/roll_factor_bench_" + std::to_string(n));
      std::printf(
          "| %d | %zu | %s | %.0f | %.1f | %s |\n", n, sim->data.passes.size(),
          term ? "roll_effect term" : "plain (prior)", f.reopen_ms,
          f.measurement_ms,
          term ? std::to_string(static_cast<int>(f.promotion_ms + 0.5)).c_str()
               : "-");
      std::fflush(stdout);
    }
  }
  return 0;
}
