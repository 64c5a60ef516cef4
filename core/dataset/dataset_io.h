// Reading and writing mill dataset folders (the CSV format of
// docs/data-format.md).
//
// ReadDataset validates every rule of the format's bad-input section and
// reports the first broken rule as "<file>:<line>:<column> <field>: <rule>"
// (line 1 is the header, column is 1-based field position). A rejected
// dataset yields no Dataset at all: import is all-or-nothing.
//
// Thread-safety: stateless functions; safe to call concurrently on distinct
// folders.
#ifndef ROLLWEAR_CORE_DATASET_DATASET_IO_H_
#define ROLLWEAR_CORE_DATASET_DATASET_IO_H_

#include <istream>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/dataset/dataset.h"
#include "core/dataset/timestamp.h"  // ParseTimestamp, FormatTimestamp

namespace rollwear {

// Where the rows of a Dataset were read from: the physical line of each row
// in its file, indexed like the Dataset's rows.
struct DatasetLines {
  std::vector<int> campaigns, mounts, passes, measurements, profile_points;
};

// How to read what a real export leaves out (docs/data-format.md, "What a
// real export lacks").
struct DatasetReadOptions {
  // Set: a timestamp without a UTC offset is the mill's local time at this
  // fixed offset (seconds east of UTC; the service's ROLLWEAR_UTC_OFFSET).
  // Unset: such a timestamp is an error, never guessed.
  std::optional<int> local_utc_offset_s;
};

// Reads DIR/{campaigns,mounts,coils,measurements}.csv and, when it exists,
// DIR/profiles.csv; fills `lines` when given.
StatusOr<Dataset> ReadDataset(const std::string& dir,
                              DatasetLines* lines = nullptr,
                              const DatasetReadOptions& options = {});

// The same from four streams. Error messages name them by the canonical file
// names (campaigns.csv, ...); a null stream is reported as a missing file.
struct DatasetStreams {
  std::istream* campaigns = nullptr;
  std::istream* mounts = nullptr;
  std::istream* coils = nullptr;
  std::istream* measurements = nullptr;
  std::istream* profiles = nullptr;  // optional
};
StatusOr<Dataset> ReadDatasetStreams(const DatasetStreams& in,
                                     DatasetLines* lines = nullptr,
                                     const DatasetReadOptions& options = {});

// Writes the four CSV files into `dir` (created if missing), and
// profiles.csv when the dataset has profile points.
Status WriteDataset(const Dataset& data, const std::string& dir);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_DATASET_DATASET_IO_H_
