#include "core/model/profile_interval.h"

#include <cmath>

namespace rollwear {

ProfilePrediction PredictProfile(const ProfileStats& stats,
                                 const ProfileFit* fit, double centre_wear_um,
                                 std::pair<double, double> centre_interval) {
  constexpr double kZ = 1.959963984540054;
  const ProfileGrid& grid = stats.grid();
  const int n = grid.slices();
  const ProfileShape shape = fit != nullptr ? fit->shape : ProfileShape();
  const std::array<double, kProfileBasis> c = shape.Coefficients();
  const double w = centre_wear_um;
  const double below = w - centre_interval.first;
  const double above = centre_interval.second - w;
  ProfilePrediction out;
  out.calibrated = fit != nullptr;
  out.x_mm.resize(n);
  out.wear_um.resize(n);
  out.lo_um.resize(n);
  out.hi_um.resize(n);
  for (int j = 0; j < n; ++j) {
    const std::array<double, kProfileBasis>& s = stats.slice(j);
    double p = 0;
    for (int i = 0; i < kProfileBasis; ++i) p += c[i] * s[i];
    double v = 0;
    if (fit != nullptr) {
      // s' C s over the shape sums with the stored (roll-clustered)
      // covariance C of the coefficients.
      for (int i = 1; i < kProfileBasis; ++i) {
        for (int l = 1; l < kProfileBasis; ++l) {
          v += s[i] * fit->covariance[i - 1][l - 1] * s[l];
        }
      }
      // The point-to-point sd: the roll's shared scatter is already in the
      // centre part above (in proportion); a model stored without it falls
      // back to the whole residual sd (wider, never narrower).
      const double sd = std::isfinite(fit->within_roll_sd_um)
                            ? fit->within_roll_sd_um
                            : fit->residual_sd_um;
      v += sd * sd;
    } else {
      v = (kUncalibratedShapeRel * p) * (kUncalibratedShapeRel * p);
    }
    const double r = w > 0 ? p / w : 0;
    out.x_mm[j] = grid.x(j);
    out.wear_um[j] = p;
    out.lo_um[j] = p - std::sqrt(r * below * r * below + kZ * kZ * v);
    out.hi_um[j] = p + std::sqrt(r * above * r * above + kZ * kZ * v);
  }
  return out;
}

}  // namespace rollwear
