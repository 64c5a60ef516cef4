// `rollwear calibrate --terms FILE`: recalibration of a model with terms
// adopted from a diagnosis (service/cmd_calibrate_terms.cc).
//
// Thread-safety: called once from main().
#ifndef ROLLWEAR_SERVICE_CALIBRATE_TERMS_H_
#define ROLLWEAR_SERVICE_CALIBRATE_TERMS_H_

#include <cstdint>
#include <string>

#include "service/commands.h"

namespace rollwear::cli {

// Returns the exit code (0 ok, 1 failure). Reads args.data, args.terms,
// args.split_seed or args.split, args.json, args.predictions and
// args.strict. Suspect measurements are left out (service/
// data_quality_cli.h); `strict` refuses a dataset with data-quality
// warnings.
int RunCalibrateWithTerms(const CalibrateArgs& args);

}  // namespace rollwear::cli

#endif  // ROLLWEAR_SERVICE_CALIBRATE_TERMS_H_
