// The intraclass correlation of values grouped in clusters, by the one-way
// ANOVA estimator (Fisher 1925, Statistical Methods for Research Workers,
// sec. 38):
//   rho = (MSB - MSW) / (MSB + (n0 - 1) MSW),
//   n0 = (N - sum_c n_c^2 / N) / (C - 1)  (the mean cluster size, corrected
//   for unequal sizes),
// clamped to [0, 0.99]. A cluster of n values with intraclass correlation
// rho carries the information of n / (1 + (n - 1) rho) independent ones,
// the design effect (Kish 1965, Survey Sampling, Wiley, sec. 5.4).
// Used where the readings of one campaign share its noise (the diagnosis)
// and the points of one profile share the roll's scatter (profile_joint).
//
// Thread-safety: a pure function.
#ifndef ROLLWEAR_CORE_BASE_INTRACLASS_H_
#define ROLLWEAR_CORE_BASE_INTRACLASS_H_

#include <vector>

namespace rollwear {

struct Intraclass {
  // In [0, 0.99]: 0.99 for a single cluster of differing values, 0 where
  // the estimator is undefined (all values equal); NaN values give NaN.
  double rho = 0;
  double n0 = 1;        // the mean cluster size, corrected
  double variance = 0;  // total variance of the values (N - 1 divisor)
};

// `values[i]` belongs to cluster `cluster[i]` (any integers; same length).
Intraclass OneWayIntraclass(const std::vector<double>& values,
                            const std::vector<int>& cluster);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_BASE_INTRACLASS_H_
