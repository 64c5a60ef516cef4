// `rollwear simulate --out DIR [--seed N] [--effect NAME[:K]]... [--campaigns
//  N] [--coils-per-campaign X] [--missing F] [--gross-errors F] [--truth FILE]
//  [--list-effects]`
// Writes a synthetic mill dataset folder and, beside it (DIR.truth.json
// unless --truth says otherwise, never inside the dataset folder), the
// simulator's ground truth; prints a one-paragraph summary.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "core/dataset/dataset_io.h"
#include "core/sim/simulator.h"
#include "service/commands.h"
#include "service/sim_truth_json.h"

namespace rollwear::cli {
namespace {

// Splits the --effect values at commas; "none" selects nothing. Duplicates
// are dropped; SimulatorOptions::IsValid checks the names (a family may
// carry a variant suffix, NAME:K).
void ParseEffects(const std::vector<std::string>& values,
                  std::vector<std::string>* out) {
  std::set<std::string> seen;
  for (const std::string& value : values) {
    size_t begin = 0;
    while (begin <= value.size()) {
      size_t end = value.find(',', begin);
      if (end == std::string::npos) end = value.size();
      std::string name = value.substr(begin, end - begin);
      begin = end + 1;
      if (name.empty() || name == "none") continue;
      if (seen.insert(name).second) out->push_back(name);
    }
  }
}

// DIR without trailing separators, made absolute when it names no folder
// ("." or ".."), so that DIR.truth.json lands beside the folder.
std::filesystem::path DefaultTruthPath(const std::string& out_dir) {
  namespace fs = std::filesystem;
  fs::path dir = fs::path(out_dir).lexically_normal();
  if (!dir.has_filename()) dir = dir.parent_path();  // "data/" -> "data"
  if (dir.empty() || dir.filename() == "." || dir.filename() == "..") {
    dir = fs::absolute(dir).lexically_normal();
    if (!dir.has_filename()) dir = dir.parent_path();
  }
  return dir.parent_path() / (dir.filename().string() + ".truth.json");
}

// True when `file` would lie inside folder `dir`.
bool IsInside(const std::filesystem::path& file, const std::string& dir) {
  namespace fs = std::filesystem;
  auto parts = [](const fs::path& p) {
    std::vector<std::string> out;
    for (const fs::path& part : fs::weakly_canonical(fs::absolute(p))) {
      if (!part.empty()) out.push_back(part.string());  // trailing separator
    }
    return out;
  };
  const std::vector<std::string> f = parts(file), d = parts(dir);
  return f.size() > d.size() && std::equal(d.begin(), d.end(), f.begin());
}

void PrintSummary(const Simulation& sim, const std::string& out_dir,
                  const std::string& truth_path) {
  const Dataset& d = sim.data;
  std::vector<double> wear;
  wear.reserve(d.measurements.size());
  for (const Measurement& m : d.measurements) wear.push_back(m.wear_center_um);
  std::sort(wear.begin(), wear.end());
  const size_t above_300 = static_cast<size_t>(
      wear.end() - std::upper_bound(wear.begin(), wear.end(), 300.0));
  std::set<std::string> rolls;
  for (const Mount& m : d.mounts) rolls.insert(m.roll_id);
  std::string effects;
  for (const SimulatedEffect& e : sim.truth.effects) {
    effects += effects.empty() ? "" : ", ";
    effects += e.name;
  }
  std::printf(
      "Simulated %zu campaigns, %zu coils (%zu pass rows at F6/F7), %zu mounts "
      "of %zu physical rolls (%zu roll types), %zu grades, %zu grinder "
      "measurements (seed %llu).",
      d.campaigns.size(), d.coil_ids.size(), d.passes.size(), d.mounts.size(),
      rolls.size(), d.roll_types.size(), d.grades.size(), d.measurements.size(),
      static_cast<unsigned long long>(sim.truth.seed));
  if (!wear.empty()) {
    std::printf(
        " Measured centre wear %.1f..%.1f um (median %.1f, %.1f%% above 300); "
        "noise floor %.2f um (grinder sd %.0f um, roll scatter %.0f%%).",
        wear.front(), wear.back(), wear[wear.size() / 2],
        100.0 * above_300 / wear.size(), sim.truth.noise_floor_um,
        sim.truth.grinder_noise_sd_um, 100 * sim.truth.roll_scatter_sd);
  }
  if (!d.profile_points.empty()) {
    std::printf(
        " %zu profile points (profile noise floor %.2f um, point sd %.0f um).",
        d.profile_points.size(), sim.truth.profile_noise_floor_um,
        sim.truth.profile_shape.point_noise_sd_um);
  }
  std::printf(" Concealed effects: %s. Dataset in %s, truth in %s.\n",
              effects.empty() ? "none" : effects.c_str(), out_dir.c_str(),
              truth_path.c_str());
}

}  // namespace

int RunSimulate(const SimulateArgs& args) {
  if (args.list_effects) {
    for (const auto& [name, description] : SimulatorEffects()) {
      std::printf("%-26s %s\n", name.c_str(), description.c_str());
    }
    return 0;
  }
  if (args.out.empty()) {
    std::fprintf(stderr, "rollwear simulate: --out DIR is required\n");
    return 2;
  }
  const std::string& out_dir = args.out;
  SimulatorOptions options = args.options;
  std::string error;
  ParseEffects(args.effects, &options.effects);
  if (!options.IsValid(&error)) {
    std::fprintf(stderr, "rollwear simulate: %s\n", error.c_str());
    return 2;
  }

  const std::string truth_path =
      args.truth.empty() ? DefaultTruthPath(out_dir).string() : args.truth;
  if (IsInside(truth_path, out_dir)) {
    std::fprintf(stderr,
                 "rollwear simulate: the truth file %s must not be inside the "
                 "dataset folder %s\n",
                 truth_path.c_str(), out_dir.c_str());
    return 2;
  }

  StatusOr<Simulation> sim = Simulate(options);
  if (!sim.ok()) {
    std::fprintf(stderr, "rollwear simulate: %s\n",
                 sim.status().message().c_str());
    return 1;
  }
  Status st = WriteDataset(sim->data, out_dir);
  if (!st.ok()) {
    std::fprintf(stderr, "rollwear simulate: %s\n", st.message().c_str());
    return 1;
  }
  st = WriteTruthJson(sim->truth, truth_path);
  if (!st.ok()) {
    std::fprintf(stderr, "rollwear simulate: %s\n", st.message().c_str());
    return 1;
  }
  PrintSummary(*sim, out_dir, truth_path);
  return 0;
}

}  // namespace rollwear::cli
