// MillStore's wear limits: the wear_limits table (schema version 5), read
// on Open and written through the writer's task queue (one transaction,
// durable before SetWearLimit returns), and the limit in force at a
// position: the API's, else the configuration's (StoreOptions).
//
// Thread-safety: as MillStoreImpl (api_limits_ is guarded by mu_).
#include <cmath>
#include <string>

#include "core/dataset/timestamp.h"
#include "storage/mill_store_impl.h"

namespace rollwear::storage::internal {
namespace {

std::string StandName(int stand) { return "F" + std::to_string(stand); }

Status CheckLimit(const WearLimitIn& in) {
  if (in.stand < kMinStand || in.stand > kMaxStand) {
    return Status::InvalidArgument("stand: unknown stand " +
                                   std::to_string(in.stand) + " (want F1..F7)");
  }
  if (in.position != Position::kTop && in.position != Position::kBottom) {
    return Status::InvalidArgument("position: want top or bottom");
  }
  if (!std::isfinite(in.limit_um) || !(in.limit_um > 0) ||
      in.limit_um > kMaxWearLimitUm) {
    return Status::InvalidArgument(
        "limit_um: must be a number in (0, " +
        std::to_string(static_cast<int>(kMaxWearLimitUm)) + "] µm, got " +
        std::to_string(in.limit_um));
  }
  return Status::Ok();
}

}  // namespace

Status MillStoreImpl::LoadWearLimits(Db* db) {
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st,
      db->Prepare("SELECT stand, position, limit_um, set_at, reason "
                  "FROM wear_limits"));
  while (true) {
    ROLLWEAR_ASSIGN_OR_RETURN(const bool row, st.Step());
    if (!row) break;
    WearLimit limit;
    limit.stand = ParseStand(st.ColumnText(0));
    const std::string where = st.ColumnText(0) + "/" + st.ColumnText(1);
    if (limit.stand == 0 || !ParsePosition(st.ColumnText(1), &limit.position) ||
        !ParseTimestamp(st.ColumnText(3), &limit.set_at)) {
      return Status::IoError("wear_limits: unreadable row for " + where);
    }
    limit.limit_um = st.ColumnDouble(2);
    limit.source = "api";
    limit.reason = st.ColumnIsNull(4) ? "" : st.ColumnText(4);
    api_limits_[RollPositionSlot(limit.stand, limit.position)] = limit;
  }
  return Status::Ok();
}

WearLimit MillStoreImpl::LimitLocked(int slot) const {
  if (api_limits_[slot]) return *api_limits_[slot];
  WearLimit limit;
  limit.stand = SlotStand(slot);
  limit.position = SlotPosition(slot);
  const double configured = options_.wear_limit_um[slot];
  if (configured > 0) {
    limit.limit_um = configured;
    limit.source = "config";
  }
  return limit;
}

StatusOr<WearLimit> MillStoreImpl::SetWearLimit(const WearLimitIn& in) {
  ROLLWEAR_RETURN_IF_ERROR(CheckLimit(in));
  WearLimit limit;
  limit.stand = in.stand;
  limit.position = in.position;
  limit.limit_um = in.limit_um;
  limit.source = "api";
  limit.set_at = NowSeconds();
  limit.reason = in.reason;
  ROLLWEAR_RETURN_IF_ERROR(RunTask(
      [&limit](Db* db) -> Status {
        ROLLWEAR_ASSIGN_OR_RETURN(
            Statement st,
            db->Prepare("INSERT OR REPLACE INTO wear_limits "
                        "(stand, position, limit_um, set_at, reason) "
                        "VALUES (?, ?, ?, ?, ?)"));
        st.BindText(1, StandName(limit.stand))
            .BindText(2, PositionName(limit.position))
            .BindDouble(3, *limit.limit_um)
            .BindText(4, FormatTimestamp(limit.set_at));
        if (limit.reason.empty()) {
          st.BindNull(5);
        } else {
          st.BindText(5, limit.reason);
        }
        return st.Run();
      },
      [this, &limit](Db*) {
        std::lock_guard<std::mutex> lock(mu_);
        api_limits_[RollPositionSlot(limit.stand, limit.position)] = limit;
      }));
  return limit;
}

std::vector<WearLimit> MillStoreImpl::WearLimits() const {
  std::lock_guard<std::mutex> lock(mu_);
  std::vector<WearLimit> out;
  for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
    out.push_back(LimitLocked(slot));
  }
  return out;
}

}  // namespace rollwear::storage::internal
