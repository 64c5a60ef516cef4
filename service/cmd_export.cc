// `rollwear export --db FILE --out DIR`
// Writes what a rollwear database holds as a dataset folder
// (docs/data-format.md): campaigns.csv, mounts.csv, coils.csv and
// measurements.csv with every extra column stored - the inverse of
// `rollwear import`, so `calibrate`, `diagnose`, `study` and `ann` run on
// what the daemon has collected. --out must be missing or an empty folder
// (nothing is overwritten). The database is read in one read transaction on
// a read-only connection: export works while a daemon runs on it and sees
// one committed state. A campaign still open is written ended at its last
// pass (the format has no open campaign). Suspect flags are not written
// (the format has no column for them): `rollwear import` of the folder
// flags the same measurements again by core's rules
// (core/dataset/data_quality.h); the count of flagged ones is printed.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/dataset/dataset_io.h"
#include "service/commands.h"
#include "storage/store_export.h"

namespace rollwear::cli {

int RunExport(const ExportArgs& args) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(args.out, ec) &&
      (!fs::is_directory(args.out, ec) || !fs::is_empty(args.out, ec))) {
    std::fprintf(stderr,
                 "rollwear export: --out %s: exists and is not an empty "
                 "folder (nothing written)\n",
                 args.out.c_str());
    return 1;
  }
  std::vector<std::string> suspect;
  StatusOr<Dataset> data = storage::ReadDatabaseDataset(args.db, &suspect);
  if (!data.ok()) {
    std::fprintf(stderr, "rollwear export: %s (nothing written)\n",
                 data.status().message().c_str());
    return 1;
  }
  fs::create_directories(args.out, ec);
  const Status written = WriteDataset(*data, args.out);
  if (ec || !written.ok()) {
    std::fprintf(stderr, "rollwear export: %s: %s\n", args.out.c_str(),
                 ec ? ec.message().c_str() : written.message().c_str());
    return 1;
  }
  int flagged = 0;
  for (const std::string& s : suspect) flagged += s.empty() ? 0 : 1;
  std::printf(
      "exported %s to %s: %zu campaigns, %zu mounts, %zu coils, %zu passes, "
      "%zu measurements (%d stored flagged as suspect; import flags them "
      "again)\n",
      args.db.c_str(), args.out.c_str(), data->campaigns.size(),
      data->mounts.size(), data->coil_ids.size(), data->passes.size(),
      data->measurements.size(), flagged);
  return 0;
}

}  // namespace rollwear::cli
