#include "core/model/roll_factor_update.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace rollwear {

namespace {

// A reading with its fixed weight w_i = 1 / s_i^2 and r_i = y_i - o_i.
struct Weighted {
  double x, r, w;
};

// F(b) of the header.
double Objective(double b, double prior_info, const std::vector<Weighted>& ws) {
  const double m = std::exp(b);
  double f = 0.5 * b * b * prior_info;
  for (const Weighted& v : ws) {
    const double e = v.r - v.x * m;
    f += 0.5 * v.w * e * e;
  }
  return f;
}

constexpr double kGridHalfWidth = 6;
constexpr double kGridStep = 0.02;

}  // namespace

RollFactorPosterior RollFactorPosteriorOf(
    double prior_sd, ReadingNoise noise,
    const std::vector<RollReading>& readings) {
  RollFactorPosterior out;
  out.log_sd = std::max(prior_sd, 0.0);
  const double prior_info = 1 / (prior_sd * prior_sd);
  if (!(prior_sd > 0) || !std::isfinite(prior_info)) return out;
  std::vector<Weighted> ws;
  for (const RollReading& r : readings) {
    if (!(r.base_um > 0) || !std::isfinite(r.base_um) ||
        !std::isfinite(r.measured_um) || !std::isfinite(r.offset_um)) {
      continue;
    }
    const double s2 = noise.sd_um * noise.sd_um +
                      (noise.rel * r.base_um) * (noise.rel * r.base_um);
    if (!(s2 > 0) || !std::isfinite(s2)) continue;
    ws.push_back({r.base_um, r.measured_um - r.offset_um, 1 / s2});
  }
  out.readings = static_cast<int>(ws.size());
  if (ws.empty()) return out;
  // The grid's best point, then golden section between its neighbours.
  const int n = static_cast<int>(2 * kGridHalfWidth / kGridStep + 0.5);
  int best = 0;
  double best_f = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= n; ++k) {
    const double f = Objective(-kGridHalfWidth + k * kGridStep, prior_info, ws);
    if (f < best_f) best_f = f, best = k;
  }
  out.converged = best > 0 && best < n;
  double lo = -kGridHalfWidth + std::max(best - 1, 0) * kGridStep;
  double hi = -kGridHalfWidth + std::min(best + 1, n) * kGridStep;
  const double kInvPhi = (std::sqrt(5.0) - 1) / 2;
  double c = hi - kInvPhi * (hi - lo), d = lo + kInvPhi * (hi - lo);
  double fc = Objective(c, prior_info, ws), fd = Objective(d, prior_info, ws);
  while (hi - lo > 1e-10) {
    if (fc < fd) {
      hi = d, d = c, fd = fc;
      c = hi - kInvPhi * (hi - lo);
      fc = Objective(c, prior_info, ws);
    } else {
      lo = c, c = d, fc = fd;
      d = lo + kInvPhi * (hi - lo);
      fd = Objective(d, prior_info, ws);
    }
  }
  // Comparing values of F pins b only to about sqrt(machine epsilon);
  // Newton steps on F'(b) = 0 (exact F'' = sum w x m (2 x m - r) + 1 /
  // tau^2, m = e^b) take it to rounding, so that re-estimates agree to
  // ~1e-15. A step over 1e-6 (no longer a polish) is not taken.
  double b_hat = (lo + hi) / 2;
  for (int it = 0; it < 3; ++it) {
    const double m = std::exp(b_hat);
    double g = b_hat * prior_info, h2 = prior_info;
    for (const Weighted& v : ws) {
      g -= v.w * (v.r - v.x * m) * v.x * m;
      h2 += v.w * v.x * m * (2 * v.x * m - v.r);
    }
    if (!(h2 > 0) || std::abs(g / h2) > 1e-6) break;
    b_hat -= g / h2;
  }
  double h = prior_info;
  for (const Weighted& v : ws) {
    const double j = v.x * std::exp(b_hat);
    h += v.w * j * j;
  }
  out.log_factor = b_hat;
  out.log_sd = 1 / std::sqrt(h);
  return out;
}

const ModelTerm* RollEffectTermOf(const std::vector<ModelTerm>& terms) {
  for (const ModelTerm& t : terms) {
    if (t.form == TermForm::kRollEffect) return &t;
  }
  return nullptr;
}

ModelTerm* RollEffectTermOf(std::vector<ModelTerm>* terms) {
  for (ModelTerm& t : *terms) {
    if (t.form == TermForm::kRollEffect) return &t;
  }
  return nullptr;
}

double RollLogFactor(const ModelTerm& term, const std::string& roll_id) {
  const int l = RollLevelOf(term, roll_id);
  return l >= 0 && static_cast<size_t>(l) < term.params.size() ? term.params[l]
                                                               : 0;
}

void SetRollLevel(const std::string& roll_id,
                  const RollFactorPosterior& posterior, ModelTerm* term) {
  const size_t n = static_cast<size_t>(std::max(0, term->num_levels));
  // Per-level sd and readings for every level (a term stored without them
  // gets the prior's sd and no count for the levels it already had).
  term->level_sd.resize(n, term->scale);
  term->level_readings.resize(n, 0);
  const int found = RollLevelOf(*term, roll_id);
  size_t l = found < 0 ? n : static_cast<size_t>(found);
  if (l >= n) {
    l = n;
    term->levels.push_back(roll_id);
    term->params.push_back(0);
    term->level_sd.push_back(term->scale);
    term->level_readings.push_back(0);
    term->num_levels = static_cast<int>(n + 1);
  }
  term->params[l] = posterior.log_factor;
  term->level_sd[l] = posterior.log_sd;
  term->level_readings[l] = posterior.readings;
}

}  // namespace rollwear
