#include "core/fit/lm_setup.h"

namespace rollwear {

bool LmOptions::IsValid(std::string* error) const {
  auto fail = [error](const char* what) {
    if (error != nullptr) *error = what;
    return false;
  };
  if (max_iterations <= 0) return fail("max_iterations must be > 0");
  if (!(function_tolerance >= 0)) return fail("function_tolerance must be >= 0");
  if (!(gradient_tolerance >= 0)) return fail("gradient_tolerance must be >= 0");
  if (!(parameter_tolerance >= 0)) return fail("parameter_tolerance must be >= 0");
  if (!(initial_trust_region_radius > 0)) {
    return fail("initial_trust_region_radius must be > 0");
  }
  if (num_threads < 1) return fail("num_threads must be >= 1");
  return true;
}

ceres::Solver::Options MakeLmSolverOptions(const LmOptions& options) {
  ceres::Solver::Options out;
  out.minimizer_type = ceres::TRUST_REGION;
  out.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  out.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  out.max_num_iterations = options.max_iterations;
  out.function_tolerance = options.function_tolerance;
  out.gradient_tolerance = options.gradient_tolerance;
  out.parameter_tolerance = options.parameter_tolerance;
  out.initial_trust_region_radius = options.initial_trust_region_radius;
  out.num_threads = options.num_threads;
  out.minimizer_progress_to_stdout = false;
  out.logging_type = ceres::SILENT;
  return out;
}

}  // namespace rollwear
