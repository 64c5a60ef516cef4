// MillStore::PlanCoils: a planned schedule checked as the writes would be,
// turned into the canonical passes the writer's PredictBatch reads, with
// the mounted state it starts from (the engine runs it through copies of
// the roll states: engine/mounted_rolls.h). Stores nothing.
//
// Thread-safety: as MillStoreImpl; the checks and the state are taken
// under one hold of mu_.
#include <string>
#include <unordered_map>
#include <utility>

#include "storage/mill_store_impl.h"
#include "storage/store_sql.h"
#include "storage/validation.h"

namespace rollwear::storage::internal {
namespace {

// "coils[i]." before a store message that names a field of the coil.
Status InCoil(size_t i, const Status& s) {
  return Status(s.code(), "coils[" + std::to_string(i) + "]." + s.message());
}

}  // namespace

StatusOr<PlannedSchedule> MillStoreImpl::PlanCoils(
    const std::vector<CoilIn>& coils) const {
  std::vector<StoredCoil> schedule;
  schedule.reserve(coils.size());
  for (size_t i = 0; i < coils.size(); ++i) {
    const Status fields = CheckCoilFields(coils[i]);
    if (!fields.ok()) return InCoil(i, fields);
    schedule.push_back(CanonicalCoil(coils[i]));
  }
  PlannedSchedule out;
  {
    std::lock_guard<std::mutex> lock(mu_);
    const std::string& open = committed_.open_campaign;
    // A planned coil is one not yet rolled: posting a stored coil again
    // adds nothing (200 unchanged), so forecasting it would not equal what
    // posting gives; a coil planned twice neither.
    std::unordered_map<std::string, size_t> first;
    for (size_t i = 0; i < coils.size(); ++i) {
      const std::string& id = coils[i].coil_id;
      if (auto [it, fresh] = first.emplace(id, i); !fresh) {
        return InCoil(i, Status::InvalidArgument(
                             "coil_id: " + id + " is planned twice (first as "
                             "coils[" + std::to_string(it->second) + "])"));
      }
      bool stored = spec_.pending_coils.count(id) > 0;
      if (!stored && committed_coil_ids_.MayContain(id)) {
        ROLLWEAR_ASSIGN_OR_RETURN(std::optional<StoredCoil> found,
                                  LookupCoil(lookup_db_.get(), id));
        stored = found.has_value();
      }
      if (stored) {
        return InCoil(i, Status::FailedPrecondition(
                             "coil_id: coil " + id +
                             " is already stored: a forecast plans coils not "
                             "yet rolled (give planned coils new ids)"));
      }
    }
    for (size_t i = 0; i < coils.size(); ++i) {
      if (coils[i].campaign_id != open) {
        return InCoil(i, Status::FailedPrecondition(
                             "campaign_id: coil is for campaign " +
                             coils[i].campaign_id + "; the running campaign " +
                             (open.empty() ? "is none" : "is " + open)));
      }
      bool unchanged = false;
      const Status admit =
          AdmitCoil(committed_, coils[i], schedule[i], std::nullopt, &unchanged,
                    /*check_seq=*/false);
      if (!admit.ok()) return InCoil(i, admit);
    }
    out.start = MountedLocked();
  }
  out.coils.reserve(schedule.size());
  for (const StoredCoil& coil : schedule) {
    PlannedCoil planned;
    planned.coil_id = coil.coil_id;
    planned.passes.reserve(coil.passes.size());
    for (const StoredPass& pass : coil.passes) {
      planned.passes.push_back({pass.stand, ToPassInput(coil.grade, pass)});
    }
    out.coils.push_back(std::move(planned));
  }
  return out;
}

}  // namespace rollwear::storage::internal
