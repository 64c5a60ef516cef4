#include "storage/extra_json.h"

#include <nlohmann/json.hpp>

namespace rollwear::storage::internal {

using Json = nlohmann::ordered_json;

std::string ExtraFieldsJson(const ExtraFields& fields) {
  if (fields.empty()) return "";
  Json obj = Json::object();
  for (const auto& [name, v] : fields.numeric) obj[name] = v;
  for (const auto& [name, v] : fields.factor) obj[name] = v;
  return obj.dump();
}

StatusOr<ExtraFields> ParseExtraFields(std::string_view text) {
  ExtraFields out;
  if (text.empty()) return out;
  const Json obj = Json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (obj.is_discarded() || !obj.is_object()) {
    return Status::IoError("stored extra columns are not a JSON object");
  }
  for (const auto& [name, value] : obj.items()) {
    if (value.is_null()) continue;
    if (value.is_number()) {
      out.numeric.emplace_back(name, value.get<double>());
    } else if (value.is_string()) {
      out.factor.emplace_back(name, value.get<std::string>());
    } else {
      out.factor.emplace_back(name, value.dump());  // as ExtraBuilder reads it
    }
  }
  out.Sort();
  return out;
}

}  // namespace rollwear::storage::internal
