// The requests rollwear's own clients send (api/request_encode.h, used by
// `rollwear replay`, the e2e tests and the load bench) decode, through the
// daemon's own decoders, to exactly the dataset's values.
#include "api/request_encode.h"

#include <gtest/gtest.h>

#include "api/codec.h"
#include "core/sim/simulator.h"

namespace rollwear::api {
namespace {

constexpr int kDepth = 32;

TEST(RequestEncodeTest, EveryEventDecodesToTheDatasetsValues) {
  SimulatorOptions so;
  so.seed = 5;
  so.num_campaigns = 6;
  StatusOr<Simulation> sim = Simulate(so);
  ASSERT_TRUE(sim.ok()) << sim.status().ToString();
  const Dataset& d = sim->data;

  std::vector<std::vector<int>> passes_of(d.coil_ids.size());
  for (size_t i = 0; i < d.passes.size(); ++i) {
    passes_of[d.passes[i].coil].push_back(static_cast<int>(i));
  }
  int coils = 0;
  for (size_t k = 0; k < passes_of.size(); ++k) {
    if (passes_of[k].empty()) continue;
    storage::CoilIn in;
    ApiError error;
    ASSERT_TRUE(DecodeCoil(CoilRequest(d, passes_of[k]), kDepth, &in, &error))
        << error.message;
    const Pass& first = d.passes[passes_of[k][0]];
    EXPECT_EQ(in.coil_id, d.coil_ids[k]);
    EXPECT_EQ(in.campaign_id, d.campaigns[first.campaign].id);
    EXPECT_EQ(in.seq, first.seq);
    EXPECT_EQ(in.rolled_at, first.rolled_at);
    EXPECT_EQ(in.grade, d.grades[first.grade]);
    ASSERT_EQ(in.passes.size(), passes_of[k].size());
    for (size_t j = 0; j < in.passes.size(); ++j) {
      const Pass& p = d.passes[passes_of[k][j]];
      const storage::PassIn& q = in.passes[j];
      EXPECT_EQ(q.stand, p.stand);
      // Bit for bit: the shortest round-trip text of each double.
      EXPECT_EQ(q.force_kn, p.force_kn);
      EXPECT_EQ(q.width_mm, p.width_mm);
      EXPECT_EQ(q.length_m, p.length_m);
      EXPECT_EQ(q.entry_thickness_mm, p.entry_thickness_mm);
      EXPECT_EQ(q.exit_thickness_mm, p.exit_thickness_mm);
      EXPECT_EQ(q.temperature_c, p.temperature_c);
      EXPECT_EQ(q.speed_mps, p.speed_mps);
      EXPECT_EQ(q.lubrication, p.lubrication);
      EXPECT_EQ(q.shift_mm, p.shift_mm);
    }
    ++coils;
  }
  EXPECT_GT(coils, 100);

  for (size_t c = 0; c < d.campaigns.size(); ++c) {
    std::vector<int> mounts;
    for (size_t i = 0; i < d.mounts.size(); ++i) {
      if (d.mounts[i].campaign == static_cast<int>(c)) {
        mounts.push_back(static_cast<int>(i));
      }
    }
    storage::RollChangeIn rc;
    ApiError error;
    ASSERT_TRUE(DecodeRollChange(
        RollChangeRequest(d, static_cast<int>(c), mounts), kDepth, &rc, &error))
        << error.message;
    EXPECT_EQ(rc.campaign_id, d.campaigns[c].id);
    EXPECT_EQ(rc.started_at, d.campaigns[c].started_at);
    ASSERT_EQ(rc.rolls.size(), mounts.size());
    for (size_t j = 0; j < mounts.size(); ++j) {
      const Mount& m = d.mounts[mounts[j]];
      EXPECT_EQ(rc.rolls[j].stand, m.stand);
      EXPECT_EQ(rc.rolls[j].position, m.position);
      EXPECT_EQ(rc.rolls[j].roll_id, m.roll_id);
      EXPECT_EQ(rc.rolls[j].roll_type, d.roll_types[m.roll_type]);
      EXPECT_EQ(rc.rolls[j].diameter_mm, m.diameter_mm);
      EXPECT_EQ(rc.rolls[j].hardness_hb, m.hardness_hb);
    }
    UnixSeconds ended_at = 0;
    ASSERT_TRUE(DecodeCampaignEnd(CampaignEndRequest(d, static_cast<int>(c)),
                                  kDepth, &ended_at, &error))
        << error.message;
    EXPECT_EQ(ended_at, d.campaigns[c].ended_at);
  }

  for (size_t i = 0; i < d.measurements.size(); ++i) {
    const Measurement& m = d.measurements[i];
    storage::MeasurementIn in;
    ApiError error;
    ASSERT_TRUE(DecodeMeasurement(MeasurementRequest(d, static_cast<int>(i)),
                                  kDepth, &in, &error))
        << error.message;
    EXPECT_EQ(in.campaign_id, d.campaigns[m.campaign].id);
    EXPECT_EQ(in.stand, m.stand);
    EXPECT_EQ(in.position, m.position);
    EXPECT_EQ(in.roll_id, m.roll_id);
    EXPECT_EQ(in.measured_at, m.measured_at);
    EXPECT_EQ(in.wear_center_um, m.wear_center_um);
  }
}

}  // namespace
}  // namespace rollwear::api
