// Repositories of the models and calibrations tables (see store_sql.h).
#include <cmath>
#include <utility>

#include <nlohmann/json.hpp>

#include "storage/model_codec.h"
#include "storage/store_sql.h"

namespace rollwear::storage::internal {
namespace {

using Json = nlohmann::ordered_json;

bool ParseStatus(const std::string& text, CalibrationStatus* out) {
  for (CalibrationStatus s :
       {CalibrationStatus::kQueued, CalibrationStatus::kRunning,
        CalibrationStatus::kDone, CalibrationStatus::kFailed}) {
    if (text == CalibrationStatusName(s)) {
      *out = s;
      return true;
    }
  }
  return false;
}

// Coefficients as [[name, value], ...] (keeps their order).
std::string CoefficientsJson(
    const std::vector<std::pair<std::string, double>>& coefs) {
  Json arr = Json::array();
  for (const auto& [name, value] : coefs) {
    arr.push_back(Json::array(
        {name, std::isfinite(value) ? Json(value) : Json(nullptr)}));
  }
  return arr.dump();
}

std::vector<std::pair<std::string, double>> ParseCoefficients(
    const std::string& text) {
  std::vector<std::pair<std::string, double>> out;
  if (text.empty()) return out;
  Json arr = Json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!arr.is_array()) return out;
  for (const Json& e : arr) {
    if (!e.is_array() || e.size() != 2 || !e[0].is_string()) continue;
    out.emplace_back(e[0].get<std::string>(),
                     e[1].is_number() ? e[1].get<double>() : std::nan(""));
  }
  return out;
}

constexpr const char* kCalibrationColumns =
    "id, status, triggered_by, law, k_option, queued_at, started_at, "
    "finished_at, coefficients_json, cost, gap_train_um, gap_val_um, "
    "active_gap_val_um, n_train, n_val, promoted, model_version, message";

CalibrationRecord ReadCalibration(const Statement& st) {
  CalibrationRecord r;
  r.id = st.ColumnInt(0);
  ParseStatus(st.ColumnText(1), &r.status);
  r.trigger = st.ColumnText(2);
  r.model = st.ColumnText(3);
  r.option = static_cast<int>(st.ColumnInt(4));
  r.queued_at = st.ColumnInt(5);
  r.started_at = st.ColumnInt(6);
  r.finished_at = st.ColumnInt(7);
  r.coefficients = ParseCoefficients(st.ColumnText(8));
  r.cost = st.ColumnIsNull(9) ? 0 : st.ColumnDouble(9);
  r.gap_train_um = st.ColumnIsNull(10) ? 0 : st.ColumnDouble(10);
  r.gap_val_um = st.ColumnIsNull(11) ? 0 : st.ColumnDouble(11);
  r.active_gap_val_um = st.ColumnIsNull(12) ? 0 : st.ColumnDouble(12);
  r.n_train = static_cast<int>(st.ColumnInt(13));
  r.n_val = static_cast<int>(st.ColumnInt(14));
  r.promoted = st.ColumnInt(15) != 0;
  r.model_version = st.ColumnInt(16);
  r.message = st.ColumnText(17);
  return r;
}

StatusOr<ModelVersion> ReadModel(const Statement& st) {
  ModelVersion m;
  m.version = st.ColumnInt(0);
  m.created_at = st.ColumnInt(1);
  m.model = st.ColumnText(2);
  m.option = static_cast<int>(st.ColumnInt(3));
  m.active = st.ColumnInt(4) != 0;
  m.gap_val_um = st.ColumnIsNull(5) ? 0 : st.ColumnDouble(5);
  StatusOr<WearModel> wm = DecodeWearModel(st.ColumnText(6));
  if (!wm.ok()) {
    return Status::IoError("stored model version " + std::to_string(m.version) +
                           " cannot be read: " + wm.status().message());
  }
  m.wear_model = std::move(wm).value();
  StatusOr<std::optional<ProfileFit>> profile =
      DecodeProfileShape(st.ColumnText(6));
  if (!profile.ok()) {
    return Status::IoError("stored model version " + std::to_string(m.version) +
                           " cannot be read: " + profile.status().message());
  }
  m.profile = std::move(profile).value();
  m.pinned = st.ColumnInt(7) != 0;
  m.calibration_id = st.ColumnIsNull(8) ? 0 : st.ColumnInt(8);
  m.trigger = st.ColumnIsNull(9) ? "" : st.ColumnText(9);
  m.source = m.calibration_id == 0 ? "" : ModelSource(m.trigger);
  m.gap_train_um = st.ColumnIsNull(10) ? 0 : st.ColumnDouble(10);
  m.n_train = static_cast<int>(st.ColumnIsNull(11) ? 0 : st.ColumnInt(11));
  m.n_val = static_cast<int>(st.ColumnIsNull(12) ? 0 : st.ColumnInt(12));
  return m;
}

// A model row with the run that made it (models m, calibrations c).
constexpr const char* kModelColumns =
    "m.version, m.created_at, m.law, m.k_option, m.active, m.gap_val_um, "
    "m.model_json, m.pinned, m.calibration, c.triggered_by, c.gap_train_um, "
    "c.n_train, c.n_val FROM models m "
    "LEFT JOIN calibrations c ON c.id = m.calibration";

}  // namespace

StatusOr<int64_t> InsertActiveModel(Db* db, const ModelVersion& m,
                                    int64_t calibration_id) {
  ROLLWEAR_RETURN_IF_ERROR(
      db->Exec("UPDATE models SET active = 0, pinned = 0 WHERE active = 1"));
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st,
      db->Prepare(
          "INSERT INTO models (created_at, law, k_option, gap_val_um, "
          "calibration, active, model_json) VALUES (?, ?, ?, ?, ?, 1, ?)"));
  st.BindInt(1, m.created_at)
      .BindText(2, m.model)
      .BindInt(3, m.option)
      .BindNullableDouble(4, m.gap_val_um)
      .BindText(6, EncodeModelJson(m.wear_model, m.profile));
  if (calibration_id > 0) {
    st.BindInt(5, calibration_id);
  } else {
    st.BindNull(5);
  }
  ROLLWEAR_RETURN_IF_ERROR(st.Run());
  return db->LastInsertRowId();
}

StatusOr<std::optional<ModelVersion>> LoadActiveModel(Db* db) {
  ROLLWEAR_ASSIGN_OR_RETURN(Statement st,
                            db->Prepare(std::string("SELECT ") + kModelColumns +
                                        " WHERE m.active = 1"));
  ROLLWEAR_ASSIGN_OR_RETURN(const bool row, st.Step());
  std::optional<ModelVersion> out;
  if (!row) return out;
  ROLLWEAR_ASSIGN_OR_RETURN(out, ReadModel(st));
  return out;
}

StatusOr<std::optional<ModelVersion>> LoadModel(Db* db, int64_t version) {
  ROLLWEAR_ASSIGN_OR_RETURN(Statement st,
                            db->Prepare(std::string("SELECT ") + kModelColumns +
                                        " WHERE m.version = ?"));
  st.BindInt(1, version);
  ROLLWEAR_ASSIGN_OR_RETURN(const bool row, st.Step());
  std::optional<ModelVersion> out;
  if (!row) return out;
  ROLLWEAR_ASSIGN_OR_RETURN(out, ReadModel(st));
  return out;
}

StatusOr<std::vector<ModelVersion>> LoadModels(Db* db) {
  ROLLWEAR_ASSIGN_OR_RETURN(Statement st,
                            db->Prepare(std::string("SELECT ") + kModelColumns +
                                        " ORDER BY m.version DESC"));
  std::vector<ModelVersion> out;
  while (true) {
    ROLLWEAR_ASSIGN_OR_RETURN(const bool row, st.Step());
    if (!row) return out;
    ROLLWEAR_ASSIGN_OR_RETURN(ModelVersion m, ReadModel(st));
    out.push_back(std::move(m));
  }
}

StatusOr<int64_t> InsertCalibration(Db* db, const CalibrationRecord& r) {
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st,
      db->Prepare(
          "INSERT INTO calibrations (status, triggered_by, law, k_option, "
          "queued_at) VALUES (?, ?, ?, ?, ?)"));
  st.BindText(1, CalibrationStatusName(r.status))
      .BindText(2, r.trigger)
      .BindText(3, r.model)
      .BindInt(4, r.option)
      .BindInt(5, r.queued_at);
  ROLLWEAR_RETURN_IF_ERROR(st.Run());
  return db->LastInsertRowId();
}

StatusOr<bool> ClaimCalibration(Db* db, int64_t id, UnixSeconds started_at) {
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st,
      db->Prepare("UPDATE calibrations SET status = 'running', started_at = ?, "
                  "measurement_watermark = "
                  "(SELECT IFNULL(MAX(id), 0) FROM measurements) "
                  "WHERE id = ? AND status = 'queued'"));
  st.BindInt(1, started_at).BindInt(2, id);
  ROLLWEAR_RETURN_IF_ERROR(st.Run());
  return db->Changes() == 1;
}

Status UpdateCalibration(Db* db, const CalibrationRecord& r) {
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st,
      db->Prepare("UPDATE calibrations SET status = ?, started_at = ?, "
                  "finished_at = ?, coefficients_json = ?, cost = ?, "
                  "gap_train_um = ?, gap_val_um = ?, active_gap_val_um = ?, "
                  "n_train = ?, n_val = ?, promoted = ?, model_version = ?, "
                  "message = ? WHERE id = ? AND status = 'running'"));
  st.BindText(1, CalibrationStatusName(r.status))
      .BindInt(2, r.started_at)
      .BindInt(3, r.finished_at)
      .BindText(4, CoefficientsJson(r.coefficients))
      .BindNullableDouble(5, r.cost)
      .BindNullableDouble(6, r.gap_train_um)
      .BindNullableDouble(7, r.gap_val_um)
      .BindNullableDouble(8, r.active_gap_val_um)
      .BindInt(9, r.n_train)
      .BindInt(10, r.n_val)
      .BindInt(11, r.promoted ? 1 : 0)
      .BindText(13, r.message)
      .BindInt(14, r.id);
  if (r.model_version > 0) {
    st.BindInt(12, r.model_version);
  } else {
    st.BindNull(12);
  }
  ROLLWEAR_RETURN_IF_ERROR(st.Run());
  if (db->Changes() != 1) {
    return Status::FailedPrecondition(
        "calibration " + std::to_string(r.id) +
        " is not running (unknown, or already finished): only a claimed run "
        "is finished");
  }
  return Status::Ok();
}

StatusOr<std::optional<CalibrationRecord>> LoadCalibration(Db* db, int64_t id) {
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st, db->Prepare(std::string("SELECT ") + kCalibrationColumns +
                                " FROM calibrations WHERE id = ?"));
  st.BindInt(1, id);
  ROLLWEAR_ASSIGN_OR_RETURN(const bool row, st.Step());
  std::optional<CalibrationRecord> out;
  if (row) out = ReadCalibration(st);
  return out;
}

StatusOr<std::vector<CalibrationRecord>> LoadCalibrations(Db* db, int limit) {
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st, db->Prepare(std::string("SELECT ") + kCalibrationColumns +
                                " FROM calibrations ORDER BY id DESC LIMIT ?"));
  st.BindInt(1, limit > 0 ? limit : -1);
  std::vector<CalibrationRecord> out;
  while (true) {
    ROLLWEAR_ASSIGN_OR_RETURN(const bool row, st.Step());
    if (!row) return out;
    out.push_back(ReadCalibration(st));
  }
}

Status FailInterruptedCalibrations(Db* db, UnixSeconds now) {
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st,
      db->Prepare(
          "UPDATE calibrations SET status = 'failed', finished_at = ?, "
          "message = 'interrupted: rollwear stopped while the run was in "
          "progress' WHERE status = 'running'"));
  st.BindInt(1, now);
  return st.Run();
}

}  // namespace rollwear::storage::internal
