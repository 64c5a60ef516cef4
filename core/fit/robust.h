// The robust loss of rollwear's wear fits (calibration.h, term_fit.h and the
// diagnosis): Huber's M-estimator computed by iteratively reweighted least
// squares, so that a few plausible-looking gross grinder errors (tens to
// hundreds of µm off) neither pull the coefficients nor create or hide
// findings, and the suspected readings can be listed.
//
// Scale. Readings are standardised by the heteroscedastic noise model
//   sd_i = c * sqrt(sigma0^2 + (rho * pred_i)^2)      (wear_model.h)
// fitted on the readings within kHuberK robust sd's of a first, global
// scale s0 = 1.4826 * MAD(e) (Hampel 1974, "The influence curve and its role
// in robust estimation", JASA 69:383), and c = 1.4826 * MAD(e_i / sd_i) so
// that the standardised residuals u_i = e_i / sd_i have unit robust spread.
// Gross errors therefore cannot inflate the scale they are judged by.
//
// Loss. Huber's rho with cut-off k = kHuberK sd's (Huber 1964, Ann. Math.
// Stat. 35:73; Huber & Ronchetti 2009, "Robust Statistics", 2nd ed., ch. 7):
// quadratic for |u| <= k, linear beyond, i.e. weight w_i = min(1, k/|u_i|)
// in IRLS (Holland & Welsch 1977, Commun. Stat. A6:813). k = 3 keeps
// ~99.7 % of Gaussian readings at full weight: on clean data the estimates
// are those of least squares to well inside their standard errors (the
// measurement is in docs/model.md), while a reading 100 sd off carries the
// influence of one 3 sd off.
//
// Listing. A reading with |u_i| > kOutlierSigmas is a suspected gross error
// (a Gaussian reading exceeds 4 sd once in ~16,000): it is kept, at Huber
// weight, and listed with its standardised residual.
//
// Thread-safety: pure functions of their arguments.
#ifndef ROLLWEAR_CORE_FIT_ROBUST_H_
#define ROLLWEAR_CORE_FIT_ROBUST_H_

#include <string>
#include <vector>

#include "core/dataset/dataset.h"
#include "core/model/wear_model.h"

namespace rollwear {

inline constexpr double kHuberK = 3.0;         // Huber cut-off, in sd's
inline constexpr double kOutlierSigmas = 4.0;  // listing threshold, in sd's
inline constexpr double kMadToSd = 1.4826;     // 1 / Phi^-1(3/4)

// 1.4826 * median |x - median(x)|: the sd of Gaussian data, unmoved by a
// minority of gross values. 0 for an empty vector.
double RobustSd(std::vector<double> x);

// Huber's IRLS weight min(1, k / |u|) of a standardised residual u.
double HuberWeight(double u, double k = kHuberK);

// The robust standardisation of errors e_i = measured - predicted at
// predictions pred_i (see the top of this file).
struct RobustNoise {
  double noise_sd_um = 0;      // c * sigma0
  double noise_rel = 0;        // c * rho
  std::vector<double> sd;      // per reading, floored at 1e-6 µm
  std::vector<double> u;       // e_i / sd_i
  std::vector<double> weight;  // HuberWeight(u_i)
  // sd of a reading predicted at `pred` under this noise model.
  double SdAt(double pred) const;
};
RobustNoise FitRobustNoise(const std::vector<double>& pred,
                           const std::vector<double>& err);

// The served interval's scale. The robust noise model describes the bulk
// of the residuals (its size is a MAD); real readings have heavier tails,
// and its nominal 95 % interval then covers fewer (87-90 % of the study's
// held-out readings). Returns c = max(1, q / 1.96), q the 95th percentile
// of |u_i| over the training readings, so that sd * c covers at least 95 %
// of them: an empirical calibration of the interval on the fitted readings
// (the idea of split-conformal intervals, Lei, G'Sell, Rinaldo, Tibshirani
// & Wasserman 2018, JASA 113:1094, here on training residuals, which are
// optimistic: held-out coverage stays a little under). Never narrows.
double TailCoverageScale(const std::vector<double>& u);

// A reading whose standardised robust residual exceeds kOutlierSigmas.
struct SuspectedOutlier {
  int campaign = -1;  // index into Dataset::campaigns
  int slot = -1;      // roll position slot (dataset.h)
  std::string campaign_id;
  int stand = 0;
  Position position = Position::kTop;
  bool training = true;  // in the fitted (training) campaigns
  double measured_um = 0;
  double predicted_um = 0;
  double standardized_residual = 0;  // (measured - predicted) / sd
};

// Fills campaign_id, stand and position of each outlier from `data` and
// sorts them by |standardized_residual|, largest first.
void NameOutliers(const Dataset& data, std::vector<SuspectedOutlier>* outliers);

// "C0042 F6/top: measured 312.0 µm, predicted 180.2 µm, r/sd = +6.1
// (training)".
std::string OutlierLine(const SuspectedOutlier& o);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_FIT_ROBUST_H_
