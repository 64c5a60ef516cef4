#include "storage/model_codec_scope.h"

#include <cmath>
#include <string>

#include "core/dataset/dataset.h"

namespace rollwear::storage {

Status BadModelField(const std::string& field, const std::string& rule) {
  return Status::InvalidArgument("model json: " + field + ": " + rule);
}

namespace {

using Json = nlohmann::ordered_json;

// A scope's optional gate: "gate" (a covariate's name), "gate_side"
// ("above" or "below") and "gate_at" (a finite number), all three or none.
Status DecodeGate(const Json& scope_json, const std::string& at,
                  TermScope* scope) {
  const auto gate = scope_json.find("gate");
  const auto side = scope_json.find("gate_side");
  const auto gate_at = scope_json.find("gate_at");
  if (gate == scope_json.end() && side == scope_json.end() &&
      gate_at == scope_json.end()) {
    return Status::Ok();
  }
  if (gate == scope_json.end() || !gate->is_string() ||
      gate->get<std::string>().empty()) {
    return BadModelField(at + "scope.gate", "must name a covariate");
  }
  if (side == scope_json.end() || !side->is_string() ||
      (*side != "above" && *side != "below")) {
    return BadModelField(at + "scope.gate_side", "must be above or below");
  }
  if (gate_at == scope_json.end() || !gate_at->is_number() ||
      !std::isfinite(gate_at->get<double>())) {
    return BadModelField(at + "scope.gate_at", "must be a finite number");
  }
  scope->gate = gate->get<std::string>();
  scope->gate_above = *side == "above";
  scope->gate_at = gate_at->get<double>();
  return Status::Ok();
}

}  // namespace

// A term's optional "scope": {"stand": "F7", "position": "top",
// "roll_type": "...", "grade": "...", and a gate}, every field optional.
Status DecodeScope(const Json& j, const std::string& at, TermScope* scope) {
  auto it = j.find("scope");
  if (it == j.end() || it->is_null()) return Status::Ok();
  if (!it->is_object()) return BadModelField(at + "scope", "must be an object");
  auto text = [&](const char* key, std::string* out) -> Status {
    auto f = it->find(key);
    if (f == it->end()) return Status::Ok();
    if (!f->is_string())
      return BadModelField(at + "scope." + key, "must be a string");
    *out = f->get<std::string>();
    return Status::Ok();
  };
  std::string stand, position;
  ROLLWEAR_RETURN_IF_ERROR(text("stand", &stand));
  ROLLWEAR_RETURN_IF_ERROR(text("position", &position));
  ROLLWEAR_RETURN_IF_ERROR(text("roll_type", &scope->roll_type));
  ROLLWEAR_RETURN_IF_ERROR(text("grade", &scope->grade));
  if (!stand.empty()) {
    scope->stand = ParseStand(stand);
    if (scope->stand == 0)
      return BadModelField(at + "scope.stand", "must be F1..F7");
  }
  if (!position.empty()) {
    Position p;
    if (!ParsePosition(position, &p)) {
      return BadModelField(at + "scope.position", "must be top or bottom");
    }
    scope->position = static_cast<int>(p);
  }
  return DecodeGate(*it, at, scope);
}

Json EncodeScope(const TermScope& s) {
  Json scope = Json::object();
  if (s.stand > 0) scope["stand"] = StandName(s.stand);
  if (s.position >= 0) {
    scope["position"] = PositionName(static_cast<Position>(s.position));
  }
  if (!s.roll_type.empty()) scope["roll_type"] = s.roll_type;
  if (!s.grade.empty()) scope["grade"] = s.grade;
  if (!s.gate.empty()) {
    scope["gate"] = s.gate;
    scope["gate_side"] = s.gate_above ? "above" : "below";
    scope["gate_at"] = s.gate_at;
  }
  return scope;
}

}  // namespace rollwear::storage
