#include "service/sim_truth_json.h"

#include <cmath>
#include <fstream>
#include <map>

#include <nlohmann/json.hpp>

#include "api/json_number.h"

namespace rollwear {
namespace {

using Json = nlohmann::ordered_json;

Json Object(const std::map<std::string, double>& m) {
  Json out = Json::object();
  for (const auto& [key, value] : m) out[key] = JsonNumber<Json>(value);
  return out;
}

}  // namespace

std::string TruthJson(const SimulationTruth& truth) {
  Json doc;
  doc["seed"] = truth.seed;
  doc["law"] = truth.law;
  doc["option"] = 1;
  doc["k_position"] = Object(truth.k_position);
  doc["k_roll_type"] = Object(truth.k_roll_type);
  doc["k_grade"] = Object(truth.k_grade);
  Json effects = Json::array();
  for (const SimulatedEffect& e : truth.effects) {
    Json effect = {{"name", e.name},
                   {"covariate", e.covariate},
                   {"description", e.description},
                   {"parameters", Object(e.parameters)}};
    // Effect families (core/sim/sim_families.cc): form, strength, where it
    // applies (null = everywhere), affected levels, expressibility.
    if (!e.form.empty()) {
      effect["form"] = e.form;
      effect["strength"] = JsonNumber<Json>(e.strength);
      effect["scope"] = e.scope.empty() ? Json(nullptr) : Json(e.scope);
      effect["levels"] = e.levels;
      effect["expressible"] = e.expressible;
      if (!e.expressible) effect["mismatch"] = e.mismatch;
      effect["null_effect"] = e.null_effect;
    }
    effects.push_back(std::move(effect));
  }
  doc["effects"] = std::move(effects);
  doc["noise_floor_um"] = JsonNumber<Json>(truth.noise_floor_um);
  doc["grinder_noise_sd_um"] = JsonNumber<Json>(truth.grinder_noise_sd_um);
  doc["roll_scatter_sd"] = JsonNumber<Json>(truth.roll_scatter_sd);
  if (!truth.roll_wear_factor.empty()) {
    doc["roll_wear_factor"] = truth.roll_wear_factor;
  }
  // One row per Dataset::measurements row; plain numbers when the keys are
  // missing (older callers fill only the values).
  const bool keyed =
      truth.noise_free_keys.size() == truth.noise_free_wear_um.size();
  // gross_errors: which readings the grinder got grossly wrong, and by how
  // much (0 on a clean reading).
  const bool gross =
      truth.gross_error_um.size() == truth.noise_free_wear_um.size();
  int num_gross = 0;
  Json rows = Json::array();
  for (size_t i = 0; i < truth.noise_free_wear_um.size(); ++i) {
    if (!keyed) {
      rows.push_back(JsonNumber<Json>(truth.noise_free_wear_um[i]));
      continue;
    }
    const SimulatedMeasurementKey& k = truth.noise_free_keys[i];
    Json row = {{"campaign_id", k.campaign_id},
                {"stand", "F" + std::to_string(k.stand)},
                {"position", PositionName(k.position)},
                {"noise_free_wear_um", JsonNumber<Json>(truth.noise_free_wear_um[i])}};
    if (gross) {
      row["gross_error_um"] = JsonNumber<Json>(truth.gross_error_um[i]);
      num_gross += truth.gross_error_um[i] != 0;
    }
    rows.push_back(std::move(row));
  }
  doc["noise_free_wear_um"] = std::move(rows);
  if (gross) doc["gross_errors"] = num_gross;
  if (truth.has_profiles) {
    // The truth's own distribution across the strip (core/sim/
    // sim_profiles.cc): g = 1 + beta2 (u/b)^2 + A (exp(-d/lambda) -
    // exp(-b/lambda)) under the strip.
    const SimulatedProfileShape& s = truth.profile_shape;
    doc["profile"] = {
        {"form", "1 + body_beta2 (u/b)^2 + edge_amplitude (exp(-d/edge_decay_mm)"
                 " - exp(-b/edge_decay_mm)), d = b - |u|"},
        {"body_beta2", JsonNumber<Json>(s.body_beta2)},
        {"edge_amplitude", JsonNumber<Json>(s.edge_amplitude)},
        {"edge_decay_mm", JsonNumber<Json>(s.edge_decay_mm)},
        {"point_noise_sd_um", JsonNumber<Json>(s.point_noise_sd_um)},
        {"noise_floor_um", JsonNumber<Json>(truth.profile_noise_floor_um)}};
  }
  return doc.dump(2) + "\n";
}

Status WriteTruthJson(const SimulationTruth& truth, const std::string& path) {
  const std::string out = TruthJson(truth);
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) return Status::IoError("cannot open " + path + " for writing");
  file.write(out.data(), static_cast<std::streamsize>(out.size()));
  file.close();
  if (!file) return Status::IoError("cannot write " + path);
  return Status::Ok();
}

}  // namespace rollwear
