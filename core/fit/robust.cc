// Huber IRLS weights and the robust noise model; see robust.h.
#include "core/fit/robust.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rollwear {
namespace {

double Median(std::vector<double>* x) {
  const size_t n = x->size();
  std::nth_element(x->begin(), x->begin() + n / 2, x->end());
  const double hi = (*x)[n / 2];
  if (n % 2 == 1) return hi;
  return 0.5 * (hi + *std::max_element(x->begin(), x->begin() + n / 2));
}

}  // namespace

double RobustSd(std::vector<double> x) {
  if (x.empty()) return 0;
  const double m = Median(&x);
  for (double& v : x) v = std::abs(v - m);
  return kMadToSd * Median(&x);
}

double HuberWeight(double u, double k) {
  const double a = std::abs(u);
  return a <= k ? 1.0 : k / a;
}

double RobustNoise::SdAt(double pred) const {
  return std::max(std::hypot(noise_sd_um, noise_rel * pred), 1e-6);
}

double TailCoverageScale(const std::vector<double>& u) {
  std::vector<double> a;
  for (double x : u) {
    if (std::isfinite(x)) a.push_back(std::abs(x));
  }
  if (a.empty()) return 1;
  const size_t k = static_cast<size_t>(std::ceil(0.95 * a.size())) - 1;
  std::nth_element(a.begin(), a.begin() + k, a.end());
  return std::max(1.0, a[k] / 1.959963984540054);
}

RobustNoise FitRobustNoise(const std::vector<double>& pred,
                           const std::vector<double>& err) {
  RobustNoise out;
  if (pred.empty()) return out;
  // Inliers of a first, global robust scale fix the shape of the noise
  // model (sigma0, rho), re-selected twice by the model's own sd (a global
  // scale would cut the tails of large, relatively noisier readings); the
  // MAD of the standardised errors then fixes its size.
  const double s0 = RobustSd(err);
  WearModel noise;
  noise.noise_sd_um = s0;
  noise.noise_rel = 0;
  for (int pass = 0; pass < 3; ++pass) {
    std::vector<double> p_in, e_in;
    for (size_t i = 0; i < pred.size(); ++i) {
      const double sd =
          std::hypot(noise.noise_sd_um, noise.noise_rel * pred[i]);
      if (!(sd > 0) || std::abs(err[i]) <= kHuberK * sd) {
        p_in.push_back(pred[i]);
        e_in.push_back(err[i]);
      }
    }
    FitNoiseModel(p_in, e_in, &noise);
  }
  out.noise_sd_um = noise.noise_sd_um;
  out.noise_rel = noise.noise_rel;
  std::vector<double> u(pred.size());
  for (size_t i = 0; i < pred.size(); ++i) u[i] = err[i] / out.SdAt(pred[i]);
  const double c = RobustSd(u);
  if (c > 0 && std::isfinite(c)) {
    out.noise_sd_um *= c;
    out.noise_rel *= c;
  }
  out.sd.resize(pred.size());
  out.u.resize(pred.size());
  out.weight.resize(pred.size());
  for (size_t i = 0; i < pred.size(); ++i) {
    out.sd[i] = out.SdAt(pred[i]);
    out.u[i] = err[i] / out.sd[i];
    out.weight[i] = HuberWeight(out.u[i]);
  }
  return out;
}

void NameOutliers(const Dataset& data,
                  std::vector<SuspectedOutlier>* outliers) {
  for (SuspectedOutlier& o : *outliers) {
    if (o.campaign >= 0 &&
        o.campaign < static_cast<int>(data.campaigns.size())) {
      o.campaign_id = data.campaigns[o.campaign].id;
    }
    o.stand = SlotStand(o.slot);
    o.position = SlotPosition(o.slot);
  }
  std::stable_sort(outliers->begin(), outliers->end(),
                   [](const SuspectedOutlier& a, const SuspectedOutlier& b) {
                     return std::abs(a.standardized_residual) >
                            std::abs(b.standardized_residual);
                   });
}

std::string OutlierLine(const SuspectedOutlier& o) {
  char buf[256];
  std::snprintf(buf, sizeof(buf),
                "%s %s: measured %.1f µm, predicted %.1f µm, r/sd = %+.1f (%s)",
                o.campaign_id.c_str(),
                RollPositionName(o.stand, o.position).c_str(), o.measured_um,
                o.predicted_um, o.standardized_residual,
                o.training ? "training" : "validation");
  return buf;
}

}  // namespace rollwear
