#include "core/model/wear_model.h"

#include <cmath>
#include <limits>

namespace rollwear {

void WearModel::AddPassGradient(const PassLoadInput& in, int p, int r, int s,
                                double* grad, double multiplier) const {
  // d(K*L*M)/d(log k_j) = K*L*M for every factor j of the cell;
  // d(K*L*M)/da = K*L*M*ln(stress) for Cao.
  const double wear = PassWear(in, p, r, s) * multiplier;
  for (size_t g = 0; g < structure.groups().size(); ++g) {
    const int c = structure.CoefficientOf(static_cast<int>(g), p, r, s);
    if (c >= 0) grad[c] += wear;
  }
  if (law == WearLaw::kCao) {
    grad[structure.num_coefficients()] += wear * std::log(CaoStress(in));
  }
}

std::pair<double, double> WearModel::Interval(double wear,
                                              const double* grad) const {
  double var = noise_sd_um * noise_sd_um + (noise_rel * wear) * (noise_rel * wear);
  const int n = num_parameters();
  if (covariance.rows() == n) {
    Eigen::Map<const Eigen::VectorXd> g(grad, n);
    var += g.dot(covariance * g);
  }
  const double half = 1.959963984540054 * std::sqrt(std::max(var, 0.0));
  return {wear - half, wear + half};
}

double WearModel::LogKStdError(int p, int r, int s) const {
  const int n = num_parameters();
  if (covariance.rows() != n) return std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
  for (size_t g = 0; g < structure.groups().size(); ++g) {
    const int c = structure.CoefficientOf(static_cast<int>(g), p, r, s);
    if (c >= 0) e[c] = 1;
  }
  return std::sqrt(std::max(0.0, e.dot(covariance * e)));
}

std::vector<std::pair<std::string, double>> WearModel::NamedCoefficients() const {
  std::vector<std::pair<std::string, double>> out;
  for (int i = 0; i < structure.num_coefficients(); ++i) {
    out.emplace_back(structure.CoefficientName(i), k[i]);
  }
  if (law == WearLaw::kCao) out.emplace_back("a", cao_exponent);
  return out;
}


// Fits sigma0^2 + (rho d)^2 to squared residuals by least squares on
// [1, d^2]; falls back to one term when the other would be negative.
void FitNoiseModel(const std::vector<double>& pred, const std::vector<double>& err,
                   WearModel* model) {
  double s00 = 0, s01 = 0, s11 = 0, t0 = 0, t1 = 0;
  for (size_t i = 0; i < pred.size(); ++i) {
    const double x = pred[i] * pred[i];
    const double y = err[i] * err[i];
    s00 += 1;
    s01 += x;
    s11 += x * x;
    t0 += y;
    t1 += x * y;
  }
  if (s00 == 0) return;
  const double det = s00 * s11 - s01 * s01;
  double a = t0 / s00, b = 0;
  if (det > 1e-12 * s00 * s11) {
    a = (s11 * t0 - s01 * t1) / det;
    b = (s00 * t1 - s01 * t0) / det;
  }
  if (b < 0) {
    b = 0;
    a = t0 / s00;
  } else if (a < 0) {
    a = 0;
    b = s11 > 0 ? t1 / s11 : 0;
  }
  model->noise_sd_um = std::sqrt(a);
  model->noise_rel = std::sqrt(b);
}

}  // namespace rollwear
