#include "core/model/model_terms.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/dataset/dataset.h"

namespace rollwear {

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
  if (!gate.empty()) {
    add("passes with " + gate + (gate_above ? " >= " : " < ") + GateAtText());
  }
  return out;
}

std::string TermScope::GateAtText() const {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.4g", gate_at);
  return buf;
}

std::vector<std::pair<std::string, std::string>> TermScope::Fields() const {
  std::vector<std::pair<std::string, std::string>> f;
  if (stand > 0) f.emplace_back("stand", StandName(stand));
  if (position >= 0) f.emplace_back("position", PositionName(static_cast<Position>(position)));
  if (!roll_type.empty()) f.emplace_back("roll_type", roll_type);
  if (!grade.empty()) f.emplace_back("grade", grade);
  if (!gate.empty()) {
    f.emplace_back("gate", gate);
    f.emplace_back("gate_side", gate_above ? "above" : "below");
    f.emplace_back("gate_at", GateAtText());
  }
  return f;
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

}  // namespace rollwear
