#include "tests/storage/store_test_util.h"

#include "core/model/aggregation.h"
#include "core/sim/simulator.h"
#include "storage/model_levels.h"

namespace rollwear::storage::testing {

void ExpectWearMatchesBatch(const MillStore& store, double tol) {
  const WearSnapshot snap = Mounted(store).Wear();
  ASSERT_FALSE(snap.positions.empty()) << "no open campaign";
  StatusOr<ModelVersion> active = store.ActiveModel();
  ASSERT_TRUE(active.ok());
  EXPECT_EQ(active->version, snap.model_version);
  StatusOr<Dataset> data = store.ExportDataset();
  ASSERT_TRUE(data.ok()) << data.status().ToString();
  int campaign = -1;
  for (size_t c = 0; c < data->campaigns.size(); ++c) {
    if (data->campaigns[c].id == snap.positions.front().campaign_id) {
      campaign = static_cast<int>(c);
    }
  }
  ASSERT_GE(campaign, 0);
  const DatasetIndex index(*data);
  StatusOr<WearStatistics> stats =
      Aggregate(*data, index, active->wear_model.law);
  ASSERT_TRUE(stats.ok()) << stats.status().ToString();
  StatusOr<WearModel> model = ModelOverLevels(
      active->wear_model, stats->positions, stats->roll_types, stats->grades);
  ASSERT_TRUE(model.ok());
  int compared = 0;
  for (const Observation& obs : stats->observations) {
    if (obs.campaign != campaign) continue;
    const double batch = PredictObservation(*model, *stats, obs);
    bool found = false;
    for (const PositionWear& w : snap.positions) {
      if (RollPositionSlot(w.stand, w.position) != obs.slot) continue;
      found = true;
      EXPECT_LE(RelDiff(w.predicted_wear_um, batch), tol)
          << RollPositionName(w.stand, w.position) << ": live "
          << w.predicted_wear_um << " batch " << batch;
      EXPECT_EQ(w.coils, obs.coils);
      EXPECT_LE(RelDiff(w.rolled_length_m, obs.rolled_length_m), tol);
      EXPECT_LE(w.interval_lo_um, w.predicted_wear_um);
      EXPECT_GE(w.interval_hi_um, w.predicted_wear_um);
      ++compared;
    }
    EXPECT_TRUE(found) << "slot " << obs.slot;
  }
  EXPECT_EQ(compared, static_cast<int>(snap.positions.size()));
}

Dataset SimulatedMill(uint64_t seed, int campaigns, int coils,
                      const std::vector<std::string>& effects) {
  SimulatorOptions o;
  o.seed = seed;
  o.num_campaigns = campaigns;
  o.coils_per_campaign = coils;
  o.effects = effects;
  StatusOr<Simulation> sim = Simulate(o);
  EXPECT_TRUE(sim.ok()) << sim.status().ToString();
  return sim.ok() ? std::move(sim->data) : Dataset{};
}

}  // namespace rollwear::storage::testing
