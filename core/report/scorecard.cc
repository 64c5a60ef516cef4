#include "core/report/scorecard.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

namespace rollwear {
namespace {

// Equivalence class of a covariate name (SameCovariate); the name itself
// when it has none.
std::string CovariateClass(const std::string& name) {
  static const std::map<std::string, std::string> kClasses = {
      // Wear rate drifting with calendar time; a drift of the reading
      // (measured_at: the gauge, not the wear) is another physics.
      {"started_at", "calendar_time"},
      {"ended_at", "calendar_time"},
      {"rolled_at", "calendar_time"},
      {"campaign_length_before_m", "rolled_amount"},
      {"campaign_coils_before", "rolled_amount"},
  };
  auto it = kClasses.find(name);
  return it == kClasses.end() ? name : it->second;
}

std::string Describe(const Finding& f) {
  std::string out = f.covariate;
  const auto scope = FindingScope(f);
  if (!scope.empty()) {
    out += " {";
    bool first = true;
    for (const auto& [key, value] : scope) {
      out += (first ? "" : ",") + key + ":" + value;
      first = false;
    }
    out += "}";
  }
  if (!f.levels.empty()) {
    out += " [";
    for (size_t i = 0; i < f.levels.size(); ++i) {
      out += (i ? "," : "") + f.levels[i];
    }
    out += "]";
  }
  // The siblings the data cannot place (docs/diagnosis.md, "The scope's
  // siblings"): "campaign_coils_before {grade:DP600} ?API-X65,API-X70".
  for (size_t i = 0; i < f.scope_undetermined.size(); ++i) {
    out += (i ? "," : " ?") + f.scope_undetermined[i];
  }
  return out;
}

double NoiseFloor(const DiagnosisReport& r, const ScoreTruth& truth) {
  double sum = 0;
  int n = 0;
  for (const DiagnosisPoint& p : r.points) {
    if (!p.validation) continue;
    auto it = truth.noise_free_um.find(
        {p.campaign_id, p.stand, static_cast<int>(p.position)});
    if (it == truth.noise_free_um.end()) continue;
    sum += std::abs(p.measured_um - it->second);
    ++n;
  }
  return n > 0 ? sum / n : std::nan("");
}

bool StartsWith(const std::string& s, const std::string& prefix) {
  return s.rfind(prefix, 0) == 0;
}

// Whether residual check `dimension` (Unexplained::dimension) looks at the
// place one part of a truth's location names (MismatchParts).
bool DimensionLocates(const std::string& part, const std::string& dimension) {
  if (part.find("time of day") != std::string::npos)
    return dimension == "time_of_day";
  const bool time = part.find("time") != std::string::npos ||
                    part.find("calendar") != std::string::npos;
  if (time) {
    return StartsWith(dimension, "time_") || dimension == "lag1_along_time" ||
           dimension == "runs_along_time" || dimension == "spread_by_time" ||
           StartsWith(dimension, "spread_time_scale_") ||
           dimension == "position_by_time_half" ||
           SameCovariate("started_at", dimension) || dimension == "measured_at";
  }
  if (part.find("after a stop") != std::string::npos)  // restarts
    return dimension == "after_stop" || dimension == "effect_by_after_stop";
  if (part.find("campaign order") != std::string::npos) {  // within a campaign
    return SameCovariate("campaign_coils_before", dimension) ||
           dimension == "campaign_rolled_length_m" ||
           dimension == "hours_since_mount" ||
           dimension == "grade_by_campaign_order";
  }
  if (part.find("grade") != std::string::npos) {
    return dimension == "dominant_grade" || dimension == "grade" ||
           StartsWith(dimension, "position_by_grade") ||
           dimension == "effect_by_grade" || dimension == "stand_by_grade" ||
           dimension == "grade_by_campaign_order";
  }
  if (part.find("roll type") != std::string::npos) {
    return dimension == "roll_type" || dimension == "position_by_roll_type" ||
           dimension == "effect_by_roll_type" ||
           dimension == "effect_by_stand_roll_type" ||
           dimension == "stand_by_roll_type";
  }
  if (part.find("position") != std::string::npos ||
      part.find("stand") != std::string::npos) {
    return dimension == "roll_position" ||
           StartsWith(dimension, "position_by_") ||
           dimension == "spread_by_position" ||
           dimension == "effect_by_position" ||
           dimension == "effect_by_stand" || StartsWith(dimension, "stand_by_");
  }
  // A covariate's own name, or the guard's refusal across its levels
  // ("effect_by_lubrication": a term whose scale differs between them).
  return SameCovariate(part, dimension) || dimension == "effect_by_" + part;
}

}  // namespace

std::vector<std::string> MismatchParts(const std::string& mismatch) {
  std::vector<std::string> parts;
  std::string rest = mismatch;
  for (const std::string& sep : {std::string(" x "), std::string(", by ")}) {
    size_t at;
    while ((at = rest.find(sep)) != std::string::npos) {
      parts.push_back(rest.substr(0, at));
      rest = rest.substr(at + sep.size());
    }
  }
  parts.push_back(rest);
  for (std::string& p : parts) {
    while (!p.empty() && p.front() == ' ') p.erase(p.begin());
    while (!p.empty() && p.back() == ' ') p.pop_back();
  }
  return parts;
}

bool LocatesMismatch(const DiagnosisReport& report,
                     const std::string& mismatch) {
  if (mismatch.empty()) return false;
  const std::vector<std::string> parts = MismatchParts(mismatch);
  return std::any_of(report.unexplained.begin(), report.unexplained.end(),
                     [&](const Unexplained& u) {
                       return std::any_of(parts.begin(), parts.end(),
                                          [&](const std::string& part) {
                                            return DimensionLocates(
                                                part, u.dimension);
                                          });
                     });
}

std::map<std::string, std::string> FindingScope(const Finding& f) {
  std::map<std::string, std::string> scope = f.scope;
  scope.erase("gate_at");  // the side of a threshold is the physics
  return scope;
}

bool SameCovariate(const std::string& truth, const std::string& found) {
  return !truth.empty() && CovariateClass(truth) == CovariateClass(found);
}

// The finding's covariate is the effect's, or one of the carriers of the
// mechanism it names (Finding::carriers: "named right" means the
// mechanism and its scope).
bool OnCovariate(const Finding& f, const std::string& truth) {
  return SameCovariate(truth, f.covariate) ||
         std::any_of(
             f.carriers.begin(), f.carriers.end(),
             [&](const std::string& c) { return SameCovariate(truth, c); });
}

// Whether the finding's form says the physics a form-defined truth
// (ConcealedEffect::form: wear per coil) is, and only then: a growth named
// on the coil count is not wear per coil, nor the reverse.
bool SamePhysicsForm(const Finding& f, const ConcealedEffect& e) {
  return (e.form == "per_coil") == (f.form == "per_coil");
}

bool Describes(const Finding& f, const ConcealedEffect& e) {
  if (!e.expressible || !OnCovariate(f, e.covariate) ||
      !SamePhysicsForm(f, e)) {
    return false;
  }
  if (FindingScope(f) != e.scope) return false;
  if (e.levels.empty()) return true;
  // A per-level effect named without its levels does not say which level.
  if (f.levels.empty()) return false;
  const std::set<std::string> found(f.levels.begin(), f.levels.end());
  return std::all_of(e.levels.begin(), e.levels.end(),
                     [&](const std::string& l) { return found.count(l) > 0; });
}

// Not wrong physics: the finding describes the effect, or it is on the
// effect's covariate and scope and names no level (an offset stated between
// the levels because the data do not say which reads true says less, not
// something wrong).
bool NotWrong(const Finding& f, const ConcealedEffect& e) {
  if (Describes(f, e)) return true;
  return e.expressible && OnCovariate(f, e.covariate) &&
         SamePhysicsForm(f, e) && FindingScope(f) == e.scope &&
         f.levels.empty();
}

// Whether the cell findings on e's covariate and scope, each naming some of
// e's levels, name all of them together (two grades wearing F7 more, named
// as two cells): `f`, when given, must be one of them.
bool CoveredByCells(const DiagnosisReport& report, const ConcealedEffect& e,
                    const Finding* f) {
  if (!e.expressible || e.levels.size() < 2) return false;
  const std::set<std::string> want(e.levels.begin(), e.levels.end());
  std::set<std::string> got;
  bool member = f == nullptr;
  for (const Finding& g : report.findings) {
    if (!SameCovariate(e.covariate, g.covariate) ||
        FindingScope(g) != e.scope || g.levels.empty() ||
        !std::all_of(g.levels.begin(), g.levels.end(),
                     [&](const std::string& l) { return want.count(l) > 0; })) {
      continue;
    }
    got.insert(g.levels.begin(), g.levels.end());
    member = member || &g == f;
  }
  return member && got == want;
}

CaseScore ScoreCase(const std::string& effect, uint64_t seed,
                    const DiagnosisReport& report, const ScoreTruth& truth) {
  CaseScore s;
  s.effect = effect;
  s.seed = seed;
  s.clean = truth.effects.empty();
  s.verdict = report.verdict;
  s.seconds = report.seconds;
  s.num_findings = static_cast<int>(report.findings.size());
  for (const ConcealedEffect& e : truth.effects) {
    s.expressible = s.expressible && e.expressible;
  }
  for (const Finding& f : report.findings) {
    s.findings.push_back(Describe(f));
    const bool right =
        std::any_of(truth.effects.begin(), truth.effects.end(),
                    [&](const ConcealedEffect& e) {
                      return NotWrong(f, e) || CoveredByCells(report, e, &f);
                    });
    s.wrong_physics += right ? 0 : 1;
  }
  if (s.clean) {
    s.named_right = false;
  } else if (!s.expressible) {
    // The verdict, and the unexplained list naming where each inexpressible
    // effect lives.
    s.named_right = report.findings.empty() &&
                    report.verdict == "mismatch_located_unexplained" &&
                    std::all_of(truth.effects.begin(), truth.effects.end(),
                                [&](const ConcealedEffect& e) {
                                  return e.expressible ||
                                         LocatesMismatch(report, e.mismatch);
                                });
  } else {
    s.named_right = std::all_of(
        truth.effects.begin(), truth.effects.end(),
        [&](const ConcealedEffect& e) {
          return CoveredByCells(report, e, nullptr) ||
                 std::any_of(report.findings.begin(), report.findings.end(),
                             [&](const Finding& f) { return Describes(f, e); });
        });
  }
  s.gap_val_um = report.final_gap_val_um;
  s.baseline_gap_val_um = report.baseline_gap_val_um;
  s.noise_floor_um = NoiseFloor(report, truth);
  s.gap_ratio = s.gap_val_um / s.noise_floor_um;
  return s;
}

std::vector<EffectScore> Summarise(const std::vector<CaseScore>& cases) {
  std::vector<EffectScore> out;
  for (const CaseScore& c : cases) {
    auto it = std::find_if(out.begin(), out.end(), [&](const EffectScore& e) {
      return e.effect == c.effect;
    });
    if (it == out.end()) {
      out.push_back({});
      it = out.end() - 1;
      it->effect = c.effect;
      it->clean = c.clean;
    }
    EffectScore& e = *it;
    ++e.cases;
    e.named_right += c.named_right ? 1 : 0;
    e.with_wrong_physics += c.wrong_physics > 0 ? 1 : 0;
    e.quiet += c.num_findings == 0 ? 1 : 0;
    e.mean_gap_ratio += c.gap_ratio;
    e.max_gap_ratio = std::max(e.max_gap_ratio, c.gap_ratio);
    e.mean_seconds += c.seconds;
    ++e.verdicts[c.verdict];
  }
  for (EffectScore& e : out) {
    e.mean_gap_ratio /= e.cases;
    e.mean_seconds /= e.cases;
  }
  return out;
}

std::string ScorecardTable(const std::vector<EffectScore>& scores) {
  std::string out =
      "| effect | cases | named right | wrong physics | quiet | gap/floor "
      "mean | gap/floor max | s/diagnosis | verdicts |\n"
      "|---|---|---|---|---|---|---|---|---|\n";
  char buf[512];
  EffectScore total;
  int named_cases = 0, total_named = 0;
  for (const EffectScore& e : scores) {
    std::string verdicts;
    for (const auto& [v, n] : e.verdicts) {
      verdicts += (verdicts.empty() ? "" : ", ") + v + " " + std::to_string(n);
    }
    const std::string named =
        e.clean ? "-"
                : std::to_string(e.named_right) + "/" + std::to_string(e.cases);
    std::snprintf(
        buf, sizeof(buf),
        "| %s | %d | %s | %d/%d | %d/%d | %.3f | %.3f | %.1f | %s |\n",
        e.effect.c_str(), e.cases, named.c_str(), e.with_wrong_physics, e.cases,
        e.quiet, e.cases, e.mean_gap_ratio, e.max_gap_ratio, e.mean_seconds,
        verdicts.c_str());
    out += buf;
    total.cases += e.cases;
    total.with_wrong_physics += e.with_wrong_physics;
    total.quiet += e.quiet;
    total.mean_gap_ratio += e.mean_gap_ratio * e.cases;
    total.max_gap_ratio = std::max(total.max_gap_ratio, e.max_gap_ratio);
    total.mean_seconds += e.mean_seconds * e.cases;
    if (!e.clean) {
      named_cases += e.cases;
      total_named += e.named_right;
    }
  }
  if (total.cases > 0) {
    std::snprintf(buf, sizeof(buf),
                  "| **all** | %d | %d/%d | %d/%d | %d/%d | %.3f | %.3f | "
                  "%.1f | |\n",
                  total.cases, total_named, named_cases,
                  total.with_wrong_physics, total.cases, total.quiet,
                  total.cases, total.mean_gap_ratio / total.cases,
                  total.max_gap_ratio, total.mean_seconds / total.cases);
    out += buf;
  }
  return out;
}

}  // namespace rollwear
