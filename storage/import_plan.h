// Internal to storage: checking a core Dataset for import and deciding,
// row by row, what it adds to what is stored.
//
// CheckDataset re-checks every rule of data-format.md on an in-memory
// Dataset (ReadDataset already enforces them for files; datasets built in
// code are not trusted): field ranges, indices, duplicate keys, coils whose
// rows disagree, measurements without their mount. Messages name the row:
// "passes[12].force_kn: must be > 0, got -1 (coil K1001 at F6)".
//
// PlanImport compares the dataset with the catalog (and stored coils): a
// row whose key is stored with equal content is skipped, with other content
// it is AlreadyExists naming the key and, for a folder, its file and line;
// everything else is new.
//
// Thread-safety: pure functions; the lookups are called on the caller's
// thread.
#ifndef ROLLWEAR_STORAGE_IMPORT_PLAN_H_
#define ROLLWEAR_STORAGE_IMPORT_PLAN_H_

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/dataset/dataset.h"
#include "core/dataset/dataset_io.h"
#include "storage/store_state.h"

namespace rollwear::storage::internal {

struct ImportPlan {
  std::vector<char> new_campaign;     // per Dataset::campaigns
  std::vector<char> new_mount;        // per Dataset::mounts
  std::vector<char> new_coil;         // per Dataset::coil_ids
  std::vector<char> new_measurement;  // per Dataset::measurements
  int64_t num_campaigns = 0, num_coils = 0, num_measurements = 0;
  // Filled by the writer (WriteImportProfiles): profiles are decided
  // against the stored rows inside the import's transaction.
  ImportTableCounts profiles;
};

Status CheckDataset(const Dataset& data);

// The dataset's coils in canonical form, indexed like Dataset::coil_ids.
std::vector<StoredCoil> DatasetCoils(const Dataset& data);

// The stored (or queued) coil with this id, if any.
using CoilLookup =
    std::function<StatusOr<std::optional<StoredCoil>>(const std::string&)>;
// The coil_id that uses (campaign_id, seq) in the database, if any.
using SeqLookup = std::function<StatusOr<std::optional<std::string>>(
    const std::string&, int)>;

// `coils` = DatasetCoils(data). A conflict names the row as
// "measurements.csv:5 <field>" when `lines` (where ReadDataset found each
// row; may be null) has one line per row, else as "measurements[3].<field>".
StatusOr<ImportPlan> PlanImport(const Dataset& data, const DatasetLines* lines,
                                const std::vector<StoredCoil>& coils,
                                const Catalog& catalog,
                                const CoilLookup& lookup_coil,
                                const SeqLookup& lookup_seq);

// Per table: the rows the plan adds and those it skips as stored alike.
ImportCounts CountImport(const ImportPlan& plan);

// Records the plan's new rows in `catalog` (speculative: also the coils as
// pending).
void ApplyImport(const Dataset& data, const std::vector<StoredCoil>& coils,
                 const ImportPlan& plan, bool speculative, Catalog* catalog);

}  // namespace rollwear::storage::internal

#endif  // ROLLWEAR_STORAGE_IMPORT_PLAN_H_
