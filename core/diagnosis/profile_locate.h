// Locating a mismatch along the barrel: where across the roll the grinder's
// profiles and the model's predicted profiles disagree - the strip-edge
// zones against the body, the drive side against the operator side, and
// either at one stand only.
//
// The residuals are those of the profile model (profile_fit.h: the centre
// model's K and the shape fitted on the training campaigns) on every
// profiled roll, after each roll's own scale (the least-squares factor of
// its measured on its predicted profile) is taken out: a roll's
// multiplicative scatter (its own K) would otherwise swamp every contrast.
// A roll's points share its scatter, so the rolls, not the points, are the
// units: each roll gives one paired contrast per test
// (the mean residual of its points in one zone minus that in the other),
// and the contrasts are tested against 0 by Student's one-sample t test
// across rolls (Student, 1908, Biometrika 6(1):1-25). A test is reported
// as significant when p < alpha / (number of tests) (Bonferroni), its
// standardised effect |mean| / sd is at least 0.2 (a "small" effect,
// Cohen, 1988, Statistical Power Analysis, 2nd ed., ch. 2) and |mean| is at
// least 0.1 of the points' residual sd: hundreds of rolls make a fraction
// of a micron significant (the shape's ramps only approximate a real edge:
// -0.23 µm, p = 2e-6, on one clean simulated seed), which is not a
// mismatch worth naming. x > 0 is the drive side (data-format.md).
//
// The contrasts: "barrel_zone" (edge zone - body), "body_side" (drive-side
// body - operator-side body), "edge_side" (drive-side edge - operator-side
// edge), and "barrel_zone@F<s>" (edge - body on the rolls of stand s). All
// significant ones are reported, strongest first: the first is where the
// mismatch lives (a drive-side edge also lifts "barrel_zone", truly).
// The symmetric shape absorbs an edge rise common to all rolls, so what
// remains in "barrel_zone" is an edge behaving differently from the
// model's shape on average (e.g. by campaign); a side difference or a
// single stand's edges are beyond a symmetric, stand-free shape and are
// located, not explained.
//
// Thread-safety: LocateAlongBarrel is a pure function of its arguments.
#ifndef ROLLWEAR_CORE_DIAGNOSIS_PROFILE_LOCATE_H_
#define ROLLWEAR_CORE_DIAGNOSIS_PROFILE_LOCATE_H_

#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/dataset/dataset.h"
#include "core/diagnosis/diagnosis_thresholds.h"
#include "core/model/metrics.h"
#include "core/model/wear_model.h"

namespace rollwear {

struct BarrelContrast {
  std::string dimension;  // "barrel_zone", "body_side", "edge_side", ...
  std::string where;      // "strip-edge zones", "drive side", ...
  double mean_um = 0;     // mean over rolls of the contrast (first - second)
  double sd_um = 0;       // its sd over rolls
  int n_rolls = 0;
  double t = 0;
  double p_value = 1;
  bool significant = false;
};

struct BarrelLocate {
  std::vector<BarrelContrast> contrasts;  // strongest (smallest p) first
  // Mean roll-scaled residual (measured - a_r predicted) over all points of
  // each zone:
  // operator-side edge, operator-side body, drive-side body, drive-side edge.
  double edge_operator_um = 0, body_operator_um = 0;
  double body_drive_um = 0, edge_drive_um = 0;
  int n_points = 0;
  int n_rolls = 0;
  double point_sd_um = 0;  // rms of the points' roll-scaled residuals

  bool any_significant() const;
};

// Fits the shape with `model`'s K on split.train (FitProfileShape) and
// tests the contrasts over the profiled rolls of all campaigns; the
// effect-size and material cuts of a significant contrast (0.2 and 0.1
// above) are thresholds.barrel_min_effect and barrel_material. Errors:
// those of FitProfileShape (no or too few profile points).
StatusOr<BarrelLocate> LocateAlongBarrel(
    const WearModel& model, const Dataset& data, const DatasetIndex& index,
    const CampaignSplit& split, double alpha = 0.001,
    const DiagnosisThresholds& thresholds = DiagnosisThresholds{});

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_DIAGNOSIS_PROFILE_LOCATE_H_
