// WearModel: a calibrated wear model as predictions use it - a wear law, a
// K structure with its coefficients, the Cao exponent, the covariance of the
// coefficients and a noise model, so that any campaign's predicted centre
// wear comes with a prediction interval.
//
// Prediction interval (95 %) for a predicted wear d with gradient g of d with
// respect to the log-coefficients (and the Cao exponent):
//   var(d) = g' * Sigma * g  +  sigma0^2 + (rho * d)^2
// where Sigma is the coefficient covariance from the Jacobian (Gauss-Newton
// approximation, rank-deficient directions removed by SVD) and
// sigma0^2 + (rho d)^2 the residual variance fitted on training campaigns
// (grinder noise plus roll-to-roll scatter, which grows with wear).
//
// A served model can instead be the study's recurrent network (ann_model.h):
// then `ann` is set, the law is Wang's, K comes from the network pass by
// pass, the coefficients, structure and terms are unused, and the interval
// is var(d) = s_members^2 + sigma0^2 + (rho d)^2 with s_members the spread
// of the ensemble members' predictions (predictor.h).
//
// Thread-safety: immutable after calibration; const methods are safe to call
// concurrently.
#ifndef ROLLWEAR_CORE_MODEL_WEAR_MODEL_H_
#define ROLLWEAR_CORE_MODEL_WEAR_MODEL_H_

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/model/k_structure.h"
#include "core/model/model_terms.h"
#include "core/model/wear_law.h"

namespace rollwear {

struct AnnModel;  // ann_model.h

struct WearModel {
  WearLaw law = WearLaw::kWang;
  KStructure structure;
  // Natural (positive) coefficients in the reported gauge (see
  // k_structure.h), size structure.num_coefficients().
  std::vector<double> k;
  double cao_exponent = 1.0;  // Cao's a; unused by other laws
  // Covariance of (log k..., a) in the reported gauge; empty when unknown.
  Eigen::MatrixXd covariance;
  // Residual noise model: var = noise_sd_um^2 + (noise_rel * wear)^2.
  double noise_sd_um = 0;
  double noise_rel = 0;
  // Terms adopted from a diagnosis (model_terms.h): wear-rate terms
  // multiply each pass's wear, additive terms add wear to each pass (wear
  // per coil); measurement terms only shift what the grinder is expected
  // to read and do not change predicted wear.
  std::vector<ModelTerm> terms;
  // The recurrent network when this model is the ANN (see above); shared,
  // immutable.
  std::shared_ptr<const AnnModel> ann;

  bool is_ann() const { return ann != nullptr; }

  int num_parameters() const {
    return structure.num_coefficients() + (law == WearLaw::kCao ? 1 : 0);
  }
  // K for level indices of the structure (-1 = unknown level, factor 1).
  double K(int p, int r, int s) const { return structure.K(k, p, r, s); }
  // Wear of one pass in µm on a roll at position p of type r, grade s.
  double PassWear(const PassLoadInput& in, int p, int r, int s) const {
    return K(p, r, s) * Load(law, in, cao_exponent);
  }
  // Adds d(pass wear)/d(log k_j, a) to `grad` (size num_parameters()) for
  // a pass whose wear is multiplied by `multiplier` (adopted terms).
  void AddPassGradient(const PassLoadInput& in, int p, int r, int s, double* grad,
                       double multiplier = 1.0) const;
  // 95 % interval [lo, hi] for predicted wear `wear` with gradient `grad`.
  std::pair<double, double> Interval(double wear, const double* grad) const;
  // Standard error of log K(p, r, s) (gauge-invariant), NaN if unknown.
  double LogKStdError(int p, int r, int s) const;

  // Coefficients by name ("kF[F6/top]" ..., plus "a" for Cao).
  std::vector<std::pair<std::string, double>> NamedCoefficients() const;
};

// Fits the noise model sigma0^2 + (rho d)^2 of `model` to residuals `err` of
// predictions `pred` by least squares on [1, d^2] against err^2; falls back
// to one term when the other would be negative.
void FitNoiseModel(const std::vector<double>& pred, const std::vector<double>& err,
                   WearModel* model);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_WEAR_MODEL_H_
