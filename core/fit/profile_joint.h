// The second stage of the profile calibration: K and the shape of the wear
// across the barrel fitted jointly by Levenberg-Marquardt on the training
// campaigns' centre measurements and grinder profile points, with exact
// derivatives, bounds and standard errors.
//
// Model. A pass p on a roll wears w_p = K(pos, type, grade_p) * Load_p * m_p
// (wear_law.h, k_structure.h; m_p the adopted wear-rate terms, held at
// their fitted values; Cao's exponent a held at the centre fit). K is a
// product of factors, so per roll and per grade s of its campaign the
// load-weighted sums
//   C_s = sum_{p in s} Load_p m_p,
//   S_{s,i}(x) = sum_{p in s} Load_p m_p basis_i(x - c_p, b_p), i = 0..5,
// are sufficient statistics that do not depend on K or the shape: the fit's
// cost is independent of the number of strips. The roll's centre wear is
// sum_s K_s C_s (plus any measurement terms, fixed) and its profile at x is
//   P(x) = sum_s K_s sum_i theta_i S_{s,i}(x),    theta = (1, beta2, ..)
// with exact derivatives
//   dP/dlog k_j = sum_s [k_j in K_s] K_s sum_i theta_i S_{s,i}(x),
//   dP/dtheta_i = sum_s K_s S_{s,i}(x).
//
// Weighting. A centre reading counts with 1 / sd_c^2 from the centre
// model's noise model (wear_model.h). The points of one profile share the
// roll's scatter (its own K deviation), so they are not independent: each
// point counts with 1 / (sigma_p^2 (1 + (n_r - 1) rho)), the design effect
// of a cluster of n_r points with intra-cluster correlation rho (Kish,
// 1965, Survey Sampling, Wiley, sec. 5.4). sigma_p and rho are estimated
// from the first stage's training residuals (profile_fit.h; rho by the
// one-way ANOVA estimator of the intraclass correlation, Fisher 1925,
// Statistical Methods for Research Workers, sec. 38). A profile of n
// points then weighs about as much as 1/rho readings: the profiles inform
// the shape with all their points but cannot outvote the centre readings
// on K with their sheer number.
//
// Bounds: beta2, beta4 in [-0.45, 10] (so g stays >= 0.1 across the body),
// alpha_m in [-5, 50], log k within +-5 of the centre fit. Gauge: as in the
// diagnosis refits (term_fit.h), levels without data and the heaviest roll
// type and grade level are held; the result is returned in the reported
// gauge (k_structure.h). Standard errors: the cluster-robust sandwich with
// the rolls as clusters (Liang & Zeger, 1986, Biometrika 73(1):13-22), which
// stays right whatever the correlation of a roll's points; a parameter at a
// bound is named in `at_bound` and its standard error is not meaningful.
//
// Thread-safety: FitProfileJoint is a pure function of its arguments.
#ifndef ROLLWEAR_CORE_FIT_PROFILE_JOINT_H_
#define ROLLWEAR_CORE_FIT_PROFILE_JOINT_H_

#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/dataset/dataset.h"
#include "core/fit/profile_fit.h"
#include "core/model/metrics.h"
#include "core/model/wear_model.h"

namespace rollwear {

struct JointProfileFit {
  // The centre model with the jointly fitted K (noise model, terms and
  // covariance of the centre fit kept).
  WearModel model;
  // Shape, its standard errors from the joint fit, residual sd and the
  // profile gap (train/validation) under the joint K.
  ProfileFit profile;
  // Mean |measured - expected| of the centre readings under the joint K.
  double centre_gap_train_um = 0;
  double centre_gap_val_um = 0;
  double intra_roll_correlation = 0;  // rho of the weighting
  int iterations = 0;
  bool converged = false;
  std::vector<std::string> at_bound;  // names of parameters at a bound
};

// Fits K and the shape jointly, starting from the centre model `centre` and
// the first stage `first` (FitProfileShape with the same split). Errors:
// no profile points on the training campaigns, or a failed solve.
StatusOr<JointProfileFit> FitProfileJoint(
    const WearModel& centre, const Dataset& data, const DatasetIndex& index,
    const CampaignSplit& split, const ProfileFit& first,
    const ProfileFitOptions& options = {});

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_FIT_PROFILE_JOINT_H_
