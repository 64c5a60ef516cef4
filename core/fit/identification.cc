#include "core/fit/identification.h"

#include <cmath>
#include <cstdio>
#include <numbers>

namespace rollwear {
namespace {

// "kS[A], kS[B], kS[C] and 17 more".
std::string ListNames(const std::vector<std::string>& names) {
  constexpr size_t kListed = 5;
  std::string out;
  for (size_t i = 0; i < names.size() && i < kListed; ++i) {
    if (i > 0) out += ", ";
    out += names[i];
  }
  if (names.size() > kListed) {
    out += " and " + std::to_string(names.size() - kListed) + " more";
  }
  return out;
}

}  // namespace

Identification JudgeIdentification(const CalibrationResult& result,
                                   const FitMetrics& train,
                                   const FitMetrics& validation,
                                   double extra_parameters) {
  Identification id;
  const auto named = result.model.NamedCoefficients();
  for (size_t i = 0; i < named.size(); ++i) {
    const bool has_data = i >= result.identified.size() || result.identified[i];
    if (!has_data) continue;
    if (i < result.at_bound.size() && result.at_bound[i]) {
      id.at_bound.push_back(named[i].first);
    } else if (i < result.std_error.size() && result.std_error[i] > 1.0) {
      id.large_error.push_back(named[i].first);
    }
  }
  // Shrunk grades count by their effective number (calibration.h).
  const GradeShrinkage& shrunk = result.grade_shrinkage;
  const double p = result.summary.num_free_parameters + extra_parameters -
                   (shrunk.applied ? shrunk.levels - shrunk.effective_parameters
                                   : 0);
  const double n = train.n;
  // Standardised by the model's noise model where it has one, so that a
  // validation set of more worn rolls (larger absolute scatter) is not
  // taken for a worse fit.
  const bool standardised = std::isfinite(train.std_gap) &&
                            std::isfinite(validation.std_gap) &&
                            train.std_gap > 0;
  if (n > p && train.gap_um > 0 && validation.n > 0) {
    id.gap_ratio = standardised ? validation.std_gap / train.std_gap
                                : validation.gap_um / train.gap_um;
    id.expected_ratio = std::sqrt((n + p) / (n - p));
    // Relative sd of a mean absolute residual of m normal residuals.
    const double rel = std::sqrt(std::numbers::pi / 2 - 1);
    const double sd =
        id.expected_ratio * rel * std::sqrt(1.0 / validation.n + 1.0 / n);
    id.z = (id.gap_ratio - id.expected_ratio) / sd;
    id.validation_beyond_noise = id.z > kIdentificationZ;
  }
  id.identified = id.at_bound.empty() && id.large_error.empty() &&
                  !id.validation_beyond_noise;
  return id;
}

std::string Identification::Sentence() const {
  if (identified) return "identified";
  std::string out = "not identified:";
  const char* sep = " ";
  if (!at_bound.empty()) {
    out += sep + std::to_string(at_bound.size()) + " coefficient" +
           (at_bound.size() == 1 ? "" : "s") + " at a bound (" +
           ListNames(at_bound) + ")";
    sep = "; ";
  }
  if (!large_error.empty()) {
    out += sep + std::to_string(large_error.size()) +
           " with relative s.e. > 100 % (" + ListNames(large_error) + ")";
    sep = "; ";
  }
  if (validation_beyond_noise) {
    char buf[160];
    std::snprintf(buf, sizeof(buf),
                  "%svalidation gap %.2f x training, the noise model allows "
                  "%.2f (z = %.1f)",
                  sep, gap_ratio, expected_ratio, z);
    out += buf;
  }
  return out;
}

}  // namespace rollwear
