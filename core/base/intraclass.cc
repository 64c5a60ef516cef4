// See intraclass.h.
#include "core/base/intraclass.h"

#include <algorithm>
#include <cstddef>
#include <map>
#include <utility>

namespace rollwear {

Intraclass OneWayIntraclass(const std::vector<double>& values,
                            const std::vector<int>& cluster) {
  Intraclass out;
  std::map<int, std::pair<double, double>> sums;  // cluster: (sum, count)
  double n = 0, grand = 0;
  for (size_t i = 0; i < values.size() && i < cluster.size(); ++i) {
    auto& s = sums[cluster[i]];
    s.first += values[i];
    s.second += 1;
    grand += values[i];
    n += 1;
  }
  if (n < 2) return out;
  grand /= n;
  std::map<int, double> mean;
  double ss_between = 0, sum_n2 = 0;
  for (const auto& [c, s] : sums) {
    mean[c] = s.first / s.second;
    ss_between += s.second * (mean[c] - grand) * (mean[c] - grand);
    sum_n2 += s.second * s.second;
  }
  double ss_within = 0;
  for (size_t i = 0; i < values.size() && i < cluster.size(); ++i) {
    const double d = values[i] - mean[cluster[i]];
    ss_within += d * d;
  }
  const double k = static_cast<double>(sums.size());
  out.variance = (ss_within + ss_between) / std::max(1.0, n - 1);
  const double msw = ss_within / std::max(1.0, n - k);
  const double msb = ss_between / std::max(1.0, k - 1);
  out.n0 = (n - sum_n2 / n) / std::max(1.0, k - 1);
  // One cluster of differing values: n0 = 0 and the estimator gives 1
  // (clamped to 0.99), the values counted as one correlated cluster; all
  // values equal: 0 / 0, taken as 0.
  const double denominator = msb + (out.n0 - 1) * msw;
  out.rho =
      denominator != 0 ? std::clamp((msb - msw) / denominator, 0.0, 0.99) : 0.0;
  return out;
}

}  // namespace rollwear
