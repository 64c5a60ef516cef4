// The first stage of the profile calibration: the shape of the wear across
// the barrel (the five free coefficients of g in barrel_profile.h) fitted to
// the grinder's profile points with K held at the centre calibration, and
// the profile gap on the training and validation campaigns.
//
// For each measured profile (one roll in one campaign) the calibrated
// centre model gives each pass its wear w_p = K_p Load_p (times any adopted
// wear-rate terms: the daemon's predictor, predictor.h), and the roll's
// ProfileStats hold, per slice, the six sums
//   s_i(x) = sum_p w_p basis_i(x - c_p, b_p),   i = 0..5
// (basis {1, (u/b)^2, (u/b)^4, ramps 1..3}; c_p by the shift convention). A
// grinder point at x is read from them by linear interpolation between
// slices. The predicted profile is s_0(x) + sum_{i>=1} theta_i s_i(x), linear
// in theta = (beta2, beta4, alpha_1..3), so with K fixed the fit is
// ordinary least squares on the training campaigns' points,
//   minimise sum (y - s_0 - S theta)^2,
// solved by column-pivoted Householder QR (Golub & Van Loan 2013, Matrix
// Computations, 4th ed., sec. 5.4). The points of one roll share its
// roll-to-roll scatter, so they are not independent: the covariance of
// theta is the roll-clustered sandwich (Liang & Zeger, 1986, Biometrika
// 73(1):13-22), B M B with B = (S'S)^-1 and M = G/(G-1) sum_r (S_r'e_r)
// (S_r'e_r)' over the G training rolls, not sigma^2 (S'S)^-1, which treats
// a profile's points as independent and is optimistic. The joint
// Levenberg-Marquardt fit of K and the shape, with the same roll-clustered
// standard errors, is the second stage (profile_joint.h).
//
// Profile gap: mean |measured - predicted| over the points, in all, and
// split into the strip-edge zone and the body. The strips of a roll's
// campaign wear the band [lo, hi] = [min_p(c_p - b_p), max_p(c_p + b_p)]
// (the widest strips at their outermost shifts). A point is in the edge
// zone when it lies within `edge_zone_mm` (100 mm) of either end of that
// band, inside or outside it: where the outer box-wear peaks stand and the
// worn band ends. It is in the body when it lies inside the band, farther
// than that from both ends (the inner strips' edges, with a width schedule,
// fall in the body). Points farther outside the band are in neither zone
// (they count in the overall gap only).
//
// Thread-safety: FitProfileShape is a pure function of its arguments.
#ifndef ROLLWEAR_CORE_FIT_PROFILE_FIT_H_
#define ROLLWEAR_CORE_FIT_PROFILE_FIT_H_

#include <array>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/base/status.h"
#include "core/dataset/dataset.h"
#include "core/model/barrel_profile.h"
#include "core/model/metrics.h"
#include "core/model/profile_calibration.h"
#include "core/model/wear_model.h"

namespace rollwear {

struct ProfileFitOptions {
  ProfileGrid grid;
  double edge_zone_mm = 100;  // see the edge zone above
};

// The indices of data.profile_points of each measured profile, keyed by
// (campaign, roll position slot), in data order within a profile.
std::map<std::pair<int, int>, std::vector<int>> ProfilePointsByRoll(
    const Dataset& data);

// Fits the shape on the profile points of split.train with `model`'s K and
// measures the gap on both halves. Errors: fewer training points than
// 2 x 5, or a shape the training profiles do not identify (rank < 5).
StatusOr<ProfileFit> FitProfileShape(const WearModel& model,
                                     const Dataset& data,
                                     const DatasetIndex& index,
                                     const CampaignSplit& split,
                                     const ProfileFitOptions& options = {});

// The profile gap of `shape` under `model`'s K on the profiles of
// `campaigns` (ascending campaign indices).
ProfileGap ProfileGapOf(const WearModel& model, const ProfileShape& shape,
                        const Dataset& data, const DatasetIndex& index,
                        const std::vector<int>& campaigns,
                        const ProfileFitOptions& options = {});

// The predicted wear at every slice of options.grid of the roll in `slot`
// (dataset.h) in `campaign` under `model`'s K and `shape`; empty when no
// roll is mounted there.
std::vector<double> PredictRollProfile(const WearModel& model,
                                       const ProfileShape& shape,
                                       const Dataset& data,
                                       const DatasetIndex& index, int campaign,
                                       int slot,
                                       const ProfileFitOptions& options = {});

// One grinder point with its prediction and zone (see the header comment).
struct ProfileResidual {
  int campaign = -1;
  int slot = -1;  // roll position slot (dataset.h)
  double x_mm = 0;
  double measured_um = 0;
  double predicted_um = 0;
  bool edge = false;  // in the strip-edge zone
  bool body = false;  // in the body (neither: beyond the worn band)
};

// The profile points of `campaigns` (ascending) with their predictions
// under `model`'s K and `shape`, in (campaign, slot, data) order.
std::vector<ProfileResidual> ProfileResiduals(
    const WearModel& model, const ProfileShape& shape, const Dataset& data,
    const DatasetIndex& index, const std::vector<int>& campaigns,
    const ProfileFitOptions& options = {});

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_FIT_PROFILE_FIT_H_
