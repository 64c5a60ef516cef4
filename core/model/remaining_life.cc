#include "core/model/remaining_life.h"

#include <algorithm>
#include <cmath>

namespace rollwear {
namespace {

constexpr double kZ95 = 1.959963984540054;

// Half-width of the 95 % interval after rolling f times the length so far:
// 1.96 sqrt(a + f^2 c) (remaining_life.h).
struct HalfWidth {
  double a = 0;
  double c = 0;
  double operator()(double f) const {
    return kZ95 * std::sqrt(std::max(0.0, a + f * f * c));
  }
};

// The smallest factor f >= 1 (to 1e-12 relative) with d f + sign * half(f)
// >= limit, or empty when it stays below up to kMaxLifeFactor. The bound
// increases with f (for sign -1 only once it can reach the limit, which
// the doubling search finds).
std::optional<double> FactorReaching(double d, double sign,
                                     const HalfWidth& half, double limit_um) {
  auto bound = [&](double f) { return d * f + sign * half(f); };
  if (bound(1.0) >= limit_um) return 1.0;
  double lo = 1.0, hi = 2.0;
  while (bound(hi) < limit_um) {
    lo = hi;
    hi *= 2;
    if (hi > kMaxLifeFactor) return std::nullopt;
  }
  for (int i = 0; i < 200 && hi - lo > 1e-12 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (bound(mid) >= limit_um ? hi : lo) = mid;
  }
  return hi;
}

}  // namespace

RollWearState ScaledRollState(const RollWearState& state, double factor) {
  RollWearState s = state;
  s.wear_um *= factor;
  s.rolled_length_m *= factor;
  for (double& g : s.gradient) g *= factor;
  if (s.ann.has_value()) {
    s.ann->wear_um *= factor;
    s.ann->rolled_length_m *= factor;
    for (double& w : s.ann->member_wear_um) w *= factor;
  }
  return s;
}

std::optional<RemainingLife> PredictRemainingLife(const WearModel& model,
                                                  const RollWearState& state,
                                                  double limit_um) {
  const double d = state.wear_um;
  const double length = state.rolled_length_m;
  const double coils = static_cast<double>(state.coils);
  if (!(d > 0) || !std::isfinite(d) || !(length > 0) || state.coils <= 0 ||
      !(limit_um > 0)) {
    return std::nullopt;
  }
  // a + c and a + 4c from the half-widths at f = 1 and f = 2.
  const auto [lo1, hi1] = WearInterval(model, state);
  const auto [lo2, hi2] = WearInterval(model, ScaledRollState(state, 2.0));
  const double h1 = (hi1 - lo1) / (2 * kZ95), h2 = (hi2 - lo2) / (2 * kZ95);
  HalfWidth half;
  half.c = std::max(0.0, (h2 * h2 - h1 * h1) / 3);
  half.a = std::max(0.0, h1 * h1 - half.c);

  RemainingLife life;
  const double f = std::max(1.0, limit_um / d);
  life.length_m = length * (f - 1);
  life.coils = coils * (f - 1);
  // The upper bound lies above the prediction, so it reaches the limit no
  // later (factor <= f); the lower bound no earlier.
  const double f_hi =
      std::min(FactorReaching(d, +1, half, limit_um).value_or(f), f);
  life.length_lo_m = length * (f_hi - 1);
  life.coils_lo = coils * (f_hi - 1);
  if (const std::optional<double> f_lo =
          FactorReaching(d, -1, half, limit_um)) {
    life.length_hi_m = length * (std::max(*f_lo, f) - 1);
    life.coils_hi = coils * (std::max(*f_lo, f) - 1);
  }
  return life;
}

}  // namespace rollwear
