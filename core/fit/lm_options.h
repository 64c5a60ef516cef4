// LmOptions: the tunable part of rollwear's one Levenberg-Marquardt set-up
// (see lm_setup.h, which turns it into Ceres solver options). Kept apart
// from lm_setup.h so that public headers need not include Ceres.
//
// Thread-safety: plain value.
#ifndef ROLLWEAR_CORE_FIT_LM_OPTIONS_H_
#define ROLLWEAR_CORE_FIT_LM_OPTIONS_H_

#include <string>

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

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_FIT_LM_OPTIONS_H_
