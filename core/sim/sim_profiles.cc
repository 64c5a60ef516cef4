// The simulator's wear profiles across the barrel: the truth's own
// distribution across the strip (an exponential edge rise, not the model's
// ramps of core/model/barrel_profile.h, so that the model is fitted to a
// form it does not contain) and the noise-free profile of one roll from the
// strips of its campaign.
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "core/base/random.h"
#include "core/sim/sim_internal.h"

namespace rollwear::sim {

SimulatedProfileShape DrawProfileShape(uint64_t seed) {
  Random rng = MakeRandom(seed, Stream::kProfile, 0);
  SimulatedProfileShape shape;
  shape.body_beta2 = rng.Uniform(-0.12, 0.08);
  shape.edge_amplitude = rng.Uniform(0.8, 2.0);
  shape.edge_decay_mm = rng.Uniform(12, 50);
  shape.point_noise_sd_um = 4;
  return shape;
}

double TrueDistribution(const SimulatedProfileShape& shape, double u_mm,
                        double half_width_mm) {
  const double a = std::abs(u_mm);
  if (a > half_width_mm) return 0;
  const double r = u_mm / half_width_mm;
  const double d = half_width_mm - a;
  return 1 + shape.body_beta2 * r * r +
         shape.edge_amplitude * (std::exp(-d / shape.edge_decay_mm) -
                                 std::exp(-half_width_mm / shape.edge_decay_mm));
}

std::vector<std::pair<double, double>> TrueProfile(
    const SimulatedProfileShape& shape, const std::vector<StripTrace>& traces) {
  double reach = 0;
  for (const StripTrace& t : traces) {
    reach = std::max(reach, std::abs(t.centre_mm) + t.half_width_mm);
  }
  const int half = static_cast<int>(std::ceil((reach + 40) / kProfileSpacingMm));
  std::vector<std::pair<double, double>> points;
  points.reserve(2 * half + 1);
  for (int k = -half; k <= half; ++k) {
    const double x = k * kProfileSpacingMm;
    double w = 0;
    for (const StripTrace& t : traces) {
      w += t.wear_um * TrueDistribution(shape, x - t.centre_mm, t.half_width_mm);
    }
    points.emplace_back(x, w);
  }
  return points;
}

}  // namespace rollwear::sim
