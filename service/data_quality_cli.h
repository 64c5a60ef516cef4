// The data-quality step every dataset tool (import, calibrate, study,
// diagnose, ann) runs after reading a folder: assess the dataset
// (core/dataset/data_quality.h), print the short summary on stdout, refuse
// under --strict when there is any warning (exit 1), and hand the tool the
// data it may fit (suspect measurements removed). DataQualityJson is the
// `data_quality` object of each tool's JSON.
//
// Thread-safety: called once from a command's Run*.
#ifndef ROLLWEAR_SERVICE_DATA_QUALITY_CLI_H_
#define ROLLWEAR_SERVICE_DATA_QUALITY_CLI_H_

#include <string>

#include <nlohmann/json.hpp>

#include "api/data_quality_json.h"
#include "core/dataset/data_quality.h"
#include "core/dataset/dataset.h"

namespace rollwear::cli {

struct CheckedDataset {
  Dataset all;        // every row read, suspects included
  Dataset fit;        // without the suspect measurements
  DataQuality quality;
  DatasetLines lines;  // where the rows of `all` were read from
};

// Reads DIR, assesses it and prints the summary. Returns 0 and fills `out`,
// or the exit code after printing "rollwear TOOL: ..." on stderr: 1 when the
// folder is rejected, or when `strict` and there is a warning.
int ReadCheckedDataset(const char* tool, const std::string& dir, bool strict,
                       CheckedDataset* out);

// The `data_quality` object (api/data_quality_json.h).
using api::DataQualityJson;

// True when the data has a warning that makes a calibration on it not
// "usable": a roll position without a pass.
bool SpoilsCalibration(const DataQuality& quality);

}  // namespace rollwear::cli

#endif  // ROLLWEAR_SERVICE_DATA_QUALITY_CLI_H_
