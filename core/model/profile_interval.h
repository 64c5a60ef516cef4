// The predicted wear profile of a mounted roll across the barrel, with a
// 95 % interval per slice, from the roll's ProfileStats (the six per-slice
// sums the predictor keeps, predictor.h) and the model's profile shape
// (profile_calibration.h, fitted by core/fit/profile_fit.h), or the default
// shape g = 1 when none is calibrated.
//
// Profile at slice j:  P_j = s_j0 + theta . s_j   (theta = beta2, beta4,
// alpha_1..3; all 0 uncalibrated: uniform wear under the strip).
// Interval: two parts combined in quadrature,
//   - K, the centre's uncertainty, carried in proportion: the centre
//     interval [lo, hi] of the centre wear W (predictor.h) scaled by
//     r_j = P_j / W, i.e. lower half-width r_j (W - lo), upper r_j (hi - W)
//     (K multiplies every slice alike; g(0) = 1 makes P at x = 0 equal W);
//   - the shape: calibrated, v_j = s_j' C s_j + sigma^2, with C the shape
//     coefficients' roll-clustered covariance (profile_calibration.h; a model
//     stored before it was kept has its diagonal se_i^2 only) and sigma the
//     profile fit's residual sd within rolls (the point-to-point part; the
//     scatter a roll's points share is its scale's, carried by the first
//     part; a model stored without it uses the whole residual sd), at
//     1.96 sigma; uncalibrated, the
//     shape is not known, and the interval adds kUncalibratedShapeRel P_j
//     (1.96 times it) for the edge rise or crown that g = 1 leaves out.
//   lo_j = P_j - sqrt((r_j (W - lo))^2 + 1.96^2 v_j), hi_j likewise.
// Coverage: tests/core/profile_coverage_test.cc (98.3 % of the noise-free
// profile slices and 98.2 % of grinder points for a nominal 95 %).
//
// Thread-safety: pure function.
#ifndef ROLLWEAR_CORE_MODEL_PROFILE_INTERVAL_H_
#define ROLLWEAR_CORE_MODEL_PROFILE_INTERVAL_H_

#include <utility>
#include <vector>

#include "core/model/barrel_profile.h"
#include "core/model/profile_calibration.h"

namespace rollwear {

// The relative sd of the shape when none is calibrated: box-wear edge
// peaks and crowns of 10-40 % of the body's wear are common, so 20 %
// (a 95 % band of about +/- 39 % of the profile) covers the usual shapes.
inline constexpr double kUncalibratedShapeRel = 0.2;

struct ProfilePrediction {
  bool calibrated = false;
  std::vector<double> x_mm;     // slice centres (ProfileGrid::x)
  std::vector<double> wear_um;  // P_j
  std::vector<double> lo_um;
  std::vector<double> hi_um;
};

// `fit` null: the default shape (uncalibrated). `centre_wear_um` and
// `centre_interval` are the roll's centre prediction (WearInterval).
ProfilePrediction PredictProfile(const ProfileStats& stats,
                                 const ProfileFit* fit, double centre_wear_um,
                                 std::pair<double, double> centre_interval);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_PROFILE_INTERVAL_H_
