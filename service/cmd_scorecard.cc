// `rollwear scorecard [--seeds N] [--first-seed S] [--effects A,B+C,...]
//  [--campaigns N] [--threads T] [--json FILE]`
// For every case (a simulator effect, several joined by '+', "clean" for
// none; default: clean, gross_errors and every effect of
// `rollwear simulate --list-effects`) and every seed: simulate in memory,
// run the diagnosis with the default options and score the report against
// the simulator's truth (core/report/scorecard.h). Prints one line per
// case to stderr as it goes, then the summary table (Markdown) on stdout;
// --json writes cases and summary.
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/report/scorecard.h"
#include "core/sim/simulator.h"
#include "service/commands.h"

namespace rollwear::cli {
namespace {

using OrderedJson = nlohmann::ordered_json;

std::vector<std::string> Split(const std::string& text, char sep) {
  std::vector<std::string> out;
  size_t begin = 0;
  while (begin <= text.size()) {
    size_t end = text.find(sep, begin);
    if (end == std::string::npos) end = text.size();
    if (end > begin) out.push_back(text.substr(begin, end - begin));
    begin = end + 1;
  }
  return out;
}

std::vector<std::string> DefaultCases() {
  std::vector<std::string> out = {"clean", "gross_errors"};
  for (const auto& [name, description] : SimulatorEffects()) {
    if (name != "gross_errors") out.push_back(name);
  }
  return out;
}

// The simulator's truth as the scorecard sees it: gross errors and null
// variants change no wear, so they are not concealed effects.
ScoreTruth ToScoreTruth(const Simulation& sim) {
  ScoreTruth t;
  for (const SimulatedEffect& e : sim.truth.effects) {
    if (e.name == "gross_errors" || e.null_effect) continue;
    t.effects.push_back({e.name, e.covariate, e.scope, e.levels, e.expressible,
                         e.mismatch,
                         e.form == "per_coil" ? e.form : std::string()});
  }
  const Dataset& d = sim.data;
  for (size_t i = 0; i < d.measurements.size(); ++i) {
    const Measurement& m = d.measurements[i];
    t.noise_free_um[{d.campaigns[m.campaign].id, m.stand,
                     static_cast<int>(m.position)}] =
        sim.truth.noise_free_wear_um[i];
  }
  return t;
}

OrderedJson CaseJson(const CaseScore& c) {
  return {{"effect", c.effect},
          {"seed", c.seed},
          {"clean", c.clean},
          {"expressible", c.expressible},
          {"named_right", c.named_right},
          {"wrong_physics", c.wrong_physics},
          {"findings", c.findings},
          {"verdict", c.verdict},
          {"gap_val_um", c.gap_val_um},
          {"baseline_gap_val_um", c.baseline_gap_val_um},
          {"noise_floor_um", c.noise_floor_um},
          {"gap_ratio", c.gap_ratio},
          {"seconds", c.seconds}};
}

OrderedJson SummaryJson(const EffectScore& e) {
  return {{"effect", e.effect},
          {"cases", e.cases},
          {"clean", e.clean},
          {"named_right", e.named_right},
          {"with_wrong_physics", e.with_wrong_physics},
          {"quiet", e.quiet},
          {"mean_gap_ratio", e.mean_gap_ratio},
          {"max_gap_ratio", e.max_gap_ratio},
          {"mean_seconds", e.mean_seconds},
          {"verdicts", e.verdicts}};
}

}  // namespace

int RunScorecard(const ScorecardArgs& args) {
  const std::vector<std::string> cases =
      args.effects.empty() ? DefaultCases() : Split(args.effects, ',');
  // Check every case before the first (slow) diagnosis.
  std::vector<SimulatorOptions> options;
  for (const std::string& name : cases) {
    SimulatorOptions o;
    o.num_campaigns = args.campaigns;
    for (const std::string& e : Split(name, '+')) {
      if (e != "clean") o.effects.push_back(e);
    }
    std::string error;
    if (!o.IsValid(&error)) {
      std::fprintf(stderr, "rollwear scorecard: case '%s': %s\n", name.c_str(),
                   error.c_str());
      return 2;
    }
    options.push_back(o);
  }
  std::vector<CaseScore> scores;
  for (size_t i = 0; i < cases.size(); ++i) {
    for (int k = 0; k < args.seeds; ++k) {
      SimulatorOptions o = options[i];
      o.seed = args.first_seed + static_cast<uint64_t>(k);
      StatusOr<Simulation> sim = Simulate(o);
      if (!sim.ok()) {
        std::fprintf(stderr, "rollwear scorecard: %s\n",
                     sim.status().message().c_str());
        return 1;
      }
      DiagnosisOptions d;
      d.num_threads = args.threads;
      StatusOr<DiagnosisReport> r = Diagnose(sim->data, d);
      if (!r.ok()) {
        std::fprintf(stderr, "rollwear scorecard: %s seed %llu: %s\n",
                     cases[i].c_str(), static_cast<unsigned long long>(o.seed),
                     r.status().message().c_str());
        return 1;
      }
      scores.push_back(ScoreCase(cases[i], o.seed, *r, ToScoreTruth(*sim)));
      const CaseScore& c = scores.back();
      std::string found;
      for (const std::string& f : c.findings) found += " " + f + ";";
      std::fprintf(stderr,
                   "%-28s seed %-4llu %-30s right %d wrong %d gap/floor "
                   "%.3f %.1f s%s\n",
                   c.effect.c_str(), static_cast<unsigned long long>(c.seed),
                   c.verdict.c_str(), c.named_right ? 1 : 0, c.wrong_physics,
                   c.gap_ratio, c.seconds, found.c_str());
    }
  }
  const std::vector<EffectScore> summary = Summarise(scores);
  std::fputs(ScorecardTable(summary).c_str(), stdout);
  if (!args.json.empty()) {
    OrderedJson doc = {{"seeds", args.seeds},         {"first_seed", args.first_seed},
                {"campaigns", args.campaigns}, {"threads", args.threads},
                {"cases", OrderedJson::array()},      {"summary", OrderedJson::array()}};
    for (const CaseScore& c : scores) doc["cases"].push_back(CaseJson(c));
    for (const EffectScore& e : summary)
      doc["summary"].push_back(SummaryJson(e));
    std::ofstream file(args.json, std::ios::trunc);
    file << doc.dump(2) << "\n";
    if (!file) {
      std::fprintf(stderr, "rollwear scorecard: cannot write %s\n",
                   args.json.c_str());
      return 1;
    }
  }
  return 0;
}

}  // namespace rollwear::cli
