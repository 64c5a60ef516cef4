// Internal to storage: the rules every write must pass (api.md and
// data-format.md), in two steps.
//
// 1. Check*Fields: the request on its own, by the rules of
//    core/dataset/input_rules.h. InvalidArgument whose message starts with
//    the JSON path of the field: "passes[1].force_kn: must be > 0, got -3".
// 2. Admit*: against the catalog (committed state plus queued writes).
//    A stored key with equal content sets *unchanged; with other content it
//    is AlreadyExists; an unknown campaign is NotFound; a state that does
//    not allow the write (ended campaign, no roll mounted, roll not mounted
//    there, seq taken, a measurement of a running campaign or before its
//    end) is FailedPrecondition, its message starting with the field. On
//    success Apply* records the write in a catalog.
//
// Thread-safety: pure functions of their arguments.
#ifndef ROLLWEAR_STORAGE_VALIDATION_H_
#define ROLLWEAR_STORAGE_VALIDATION_H_

#include <optional>
#include <string>

#include "core/base/status.h"
#include "storage/store_state.h"
#include "storage/store_types.h"

namespace rollwear::storage::internal {

Status CheckRollChangeFields(const RollChangeIn& in);
Status CheckEndFields(const std::string& campaign_id, UnixSeconds ended_at);
Status CheckCoilFields(const CoilIn& in);
Status CheckMeasurementFields(const MeasurementIn& in);

Status AdmitRollChange(const Catalog& c, const RollChangeIn& in,
                       bool* unchanged);
void ApplyRollChange(const RollChangeIn& in, Catalog* c);

Status AdmitEnd(const Catalog& c, const std::string& campaign_id,
                UnixSeconds ended_at, bool* unchanged);
void ApplyEnd(const std::string& campaign_id, UnixSeconds ended_at, Catalog* c);

// `stored` is the coil stored (or queued) under the same coil_id, if any.
// check_seq = false skips the check that seq is free (a forecast's coils
// may repeat stored seqs; their coil ids must be new, store_forecast.cc).
Status AdmitCoil(const Catalog& c, const CoilIn& in, const StoredCoil& coil,
                 const std::optional<StoredCoil>& stored, bool* unchanged,
                 bool check_seq = true);
// speculative: also remember the coil in pending_coils.
void ApplyCoil(const StoredCoil& coil, bool speculative, Catalog* c);

Status AdmitMeasurement(const Catalog& c, const MeasurementIn& in,
                        bool* unchanged);
void ApplyMeasurement(const MeasurementIn& in, Catalog* c);

// A grinder profile: the measurement's id rules, at least one point, each
// x_mm finite and within the barrel (|x_mm| <= kMaxProfileXMm) and each
// wear_um finite ("points[3].x_mm: ..."). AdmitProfile checks it against
// its campaign as AdmitMeasurement does (mount, roll, campaign ended,
// measured after the end); a repeat is decided on the stored rows
// (store_profiles.cc), not on the catalog.
Status CheckProfileFields(const ProfileIn& in);
Status AdmitProfile(const Catalog& c, const ProfileIn& in);

}  // namespace rollwear::storage::internal

#endif  // ROLLWEAR_STORAGE_VALIDATION_H_
