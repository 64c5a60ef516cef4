// What a profile calibration leaves behind: the fitted shape of the wear
// across the barrel (the five free coefficients of g, barrel_profile.h),
// their roll-clustered covariance, the residual scatter and the profile gap
// on the training and validation campaigns. A model version stores it and
// the served profile interval (profile_interval.h) reads it; how it is
// fitted is core/fit/profile_fit.h (first stage, K held) and
// core/fit/profile_joint.h (K and shape jointly). The types live here, with
// the model, so that the layers that store and serve a model need no
// fitting header.
//
// Thread-safety: plain values; the functions are pure.
#ifndef ROLLWEAR_CORE_MODEL_PROFILE_CALIBRATION_H_
#define ROLLWEAR_CORE_MODEL_PROFILE_CALIBRATION_H_

#include <array>
#include <limits>
#include <string>

#include "core/model/barrel_profile.h"

namespace rollwear {

// The fitted coefficients of g, without the fixed 1.
inline constexpr int kProfileShapeParameters = kProfileBasis - 1;
// Their names in reports and JSON: beta2, beta4, alpha1, alpha2, alpha3.
const std::array<std::string, kProfileShapeParameters>& ProfileShapeNames();
// {beta2, beta4, alpha_1, alpha_2, alpha_3} of `shape`.
std::array<double, kProfileShapeParameters> ProfileShapeValues(
    const ProfileShape& shape);

// Mean |measured - predicted| over a set of profile points, in all and by
// zone (the edge zone and the body: core/fit/profile_fit.h; NaN where a set
// is empty).
struct ProfileGap {
  int n_points = 0;
  int n_edge = 0;  // n_edge + n_body <= n_points (points outside the band)
  int n_body = 0;
  int n_profiles = 0;  // rolls
  double gap_um = 0;
  double edge_um = 0;
  double body_um = 0;
};

struct ProfileFit {
  ProfileShape shape;
  // Standard errors of ProfileShapeValues(shape), same order, and their
  // covariance: roll-clustered (Liang & Zeger, 1986, Biometrika 73(1):13-22;
  // core/fit/profile_fit.h; the sqrt of its diagonal).
  std::array<double, kProfileShapeParameters> std_error{};
  std::array<std::array<double, kProfileShapeParameters>,
             kProfileShapeParameters>
      covariance{};
  double residual_sd_um = 0;  // sigma on the training points
  // The residual sd within rolls (one-way ANOVA's within mean square): the
  // point-to-point part of sigma, without the scatter a roll's points share.
  // NaN when unknown (a stored model from before it was kept).
  double within_roll_sd_um = std::numeric_limits<double>::quiet_NaN();
  ProfileGap train;
  ProfileGap validation;
};

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_PROFILE_CALIBRATION_H_
