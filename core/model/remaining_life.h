// Remaining life of a mounted roll: how much more it can roll, at the mix
// its campaign has rolled so far, before its predicted wear reaches a wear
// limit, with an interval from the model's 95 % prediction interval.
//
// "At the current mix" means each further metre adds wear, and wear
// gradient with respect to the model parameters, in the proportion the
// campaign has so far: after rolling f times the length rolled so far
// (L), the state is the current one scaled by f (wear d*f, gradient g*f,
// for the recurrent network each member's wear times f). Both the
// parametric law (wear_i = K * Load(pass_i), summed over passes) and its
// gradient are sums over passes, so this scaling is exact for a campaign
// whose future passes repeat its past mix.
//
//   remaining length  R   = L * (limit / d - 1)
//   remaining coils   R_c = N * (limit / d - 1)           (N coils so far)
//   interval [R_lo, R_hi]: R_lo = L * (f_hi - 1), where the upper bound of
//   the wear interval at f_hi (WearInterval of the scaled state) reaches
//   the limit; R_hi = L * (f_lo - 1), where its lower bound does. The
//   interval's half-width is 1.96 * sqrt(A + f^2 C) for every model
//   (A = sigma0^2; C = (rho d)^2 + g' Cov g, or for the network the
//   members' variance plus (rho d)^2, all scaling with f^2), so A and C
//   follow from the half-widths at f = 1 and f = 2, and f_hi, f_lo are
//   found by bisection on d f +- 1.96 sqrt(A + f^2 C) = limit. The coils'
//   interval scales the same way (N instead of L).
// The interval is the model's (parameter covariance propagated through the
// gradient, plus the fitted noise model sigma0^2 + (rho d)^2, wear_model.h),
// so it also covers the scatter of a roll's wear about the model; it does
// not know how the rest of the campaign's mix will differ from the past
// (docs/model.md, "Remaining life", reports its coverage on a simulated
// mill).
//
// Thread-safety: pure functions; the model and the state are only read.
#ifndef ROLLWEAR_CORE_MODEL_REMAINING_LIFE_H_
#define ROLLWEAR_CORE_MODEL_REMAINING_LIFE_H_

#include <optional>

#include "core/model/predictor.h"
#include "core/model/wear_model.h"

namespace rollwear {

struct RemainingLife {
  double length_m = 0;  // remaining rolled length until the limit (>= 0)
  double coils = 0;     // remaining coils until the limit (>= 0)
  // Interval of length_m: lo when the wear's upper bound reaches the limit,
  // hi when its lower bound does; hi is empty when the lower bound never
  // reaches it (an interval so wide its lower bound stays below the limit
  // up to kMaxLifeFactor times the length rolled so far).
  double length_lo_m = 0;
  std::optional<double> length_hi_m;
  double coils_lo = 0;
  std::optional<double> coils_hi;
};

// Up to this many times the length rolled so far a bound is searched for.
inline constexpr double kMaxLifeFactor = 1e6;

// The state after rolling `factor` times its rolled length at its mix so far
// (see above): wear, gradient, length and the network members' wear scaled
// (not the coil count: WearInterval does not read it).
RollWearState ScaledRollState(const RollWearState& state, double factor);

// The remaining life of `state` until `limit_um` (> 0); empty when the
// roll has no wear yet (no coils, or zero wear: there is no mix to
// extrapolate). A roll already at or over the limit has 0 remaining.
std::optional<RemainingLife> PredictRemainingLife(const WearModel& model,
                                                  const RollWearState& state,
                                                  double limit_um);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_REMAINING_LIFE_H_
