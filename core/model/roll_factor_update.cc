#include "core/model/roll_factor_update.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>

namespace rollwear {

namespace {

// Gradient and curvature of F at b (header), the weights at b.
std::pair<double, double> SlopeAndCurvature(
    double b, double prior_info, ReadingNoise noise,
    const std::vector<const RollReading*>& used) {
  const double m = std::exp(b);
  double g = b * prior_info, h = prior_info;
  for (const RollReading* r : used) {
    const double j = r->base_um * m;  // d(x e^b)/db = x e^b
    const double w =
        1 / (noise.sd_um * noise.sd_um + (noise.rel * j) * (noise.rel * j));
    g -= w * j * (r->measured_um - r->offset_um - j);
    h += w * j * j;
  }
  return {g, h};
}

}  // namespace

RollFactorPosterior RollFactorPosteriorOf(
    double prior_sd, ReadingNoise noise,
    const std::vector<RollReading>& readings) {
  RollFactorPosterior out;
  out.log_sd = std::max(prior_sd, 0.0);
  if (!(prior_sd > 0) || !std::isfinite(prior_sd)) return out;
  if (!(noise.sd_um > 0 || noise.rel > 0)) return out;
  std::vector<const RollReading*> used;
  for (const RollReading& r : readings) {
    if (r.base_um > 0 && std::isfinite(r.base_um) &&
        std::isfinite(r.measured_um) && std::isfinite(r.offset_um)) {
      used.push_back(&r);
    }
  }
  out.readings = static_cast<int>(used.size());
  if (used.empty()) return out;
  const double prior_info = 1 / (prior_sd * prior_sd);
  double b = 0;
  for (int it = 0; it < 100; ++it) {
    const auto [g, h] = SlopeAndCurvature(b, prior_info, noise, used);
    const double step = std::clamp(-g / h, -1.0, 1.0);
    b += step;
    if (std::abs(step) < 1e-12) break;
  }
  out.log_factor = b;
  out.log_sd =
      1 / std::sqrt(SlopeAndCurvature(b, prior_info, noise, used).second);
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
  const size_t n = std::min(term.levels.size(), term.params.size());
  for (size_t l = 0; l < n; ++l) {
    if (term.levels[l] == roll_id) return term.params[l];
  }
  return 0;
}

void SetRollLevel(const std::string& roll_id,
                  const RollFactorPosterior& posterior, ModelTerm* term) {
  const size_t n = static_cast<size_t>(std::max(0, term->num_levels));
  // Per-level sd and readings for every level (a term stored without them
  // gets the prior's sd and no count for the levels it already had).
  term->level_sd.resize(n, term->scale);
  term->level_readings.resize(n, 0);
  size_t l = 0;
  while (l < n && term->levels[l] != roll_id) ++l;
  if (l == n) {
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
