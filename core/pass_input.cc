#include "core/pass_input.h"

namespace rollwear {

PassInput PassInputOf(const Dataset& data, const Pass& p) {
  PassInput in;
  in.grade = p.grade >= 0 ? data.grades[p.grade] : std::string();
  in.force_kn = p.force_kn;
  in.width_mm = p.width_mm;
  in.length_m = p.length_m;
  in.entry_thickness_mm = p.entry_thickness_mm;
  in.exit_thickness_mm = p.exit_thickness_mm;
  in.rolled_at = p.rolled_at;
  in.temperature_c = p.temperature_c;
  in.speed_mps = p.speed_mps;
  in.lubrication = p.lubrication;
  in.shift_mm = p.shift_mm;
  return in;
}

}  // namespace rollwear
