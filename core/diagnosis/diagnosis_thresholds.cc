// DiagnosisThresholds::IsValid (diagnosis_thresholds.h).
#include "core/diagnosis/diagnosis_thresholds.h"

#include <string>

namespace rollwear {

bool DiagnosisThresholds::IsValid(std::string* error) const {
  std::string bad;
  const auto level = [&bad](const char* name, double v) {
    if (bad.empty() && !(v > 0 && v < 1))
      bad = std::string(name) + " must be in (0, 1)";
  };
  const auto share = [&bad](const char* name, double v) {
    if (bad.empty() && !(v >= 0 && v <= 1))
      bad = std::string(name) + " must be in [0, 1]";
  };
  const auto positive = [&bad](const char* name, double v) {
    if (bad.empty() && !(v > 0)) bad = std::string(name) + " must be > 0";
  };
  const auto count = [&bad](const char* name, int v) {
    if (bad.empty() && v < 1) bad = std::string(name) + " must be >= 1";
  };
  level("alternative_alpha", alternative_alpha);
  level("everywhere_alpha", everywhere_alpha);
  level("plain_alpha", plain_alpha);
  positive("shadow_delta", shadow_delta);
  positive("reference_chi2_critical", reference_chi2_critical);
  positive("rival_pair_margin", rival_pair_margin);
  positive("material_scale", material_scale);
  share("look_again_shrink", look_again_shrink);
  share("along_time_share", along_time_share);
  share("order_touched_share", order_touched_share);
  positive("material_slope", material_slope);
  share("material_autocorrelation", material_autocorrelation);
  positive("material_runs_share", material_runs_share);
  positive("material_spread_share", material_spread_share);
  positive("material_noise_share", material_noise_share);
  positive("barrel_min_effect", barrel_min_effect);
  positive("barrel_material", barrel_material);
  count("min_group_observations", min_group_observations);
  count("min_roll_readings", min_roll_readings);
  count("min_campaigns_per_block", min_campaigns_per_block);
  count("min_opening_readings", min_opening_readings);
  count("min_readings_per_roll", min_readings_per_roll);
  count("min_group_rolls", min_group_rolls);
  count("min_scope_observations", min_scope_observations);
  count("min_cell_observations", min_cell_observations);
  count("min_part_observations", min_part_observations);
  share("min_level_share", min_level_share);
  count("min_level_readings", min_level_readings);
  if (bad.empty() && !(min_flag_share >= 0 && min_flag_share < 0.5))
    bad = "min_flag_share must be in [0, 0.5)";
  if (bad.empty() && step_grid < 2) bad = "step_grid must be >= 2";
  if (bad.empty() && gate_grid < 2) bad = "gate_grid must be >= 2";
  count("max_refits", max_refits);
  positive("max_refit_score_p", max_refit_score_p);
  share("alternatives_cv_margin", alternatives_cv_margin);
  count("max_cross_validated", max_cross_validated);
  if (bad.empty() && (max_joint_candidates < 0 || max_joint_contexts < 0))
    bad = "max_joint_candidates and max_joint_contexts must be >= 0";
  if (bad.empty()) return true;
  if (error != nullptr) *error = bad;
  return false;
}

}  // namespace rollwear
