#include "core/model/wear_law.h"

namespace rollwear {

const char* WearLawName(WearLaw law) {
  switch (law) {
    case WearLaw::kWang: return "wang";
    case WearLaw::kNikitenko: return "nikitenko";
    case WearLaw::kCao: return "cao";
  }
  return "unknown";
}

bool ParseWearLaw(const std::string& name, WearLaw* out) {
  if (name == "wang") *out = WearLaw::kWang;
  else if (name == "nikitenko") *out = WearLaw::kNikitenko;
  else if (name == "cao") *out = WearLaw::kCao;
  else return false;
  return true;
}

}  // namespace rollwear
