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

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/data_quality_json.h"
#include "core/dataset/data_quality.h"
#include "core/dataset/dataset_io.h"
#include "core/dataset/dataset.h"
#include "core/model/given_split.h"

namespace rollwear::cli {

// Which dataset a tool keeps of what it read: the one it fits (suspect
// measurements out, removed in place) or, for import, every row read. One
// of the two: keeping both copied the whole dataset, a third of
// `calibrate`'s page faults on a paper-size mill.
enum class Keep { kFit, kAll };

struct CheckedDataset {
  Dataset all;  // every row read, suspects included (Keep::kAll; else empty)
  Dataset fit;  // without the suspect measurements (Keep::kFit; else empty)
  DataQuality quality;  // of every row read
  DatasetLines lines;   // where the rows read came from
};

// The dataset reader's settings from the environment: ROLLWEAR_UTC_OFFSET
// (+HH:MM, -HH:MM or Z), the fixed UTC offset of timestamps written without
// one (docs/data-format.md). Returns 0 and fills `out`, or 2 after printing
// "rollwear TOOL: ROLLWEAR_UTC_OFFSET ..." on stderr when it is malformed.
int DatasetReadOptionsFromEnvironment(const char* tool, DatasetReadOptions* out);

// Reads DIR with the settings above, unassessed. Returns 0, or the exit
// code after printing "rollwear TOOL: ..." on stderr (1 rejected, 2 a
// malformed setting).
int ReadDatasetForTool(const char* tool, const std::string& dir, Dataset* out);

// Reads DIR (with the settings above), assesses it and prints the summary.
// Returns 0 and fills `out`, or the exit code after printing "rollwear TOOL:
// ..." on stderr: 1 when the folder is rejected, or when `strict` and there
// is a warning; 2 when ROLLWEAR_UTC_OFFSET is malformed.
int ReadCheckedDataset(const char* tool, const std::string& dir, bool strict,
                       CheckedDataset* out, Keep keep = Keep::kFit);

// --split FILE (core/model/given_split.h): replaces out->fit with the
// readings of the file's split (a campaign with readings in both sets
// split in two) and sets *split; prints DescribeSplit. Nothing when `file`
// is empty. 0, or exit code 1 after the message on stderr.
int ApplySplitFile(const char* tool, const std::string& file,
                   CheckedDataset* out, std::optional<CampaignSplit>* split,
                   SplitDataset* applied = nullptr);

// The `data_quality` object (api/data_quality_json.h).
using api::DataQualityJson;

// The fit's suspected gross errors (core/fit/robust.h) on stdout: their
// count and the first `max_listed`, e.g.
//   suspected outliers: 3 readings more than 4 sd off (kept at Huber weight)
//     C0042 F6/top: measured 312.0 µm, predicted 180.2 µm, r/sd = +6.1 (training)
// "suspected outliers: none (...)" when there is none.
void PrintSuspectedOutliers(const std::vector<SuspectedOutlier>& outliers,
                            int max_listed = 5);

// True when the data has a warning that makes a calibration on it not
// "usable": a roll position without a pass.
bool SpoilsCalibration(const DataQuality& quality);

}  // namespace rollwear::cli

#endif  // ROLLWEAR_SERVICE_DATA_QUALITY_CLI_H_
