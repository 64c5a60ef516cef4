// libFuzzer target: the dataset CSV reader (core/dataset/dataset_io.h,
// ReadDatasetStreams, which runs the RFC 4180 parser, the column and number
// parsers, the timestamp parser and every cross-file rule).
//
// Input: the four files campaigns.csv, mounts.csv, coils.csv and
// measurements.csv in that order, separated by NUL bytes. Fewer than four
// parts leave the remaining files missing (reported as such by the
// reader). The reader must return a Status for anything; a crash, a leak or
// a sanitizer report is a bug.
//
// Thread-safety: libFuzzer calls the entry point from one thread.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>

#include "core/dataset/dataset_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  std::istringstream streams[4];
  std::istream* present[4] = {nullptr, nullptr, nullptr, nullptr};
  size_t begin = 0;
  for (int i = 0; i < 4 && begin <= input.size(); ++i) {
    size_t end = input.find('\0', begin);
    if (end == std::string_view::npos || i == 3) end = input.size();
    streams[i].str(std::string(input.substr(begin, end - begin)));
    present[i] = &streams[i];
    begin = end + 1;
  }
  rollwear::DatasetStreams in;
  in.campaigns = present[0];
  in.mounts = present[1];
  in.coils = present[2];
  in.measurements = present[3];
  rollwear::StatusOr<rollwear::Dataset> dataset =
      rollwear::ReadDatasetStreams(in);
  if (dataset.ok()) {
    // A dataset that was accepted must be internally consistent enough to
    // be summarised; touching its sizes keeps the result alive.
    volatile size_t n = dataset->coil_ids.size() + dataset->campaigns.size();
    (void)n;
  } else if (dataset.status().message().empty()) {
    __builtin_trap();  // every error names its place
  }
  return 0;
}
