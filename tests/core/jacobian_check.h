// A term model's Jacobian (core/fit/term_model_internal.h) against central
// finite differences of its prediction, for the family tests.
// Thread-safety: test helper, single-threaded.
#ifndef ROLLWEAR_TESTS_CORE_JACOBIAN_CHECK_H_
#define ROLLWEAR_TESTS_CORE_JACOBIAN_CHECK_H_

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "core/fit/term_model_internal.h"

namespace rollwear::jacobian_check {

struct Counts {
  int nonzero = 0;  // derivatives checked that were not 0
  int moved = 0;    // observations whose derivative in `watch` was not 0
};

// Every derivative of `model`'s prediction at `x`, for every `stride`-th
// of its `num_obs` observations, must be that of central differences
// (relative 1e-5); leaves the model's parameters at x.
inline Counts ExpectJacobianOfPrediction(fit_internal::TermModel* model,
                                         const std::vector<double>& x,
                                         int num_obs, int stride,
                                         int watch = -1) {
  Counts counts;
  model->SetParams(x.data());
  for (int o = 0; o < num_obs; o += stride) {
    std::vector<double> grad(x.size(), 0.0);
    model->Predict(x.data(), o, grad.data());
    for (size_t j = 0; j < x.size(); ++j) {
      const double h = 1e-6 * (1 + std::abs(x[j]));
      std::vector<double> up = x, down = x;
      up[j] += h;
      down[j] -= h;
      model->SetParams(up.data());
      const double f_up = model->Predict(up.data(), o, nullptr);
      model->SetParams(down.data());
      const double f_down = model->Predict(down.data(), o, nullptr);
      model->SetParams(x.data());
      const double numeric = (f_up - f_down) / (2 * h);
      EXPECT_NEAR(grad[j], numeric, 1e-5 * (1 + std::abs(numeric)))
          << "observation " << o << " parameter " << j;
      counts.nonzero += numeric != 0 ? 1 : 0;
    }
    if (watch >= 0) counts.moved += grad[watch] != 0 ? 1 : 0;
  }
  return counts;
}

}  // namespace rollwear::jacobian_check

#endif  // ROLLWEAR_TESTS_CORE_JACOBIAN_CHECK_H_
