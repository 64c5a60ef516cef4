// `rollwear import --db FILE DIR [--strict]`
// Loads a dataset folder (docs/data-format.md) into the database,
// all-or-nothing: the folder is read and validated completely first (the
// first broken rule is reported as file:line:column), its data quality is
// printed (service/data_quality_cli.h), then it is stored in one
// transaction; a rejected dataset changes nothing. A suspect measurement is
// stored flagged (the store judges the folder by the same rules,
// storage/mill_store.h) and left out of the daemon's fitting; --strict
// refuses a folder with any warning instead. It says per table what
// was new and what was already stored alike ("0 new, N unchanged" on a
// second import), names the file and line of a row that conflicts with
// what is stored, and is refused while a daemon holds the database.
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <utility>

#include "core/dataset/dataset_io.h"
#include "engine/wear_prediction.h"
#include "service/commands.h"
#include "service/data_quality_cli.h"
#include "storage/db_lock.h"
#include "storage/mill_store.h"

namespace rollwear::cli {

namespace {

// "campaigns 0 new, 6 unchanged; mounts ...".
std::string Summary(const storage::ImportCounts& c) {
  std::string out;
  const std::pair<const char*, const storage::ImportTableCounts*> tables[] = {
      {"campaigns", &c.campaigns},
      {"mounts", &c.mounts},
      {"coils", &c.coils},
      {"measurements", &c.measurements},
      {"profiles", &c.profiles}};
  for (const auto& [name, t] : tables) {
    if (!out.empty()) out += "; ";
    out += std::string(name) + " " + std::to_string(t->added) + " new, " +
           std::to_string(t->unchanged) + " unchanged";
  }
  return out;
}

}  // namespace

int RunImport(const ImportArgs& args) {
  const std::string& dir = args.dir;
  const auto start = std::chrono::steady_clock::now();
  CheckedDataset checked;
  if (int code = ReadCheckedDataset("import", dir, args.strict, &checked, Keep::kAll)) {
    std::fprintf(stderr, "rollwear import: %s: nothing imported\n",
                 dir.c_str());
    return code;
  }
  // A running daemon holds the database: refused (storage/db_lock.h).
  StatusOr<storage::DatabaseLock> lock =
      storage::DatabaseLock::Acquire(args.db, "rollwear import");
  if (!lock.ok()) {
    std::fprintf(stderr, "rollwear import: %s (nothing imported)\n",
                 lock.status().message().c_str());
    return 1;
  }
  StatusOr<std::unique_ptr<storage::MillStore>> store =
      engine::OpenStore(args.db);
  if (!store.ok()) {
    std::fprintf(stderr, "rollwear import: %s: %s\n", args.db.c_str(),
                 store.status().message().c_str());
    return 1;
  }
  storage::ImportCounts counts;
  const Status imported = (*store)->ImportDataset(checked.all, &checked.lines, &counts);
  if (!imported.ok()) {
    std::fprintf(stderr, "rollwear import: %s: %s (nothing imported)\n",
                 dir.c_str(), imported.message().c_str());
    return 1;
  }
  const storage::StoreCounters c = (*store)->Counters();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  std::printf(
      "imported %s into %s: %s (%.1f s); the database now holds %lld "
      "campaigns, %lld coils, %lld measurements\n",
      dir.c_str(), args.db.c_str(), Summary(counts).c_str(), seconds,
      static_cast<long long>(c.campaigns), static_cast<long long>(c.coils),
      static_cast<long long>(c.measurements));
  if (const size_t n = checked.all.profile_points.size(); n > 0) {
    std::printf("profiles.csv: %zu profile point(s) in %lld new and %lld "
                "unchanged profile(s)\n",
                n, static_cast<long long>(counts.profiles.added),
                static_cast<long long>(counts.profiles.unchanged));
  }
  if (const int n = checked.quality.NumSuspect(); n > 0) {
    std::printf(
        "%d suspect measurement(s) stored flagged (listed above): "
        "kept, left out of calibration and diagnosis\n",
        n);
  }
  return 0;
}

}  // namespace rollwear::cli
