// MillStore: finished diagnoses of the daemon, stored so that they outlive
// a restart (table diagnoses, schema version 6). Written through the
// writer thread like every other write; read on the read connection.
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "storage/mill_store_impl.h"
#include "storage/store_sql.h"

namespace rollwear::storage::internal {

Status MillStoreImpl::SaveDiagnosis(const StoredDiagnosis& d) {
  if (d.id <= 0) return Status::InvalidArgument("id: must be > 0");
  if (d.status != "done" && d.status != "failed") {
    return Status::InvalidArgument("status: must be done or failed, got '" +
                                   d.status + "'");
  }
  return RunTask([&d](Db* db) { return UpsertDiagnosis(db, d); }, nullptr);
}

StatusOr<std::optional<StoredDiagnosis>> MillStoreImpl::GetDiagnosis(
    int64_t id) const {
  std::optional<StoredDiagnosis> out;
  if (id <= 0) return out;
  std::lock_guard<std::mutex> lock(read_mu_);
  ROLLWEAR_ASSIGN_OR_RETURN(
      std::vector<StoredDiagnosis> rows,
      LoadDiagnoses(read_db_.get(), id, 1, /*report=*/true));
  if (!rows.empty()) out = std::move(rows.front());
  return out;
}

StatusOr<std::vector<StoredDiagnosis>> MillStoreImpl::ListDiagnoses(
    int limit) const {
  std::lock_guard<std::mutex> lock(read_mu_);
  return LoadDiagnoses(read_db_.get(), 0, limit, /*report=*/false);
}

StatusOr<int64_t> MillStoreImpl::LastDiagnosisId() const {
  std::lock_guard<std::mutex> lock(read_mu_);
  ROLLWEAR_ASSIGN_OR_RETURN(
      std::vector<StoredDiagnosis> rows,
      LoadDiagnoses(read_db_.get(), 0, 1, /*report=*/false));
  return rows.empty() ? 0 : rows.front().id;
}

}  // namespace rollwear::storage::internal
