// The one Levenberg-Marquardt set-up of rollwear: every least-squares fit
// (wear-coefficient calibration, diagnosis refits, the NIST StRD checks)
// builds its ceres::Solver::Options here, so that what the NIST tests
// certify is what calibration runs.
//
// Internal header: includes Ceres; include it only from .cc files that
// build Ceres problems.
//
// Thread-safety: pure function.
#ifndef ROLLWEAR_CORE_LM_SETUP_H_
#define ROLLWEAR_CORE_LM_SETUP_H_

#include <string>

#include <ceres/solver.h>

namespace rollwear {

struct LmOptions {
  int max_iterations = 500;
  double function_tolerance = 1e-14;
  double gradient_tolerance = 1e-14;
  double parameter_tolerance = 1e-12;
  // Trust-region radius at start (Ceres default is 1e4).
  double initial_trust_region_radius = 1e4;
  int num_threads = 1;

  bool IsValid(std::string* error) const;
};

// Levenberg-Marquardt, dense QR (the problems are small and dense), no
// logging to stdout.
ceres::Solver::Options MakeLmSolverOptions(const LmOptions& options);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_LM_SETUP_H_
