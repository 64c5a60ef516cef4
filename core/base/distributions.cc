#include "core/base/distributions.h"

#include <math.h>

#include <cmath>
#include <limits>

namespace rollwear {
namespace {

// ln Gamma(x) without touching glibc's global `signgam` (std::lgamma writes
// it, a data race when the diagnosis evaluates p-values on several threads):
// the reentrant lgamma_r of glibc/POSIX-2008 extensions.
double LogGamma(double x) {
  int sign = 0;
  return ::lgamma_r(x, &sign);
}

constexpr double kEps = 1e-15;
constexpr double kTiny = 1e-300;
constexpr int kMaxIter = 10000;

// P(a, x) by its series (NR 6.2.5), valid for x < a + 1.
double GammaPSeries(double a, double x) {
  double ap = a, sum = 1.0 / a, del = sum;
  for (int n = 0; n < kMaxIter; ++n) {
    ap += 1;
    del *= x / ap;
    sum += del;
    if (std::abs(del) < std::abs(sum) * kEps) break;
  }
  return sum * std::exp(-x + a * std::log(x) - LogGamma(a));
}

// Q(a, x) by its continued fraction (NR 6.2.7, modified Lentz), x >= a + 1.
double GammaQFraction(double a, double x) {
  double b = x + 1 - a, c = 1 / kTiny, d = 1 / b, h = d;
  for (int i = 1; i < kMaxIter; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1) < kEps) break;
  }
  return std::exp(-x + a * std::log(x) - LogGamma(a)) * h;
}

// Continued fraction of the incomplete beta (NR 6.4.5, modified Lentz).
double BetaFraction(double x, double a, double b) {
  const double qab = a + b, qap = a + 1, qam = a - 1;
  double c = 1, d = 1 - qab * x / qap;
  if (std::abs(d) < kTiny) d = kTiny;
  d = 1 / d;
  double h = d;
  for (int m = 1; m < kMaxIter; ++m) {
    const int m2 = 2 * m;
    double aa = m * (b - m) * x / ((qam + m2) * (a + m2));
    d = 1 + aa * d;
    if (std::abs(d) < kTiny) d = kTiny;
    c = 1 + aa / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1 / d;
    h *= d * c;
    aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
    d = 1 + aa * d;
    if (std::abs(d) < kTiny) d = kTiny;
    c = 1 + aa / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1) < kEps) break;
  }
  return h;
}

}  // namespace

double RegularizedGammaQ(double a, double x) {
  if (!(a > 0) || std::isnan(x)) return std::numeric_limits<double>::quiet_NaN();
  if (x <= 0) return 1.0;
  if (x < a + 1) return 1.0 - GammaPSeries(a, x);
  return GammaQFraction(a, x);
}

double RegularizedBeta(double x, double a, double b) {
  if (x <= 0) return 0.0;
  if (x >= 1) return 1.0;
  const double front = std::exp(LogGamma(a + b) - LogGamma(a) - LogGamma(b) +
                                a * std::log(x) + b * std::log1p(-x));
  // Use the fraction where it converges fast (NR 6.4.6 symmetry).
  if (x < (a + 1) / (a + b + 2)) return front * BetaFraction(x, a, b) / a;
  return 1.0 - front * BetaFraction(1 - x, b, a) / b;
}

double ChiSquareSurvival(double x, double k) {
  if (x <= 0) return 1.0;
  return RegularizedGammaQ(k / 2, x / 2);
}

double StudentTTwoSided(double t, double nu) {
  if (std::isnan(t)) return std::numeric_limits<double>::quiet_NaN();
  return RegularizedBeta(nu / (nu + t * t), nu / 2, 0.5);
}

double FSurvival(double f, double d1, double d2) {
  if (f <= 0) return 1.0;
  return RegularizedBeta(d2 / (d2 + d1 * f), d2 / 2, d1 / 2);
}

}  // namespace rollwear
