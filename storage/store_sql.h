// Internal to storage: the repositories - every SQL statement MillStore
// runs, one function per row operation, over the schema of schema.h. All
// values are bound parameters. Functions that write expect the caller to
// hold a transaction (the group-commit writer does).
//
// Thread-safety: each function uses only the Db it is given; callers
// serialise use of a Db.
#ifndef ROLLWEAR_STORAGE_STORE_SQL_H_
#define ROLLWEAR_STORAGE_STORE_SQL_H_

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "core/base/status.h"
#include "core/dataset/dataset.h"
#include "core/model/roll_wear_state.h"
#include "core/model/wear_model.h"
#include "storage/import_plan.h"
#include "storage/sqlite_db.h"
#include "storage/store_state.h"
#include "storage/store_types.h"
#include "storage/wear_predictor.h"

namespace rollwear::storage::internal {

// ---- row iteration (store_sql.cc)
// Resets a cached statement when the scope ends, so that no statement is
// left mid-iteration holding a read snapshot on its connection.
class ResetOnExit {
 public:
  explicit ResetOnExit(Statement* st) : st_(st) {}
  ~ResetOnExit() { st_->Reset(); }
  ResetOnExit(const ResetOnExit&) = delete;
  ResetOnExit& operator=(const ResetOnExit&) = delete;

 private:
  Statement* st_;
};

// Steps `st` to its end, calling `visit` on each row (the first Step error
// is returned; the statement is not reset: pair a cached one with
// ResetOnExit).
Status ForEachRow(Statement* st,
                  const std::function<void(const Statement&)>& visit);

// The columns of a stored pass that its readers share, in this order:
// stand, rolled_at, then the measures force_kn .. shift_mm (11 columns, `p`
// the passes table's alias). ReadPassMeasures reads them back.
inline constexpr const char* kPassMeasureColumns =
    "p.stand, p.rolled_at, p.force_kn, p.width_mm, p.length_m, "
    "p.entry_thickness_mm, p.exit_thickness_mm, p.temperature_c, "
    "p.speed_mps, p.lubrication, p.shift_mm";
// The kPassMeasureColumns of the row `st` is on, from column `first`.
void ReadPassMeasures(const Statement& st, int first, PassMeasures* measures,
                      UnixSeconds* rolled_at);

// ---- campaigns, mounts, coils, passes, measurements (store_sql.cc)
StatusOr<int64_t> InsertCampaign(Db* db, const std::string& campaign_id,
                                 UnixSeconds started_at,
                                 std::optional<UnixSeconds> ended_at,
                                 const std::string& extra_json);
// Row id of a stored campaign; NotFound when absent.
StatusOr<int64_t> CampaignRow(Db* db, const std::string& campaign_id);
Status SetCampaignEnded(Db* db, const std::string& campaign_id,
                        UnixSeconds ended_at);
// Ends every open campaign (there is at most one) at `ended_at`.
Status EndOpenCampaigns(Db* db, UnixSeconds ended_at);
Status InsertMount(Db* db, int64_t campaign_row, const MountedRollIn& m,
                   const std::string& extra_json);
// Inserts the coil row (not its passes); returns its row id. `wear_blob`:
// the coil's first answer (EncodeCoilWear); null stores NULL, to be filled
// by BackfillCoilWear.
StatusOr<int64_t> InsertCoil(Db* db, int64_t campaign_row,
                             const StoredCoil& coil,
                             const std::string* wear_blob = nullptr);
Status InsertPass(Db* db, int64_t coil_row, int64_t campaign_row,
                  const StoredPass& p, const std::string& extra_json);
// Inserts the coil and all its passes.
Status InsertCoilWithPasses(Db* db, const StoredCoil& coil,
                            const std::string* wear_blob = nullptr);
Status InsertMeasurement(Db* db, int64_t campaign_row, const MeasurementIn& m,
                         const std::string& extra_json);

StatusOr<std::optional<StoredCoil>> LookupCoil(Db* db,
                                               const std::string& coil_id);
// Calls `visit` with the coil_id of every stored coil (any order).
Status ForEachCoilId(Db* db,
                     const std::function<void(const std::string&)>& visit);
// coil_id of the coil using (campaign_id, seq), if any.
StatusOr<std::optional<std::string>> LookupSeq(Db* db,
                                               const std::string& campaign_id,
                                               int seq);

// Everything the catalog holds (store_state.h), from the database.
StatusOr<Catalog> LoadCatalog(Db* db);

struct StoredCounts {
  int64_t campaigns = 0;
  int64_t coils = 0;
  int64_t measurements = 0;
  int64_t measurements_since_last_calibration = 0;
  int64_t suspect_measurements = 0;
};
StatusOr<StoredCounts> LoadCounts(Db* db);

// ---- a coil's first answer (coils.wear, schema version 2)
// What a coil added to each roll position it passed, in answer order:
// EncodeCoilWear gives the stored bytes, DecodeCoilWear reads them back
// (false when they are not in a known format). Doubles round-trip exactly.
std::string EncodeCoilWear(const std::vector<CoilWearEntry>& entries);
bool DecodeCoilWear(std::string_view blob, std::vector<CoilWearEntry>* out);
// The stored answer of `coil_id`; empty when the coil is unknown or has
// none yet.
StatusOr<std::optional<std::string>> LookupCoilWear(Db* db,
                                                    const std::string& coil_id);

// The predicted state of each mounted roll of `campaign` under `model`,
// replaying its stored passes in the order they were stored (the order in
// which the live state added them, so the result is bit-identical).
// ReplayCampaignCoils also calls `visit` (may be empty) after each coil with
// what that coil added; an error from `visit` ends the replay with it. With
// `track_profiles` each roll's profile sums are kept too (WearPredictor::
// Mount): the live rolls' state. The predictor computes every state.
using RollStates =
    std::array<std::optional<RollWearState>, kNumRollPositionSlots>;
struct ReplayedCoil {
  int64_t row = 0;  // coils.id
  std::string coil_id;
  bool wear_missing = false;  // coils.wear is NULL
  std::vector<CoilWearEntry> entries;
};
using CoilVisitor = std::function<Status(const ReplayedCoil&)>;
StatusOr<RollStates> ReplayCampaignCoils(Db* db, const WearPredictor& predictor,
                                         const CampaignRec& campaign,
                                         const WearModel& model,
                                         const CoilVisitor& visit,
                                         bool track_profiles = false);
// The queries that run per request or per measurement, whose cost must not
// grow with the mill's history: each reaches passes, coils and
// measurements through an index, never a scan (checked on their query
// plans by StoreQueryPlanTest, from PerRequestQueries()).
//
// A stored coil by coil_id (a new coil whose id the filter may hold, a
// repeat, a forecast's planned id).
inline constexpr char kLookupCoilSql[] =
    "SELECT g.campaign_id, c.seq, c.grade, p.stand, p.rolled_at, "
    "p.force_kn, p.width_mm, p.length_m, p.entry_thickness_mm, "
    "p.exit_thickness_mm, p.temperature_c, p.speed_mps, p.lubrication, "
    "p.shift_mm, p.extra FROM coils c JOIN campaigns g ON g.id = c.campaign "
    "JOIN passes p ON p.coil = c.id WHERE c.coil_id = ? ORDER BY p.stand";
// The coil stored under (campaign, seq).
inline constexpr char kLookupSeqSql[] =
    "SELECT c.coil_id FROM coils c JOIN campaigns g ON "
    "g.id = c.campaign WHERE g.campaign_id = ? AND c.seq = ?";
// A stored coil's first answer (a repeat's).
inline constexpr char kCoilWearSql[] =
    "SELECT wear FROM coils WHERE coil_id = ?";
// A campaign's row id (a measurement's, a profile's).
inline constexpr char kCampaignRowSql[] =
    "SELECT id FROM campaigns WHERE campaign_id = ?";
// A stored profile by campaign, stand and position (a profile post).
inline constexpr char kLookupProfileSql[] =
    "SELECT p.roll_id, p.measured_at, p.x_mm, p.wear_um FROM "
    "profile_points p JOIN campaigns c ON c.id = p.campaign "
    "WHERE c.campaign_id = ? AND p.stand = ? AND p.position = ? "
    "ORDER BY p.point";
// The most recently started ended campaigns with a stored profile (the
// dashboard's profile charts); scans the campaigns, a few hundred a year.
inline constexpr char kCampaignsWithProfilesSql[] =
    "SELECT c.campaign_id FROM campaigns c "
    "WHERE c.ended_at IS NOT NULL AND EXISTS (SELECT 1 FROM "
    "profile_points p WHERE p.campaign = c.id) "
    "ORDER BY c.started_at DESC, c.campaign_id DESC LIMIT ?";
struct PerRequestQuery {
  std::string name;  // what runs it
  std::string sql;
  // Tables (by their alias in `sql`) it may scan: a table other than
  // passes, coils and measurements whose size does not grow with coils.
  std::vector<std::string> may_scan;
};
// Every query above, and the replay's.
std::vector<PerRequestQuery> PerRequestQueries();

// The replay's one query: a campaign's passes with their coils, by the
// campaign's id (bound as ?), in stored order. Reached through the
// campaigns, coils (campaign, seq) and passes (coil, stand) indexes
// (StoreQueryPlanTest): a replay costs the campaign's rows, whatever the
// history.
std::string ReplayCampaignQuery();
StatusOr<RollStates> ReplayCampaign(Db* db, const WearPredictor& predictor,
                                    const CampaignRec& campaign,
                                    const WearModel& model,
                                    bool track_profiles = false);
// Stores the answer of every coil that has none (a version-1 file, an
// import), replaying their campaigns under `model`; inside the caller's
// transaction. Returns how many coils it filled.
StatusOr<int> BackfillCoilWear(Db* db, const WearPredictor& predictor,
                               const Catalog& catalog, const WearModel& model);

// ---- datasets (store_dataset.cc)
// Writes the new rows of an import plan (inside the caller's transaction).
// `suspect` is parallel to data.measurements: each one's flag ("" when
// plausible; MeasurementIn::suspect).
Status WriteImport(Db* db, const Dataset& data,
                   const std::vector<StoredCoil>& coils, const ImportPlan& plan,
                   const std::vector<std::string>& suspect);
// Everything stored as a Dataset: rows in the order they were stored,
// labels interned in first-seen order, extra columns rebuilt. An open
// campaign gets ended_at = max(started_at, last rolled_at of its passes).
// `suspect` (may be null) receives each measurement's stored flag ("" when
// plausible), parallel to the Dataset's measurements.
StatusOr<Dataset> ReadStoredDataset(
    Db* db, std::vector<std::string>* suspect = nullptr);

// ---- grinder profiles (store_profiles.cc)
// The stored profile of (campaign, stand, position), points in order;
// nullopt when none is stored.
StatusOr<std::optional<ProfileIn>> LookupProfile(Db* db, const ProfileIn& key);
// Inserts every point of `in` (no profile stored under its key).
Status InsertProfile(Db* db, int64_t campaign_row, const ProfileIn& in);
// The profiles of `data` (profile_points grouped by campaign, stand and
// position in file order), each checked against `catalog` (the catalog
// after the import) as a posted one is, then added, skipped when stored
// alike, or AlreadyExists when stored otherwise; errors name
// "profiles.csv:LINE field" when `lines` has a line per point. Inside the
// caller's transaction; `counts` gets what was added and skipped.
Status WriteImportProfiles(Db* db, const Dataset& data,
                           const DatasetLines* lines, const Catalog& catalog,
                           ImportTableCounts* counts);
// Appends the stored points of the campaigns in `campaign_index` (row id ->
// Dataset::campaigns index; others are skipped) to data->profile_points.
Status ReadStoredProfiles(
    Db* db, const std::unordered_map<int64_t, int>& campaign_index,
    Dataset* data);

// ---- models and calibrations (store_sql_models.cc)
// version of a ModelVersion is ignored; returns the new version.
StatusOr<int64_t> InsertActiveModel(Db* db, const ModelVersion& m,
                                    int64_t calibration_id);
StatusOr<std::optional<ModelVersion>> LoadActiveModel(Db* db);
StatusOr<std::vector<ModelVersion>> LoadModels(Db* db);
StatusOr<std::optional<ModelVersion>> LoadModel(Db* db, int64_t version);

// ---- model activation, audit trail, diagnoses (store_sql_audit.cc)
// Appends `p` (id ignored) to model_history.
Status InsertPromotion(Db* db, const ModelPromotion& p);
StatusOr<std::vector<ModelPromotion>> LoadPromotions(Db* db, int limit);
// Makes `version` the active row with pinned = `pin`.
Status SetActiveModel(Db* db, int64_t version, bool pin);
Status UpsertDiagnosis(Db* db, const StoredDiagnosis& d);
// With `report`, report_json is read too.
StatusOr<std::vector<StoredDiagnosis>> LoadDiagnoses(Db* db, int64_t id,
                                                     int limit, bool report);

StatusOr<int64_t> InsertCalibration(Db* db, const CalibrationRecord& r);
// Marks a queued run as running and records the measurement watermark;
// false when the run was not queued.
StatusOr<bool> ClaimCalibration(Db* db, int64_t id, UnixSeconds started_at);
// Writes every result field of `r` (status, times, metrics, ...) of a run
// that is running; FailedPrecondition when run r.id is not (unknown, still
// queued or already finished).
Status UpdateCalibration(Db* db, const CalibrationRecord& r);
StatusOr<std::optional<CalibrationRecord>> LoadCalibration(Db* db, int64_t id);
StatusOr<std::vector<CalibrationRecord>> LoadCalibrations(Db* db, int limit);
// Runs left 'running' by a process that stopped become 'failed'.
Status FailInterruptedCalibrations(Db* db, UnixSeconds now);

}  // namespace rollwear::storage::internal

#endif  // ROLLWEAR_STORAGE_STORE_SQL_H_
