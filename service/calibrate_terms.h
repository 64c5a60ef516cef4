// `rollwear calibrate --terms FILE`: recalibration of a model with terms
// adopted from a diagnosis (service/cmd_calibrate_terms.cc).
//
// Thread-safety: called once from main().
#ifndef ROLLWEAR_SERVICE_CALIBRATE_TERMS_H_
#define ROLLWEAR_SERVICE_CALIBRATE_TERMS_H_

#include <cstdint>
#include <string>

namespace rollwear::cli {

// Returns the exit code (0 ok, 1 failure); `json_file` empty = no JSON.
// Suspect measurements are left out (service/data_quality_cli.h); `strict`
// refuses a dataset with data-quality warnings.
int RunCalibrateWithTerms(const std::string& data_dir,
                          const std::string& terms_file, uint64_t split_seed,
                          const std::string& json_file, bool strict);

}  // namespace rollwear::cli

#endif  // ROLLWEAR_SERVICE_CALIBRATE_TERMS_H_
