#include "core/model/model_terms.h"

#include <algorithm>
#include <cmath>

#include "core/dataset/dataset.h"

namespace rollwear {

const char* TermFormName(TermForm f) {
  switch (f) {
    case TermForm::kLogLinear: return "log_linear";
    case TermForm::kPower: return "power";
    case TermForm::kSaturating: return "saturating";
    case TermForm::kDecaying: return "decaying";
    case TermForm::kFlag: return "flag";
    case TermForm::kBinned: return "binned";
    case TermForm::kPerLevel: return "per_level";
    case TermForm::kCell: return "cell";
    case TermForm::kOffsetDecay: return "offset_decay";
    case TermForm::kOffsetLinear: return "offset_linear";
    case TermForm::kOffsetBinned: return "offset_binned";
    case TermForm::kOffsetPerLevel: return "offset_per_level";
    case TermForm::kRollEffect: return "roll_effect";
  }
  return "unknown";
}

bool ParseTermForm(const std::string& name, TermForm* out) {
  for (TermForm f : {TermForm::kLogLinear, TermForm::kPower, TermForm::kSaturating,
                     TermForm::kDecaying, TermForm::kFlag, TermForm::kBinned,
                     TermForm::kPerLevel, TermForm::kCell, TermForm::kOffsetDecay,
                     TermForm::kOffsetLinear, TermForm::kOffsetPerLevel,
                     TermForm::kOffsetBinned, TermForm::kRollEffect}) {
    if (name == TermFormName(f)) {
      *out = f;
      return true;
    }
  }
  return false;
}

std::string TermScope::Label() const {
  std::string out;
  auto add = [&out](const std::string& part) {
    if (!out.empty()) out += ", ";
    out += part;
  };
  if (stand > 0) add(StandName(stand));
  if (position >= 0) add(std::string(PositionName(static_cast<Position>(position))) + " rolls");
  if (!roll_type.empty()) add("roll type " + roll_type);
  if (!grade.empty()) add("grade " + grade);
  return out;
}

std::vector<std::pair<std::string, std::string>> TermScope::Fields() const {
  std::vector<std::pair<std::string, std::string>> f;
  if (stand > 0) f.emplace_back("stand", StandName(stand));
  if (position >= 0) f.emplace_back("position", PositionName(static_cast<Position>(position)));
  if (!roll_type.empty()) f.emplace_back("roll_type", roll_type);
  if (!grade.empty()) f.emplace_back("grade", grade);
  return f;
}

int ModelTerm::NumParams() const {
  switch (form) {
    case TermForm::kSaturating:
    case TermForm::kDecaying:
    case TermForm::kOffsetDecay:
      return 2;
    case TermForm::kBinned:
    case TermForm::kOffsetBinned:
      return static_cast<int>(edges.size());
    case TermForm::kPerLevel:
    case TermForm::kOffsetPerLevel:
      return std::max(0, num_levels - 1);
    case TermForm::kRollEffect:
      return std::max(0, num_levels);
    default: return 1;
  }
}

int TermBin(const ModelTerm& t, double z) {
  return static_cast<int>(std::upper_bound(t.edges.begin(), t.edges.end(), z) -
                          t.edges.begin());
}

int RollLevelOf(const ModelTerm& t, const std::string& roll_id) {
  const auto it = std::find(t.levels.begin(), t.levels.end(), roll_id);
  return it == t.levels.end() ? -1 : static_cast<int>(it - t.levels.begin());
}

std::optional<RollWearFactor> RollWearFactorOf(const std::vector<ModelTerm>& terms,
                                               const std::string& roll_id) {
  constexpr double kZ95 = 1.959964;
  for (const ModelTerm& t : terms) {
    if (t.form != TermForm::kRollEffect) continue;
    RollWearFactor f;
    f.lo = std::exp(-kZ95 * t.scale);
    f.hi = std::exp(kZ95 * t.scale);
    f.log_sd = t.scale;
    const int level = RollLevelOf(t, roll_id);
    if (level >= 0 && static_cast<size_t>(level) < t.params.size()) {
      const size_t l = static_cast<size_t>(level);
      const double b = t.params[l];
      const double sd = l < t.level_sd.size() ? t.level_sd[l] : t.scale;
      f.readings = l < t.level_readings.size() ? t.level_readings[l] : 0;
      // Known when it had readings (or the model did not keep the counts,
      // or a level re-estimated later lacks them: a factor off 1 is the
      // fit's, not the prior's).
      f.known = f.readings > 0 || t.level_readings.empty() || b != 0;
      f.value = std::exp(b);
      f.log_sd = sd;
      f.lo = std::exp(b - kZ95 * sd);
      f.hi = std::exp(b + kZ95 * sd);
    }
    return f;
  }
  return std::nullopt;
}

double WidenForRollFactor(const std::vector<ModelTerm>& terms,
                          const std::string& roll_id, double wear, double half) {
  const std::optional<RollWearFactor> f = RollWearFactorOf(terms, roll_id);
  if (!f) return half;
  return std::hypot(half, 1.959963984540054 * wear * f->log_sd);
}

double TermMultiplier(const ModelTerm& t, double z, double* grad) {
  const int n = t.NumParams();
  if (grad != nullptr) std::fill(grad, grad + n, 0.0);
  if (std::isnan(z)) return 1.0;
  const double* p = t.params.data();
  switch (t.form) {
    case TermForm::kLogLinear: {
      const double u = (z - t.center) / t.scale;
      const double m = std::exp(p[0] * u);
      if (grad != nullptr) grad[0] = m * u;
      return m;
    }
    case TermForm::kPower: {
      const double lz = std::log(std::max(z, 1e-12) / t.center);
      const double m = std::exp(p[0] * lz);
      if (grad != nullptr) grad[0] = m * lz;
      return m;
    }
    case TermForm::kSaturating: {
      const double lam = std::exp(p[1]);
      const double e = std::exp(-z / lam);
      if (grad != nullptr) {
        grad[0] = 1 - e;
        grad[1] = -p[0] * e * (z / lam);  // d/dq of -b*e, q = log lam
      }
      return 1 + p[0] * (1 - e);
    }
    case TermForm::kDecaying: {
      const double lam = std::exp(p[1]);
      const double e = std::exp(-z / lam);
      if (grad != nullptr) {
        grad[0] = e;
        grad[1] = p[0] * e * (z / lam);
      }
      return 1 + p[0] * e;
    }
    case TermForm::kCell: {
      const double m = std::exp(p[0]);
      if (grad != nullptr) grad[0] = m;
      return m;
    }
    case TermForm::kFlag: {
      const double m = std::exp(p[0] * z);
      if (grad != nullptr) grad[0] = m * z;
      return m;
    }
    case TermForm::kBinned: {
      const int b = TermBin(t, z);
      if (b == 0) return 1.0;
      const double m = std::exp(p[b - 1]);
      if (grad != nullptr) grad[b - 1] = m;
      return m;
    }
    case TermForm::kPerLevel: {
      const int l = static_cast<int>(z);
      if (l <= 0 || l >= t.num_levels) return 1.0;
      const double m = std::exp(p[l - 1]);
      if (grad != nullptr) grad[l - 1] = m;
      return m;
    }
    case TermForm::kRollEffect: {
      const int l = static_cast<int>(z);
      if (l < 0 || l >= t.num_levels) return 1.0;
      const double m = std::exp(p[l]);
      if (grad != nullptr) grad[l] = m;
      return m;
    }
    case TermForm::kOffsetDecay:
    case TermForm::kOffsetLinear:
    case TermForm::kOffsetPerLevel:
    case TermForm::kOffsetBinned:
      return 1.0;
  }
  return 1.0;
}

double TermOffset(const ModelTerm& t, double z, double* grad) {
  const int n = t.NumParams();
  if (grad != nullptr) std::fill(grad, grad + n, 0.0);
  if (std::isnan(z)) return 0.0;
  const double* p = t.params.data();
  if (t.form == TermForm::kOffsetDecay) {
    const double tau = std::exp(p[1]);
    const double e = std::exp(-z / tau);
    if (grad != nullptr) {
      grad[0] = e;
      grad[1] = p[0] * e * (z / tau);
    }
    return p[0] * e;
  }
  if (t.form == TermForm::kOffsetPerLevel) {
    const int l = static_cast<int>(z);
    if (l < 0 || l >= t.num_levels || l == t.reference_level) return 0.0;
    const int j = l < t.reference_level ? l : l - 1;
    if (grad != nullptr) grad[j] = 1.0;
    return p[j];
  }
  if (t.form == TermForm::kOffsetBinned) {
    const int b = TermBin(t, z);
    if (b == 0) return 0.0;  // the first bin reads as is
    if (grad != nullptr) grad[b - 1] = 1.0;
    return p[b - 1];
  }
  if (t.form == TermForm::kOffsetLinear) {
    const double u = (z - t.center) / t.scale;
    if (grad != nullptr) grad[0] = u;
    return p[0] * u;
  }
  return 0.0;
}

}  // namespace rollwear
