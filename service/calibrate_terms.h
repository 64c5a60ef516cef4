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
int RunCalibrateWithTerms(const std::string& data_dir,
                          const std::string& terms_file, uint64_t split_seed,
                          const std::string& json_file);

}  // namespace rollwear::cli

#endif  // ROLLWEAR_SERVICE_CALIBRATE_TERMS_H_
