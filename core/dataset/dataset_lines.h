// Reading a dataset folder and keeping where each row came from: the line
// of every mounts.csv and measurements.csv row, for messages that name a
// row that was read without error (the data-quality warnings of
// core/dataset/data_quality.h). Otherwise the same as dataset_io.h's
// ReadDataset / ReadDatasetStreams.
//
// Thread-safety: stateless functions, as dataset_io.h.
#ifndef ROLLWEAR_CORE_DATASET_DATASET_LINES_H_
#define ROLLWEAR_CORE_DATASET_DATASET_LINES_H_

#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/dataset/dataset.h"

namespace rollwear {

struct DatasetStreams;  // dataset_io.h

// The physical line (the header is line 1) of each row, parallel to
// Dataset::mounts and Dataset::measurements.
struct DatasetSourceLines {
  std::vector<int> mounts;
  std::vector<int> measurements;
};

// ReadDataset / ReadDatasetStreams that also fill `lines` (may be null);
// defined in dataset_io.cc, beside the reader.
StatusOr<Dataset> ReadDatasetWithLines(const std::string& dir,
                                       DatasetSourceLines* lines);
StatusOr<Dataset> ReadDatasetStreamsWithLines(const DatasetStreams& in,
                                              DatasetSourceLines* lines);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_DATASET_DATASET_LINES_H_
