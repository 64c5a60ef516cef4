// `rollwear import --db FILE DIR [--strict]`
// Loads a dataset folder (docs/data-format.md) into the database,
// all-or-nothing: the folder is read and validated completely first (the
// first broken rule is reported as file:line:column), its data quality is
// printed (service/data_quality_cli.h), then it is stored in one
// transaction; a rejected dataset changes nothing. A suspect measurement is
// stored flagged (the store judges the folder by the same rules,
// storage/mill_store.h) and left out of the daemon's fitting; --strict
// refuses a folder with any warning instead.
#include <chrono>
#include <cstdio>
#include <memory>

#include "core/dataset/dataset_io.h"
#include "service/commands.h"
#include "service/data_quality_cli.h"
#include "storage/mill_store.h"

namespace rollwear::cli {

int RunImport(const ImportArgs& args) {
  const std::string& dir = args.dir;
  const auto start = std::chrono::steady_clock::now();
  CheckedDataset checked;
  if (ReadCheckedDataset("import", dir, args.strict, &checked) != 0) {
    std::fprintf(stderr, "rollwear import: %s: nothing imported\n",
                 dir.c_str());
    return 1;
  }
  const Dataset* data = &checked.all;
  StatusOr<std::unique_ptr<storage::MillStore>> store =
      storage::MillStore::Open(args.db, storage::StoreOptions());
  if (!store.ok()) {
    std::fprintf(stderr, "rollwear import: %s: %s\n", args.db.c_str(),
                 store.status().message().c_str());
    return 1;
  }
  const Status imported = (*store)->ImportDataset(*data);
  if (!imported.ok()) {
    std::fprintf(stderr, "rollwear import: %s (nothing imported)\n",
                 imported.message().c_str());
    return 1;
  }
  const storage::StoreCounters c = (*store)->Counters();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  std::printf(
      "imported %s into %s: %zu campaigns, %zu coils, %zu measurements "
      "(%.1f s); the database now holds %lld campaigns, %lld coils, %lld "
      "measurements\n",
      dir.c_str(), args.db.c_str(), data->campaigns.size(),
      data->coil_ids.size(), data->measurements.size(), seconds,
      static_cast<long long>(c.campaigns), static_cast<long long>(c.coils),
      static_cast<long long>(c.measurements));
  if (const int n = checked.quality.NumSuspect(); n > 0) {
    std::printf(
        "%d suspect measurement(s) stored flagged (listed above): "
        "kept, left out of calibration and diagnosis\n",
        n);
  }
  return 0;
}

}  // namespace rollwear::cli
