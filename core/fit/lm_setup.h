// The one Levenberg-Marquardt set-up of rollwear: every least-squares fit
// (wear-coefficient calibration, diagnosis refits, the NIST StRD checks)
// builds its ceres::Solver::Options here, so that what the NIST tests
// certify is what calibration runs.
//
// Internal header: includes Ceres; include it only from .cc files that
// build Ceres problems.
//
// Thread-safety: pure function.
#ifndef ROLLWEAR_CORE_FIT_LM_SETUP_H_
#define ROLLWEAR_CORE_FIT_LM_SETUP_H_

#include <ceres/solver.h>

#include "core/fit/lm_options.h"

namespace rollwear {

// Levenberg-Marquardt with a dense normal-equations Cholesky solver (the
// problems are small and dense; on the calibration's ~1000 x 90 Jacobians
// it is several times faster than dense QR, and the NIST StRD tests show it
// loses no certified digit), no logging to stdout.
ceres::Solver::Options MakeLmSolverOptions(const LmOptions& options);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_FIT_LM_SETUP_H_
