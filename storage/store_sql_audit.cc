// Repositories of the model audit trail (model_history), of the manual
// activation and pin of models, and of stored diagnoses (see store_sql.h;
// schema version 6, storage/schema.cc).
#include <string>
#include <utility>
#include <vector>

#include "storage/store_sql.h"

namespace rollwear::storage::internal {

Status InsertPromotion(Db* db, const ModelPromotion& p) {
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st,
      db->Prepare("INSERT INTO model_history (version, previous_version, "
                  "source, reason, at, pinned) VALUES (?, ?, ?, ?, ?, ?)"));
  st.BindInt(1, p.version);
  if (p.previous_version > 0) {
    st.BindInt(2, p.previous_version);
  } else {
    st.BindNull(2);
  }
  st.BindText(3, p.source)
      .BindText(4, p.reason)
      .BindInt(5, p.at)
      .BindInt(6, p.pinned ? 1 : 0);
  return st.Run();
}

StatusOr<std::vector<ModelPromotion>> LoadPromotions(Db* db, int limit) {
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st,
      db->Prepare("SELECT id, version, previous_version, source, reason, at, "
                  "pinned FROM model_history ORDER BY id DESC LIMIT ?"));
  st.BindInt(1, limit > 0 ? limit : -1);
  std::vector<ModelPromotion> out;
  while (true) {
    ROLLWEAR_ASSIGN_OR_RETURN(const bool row, st.Step());
    if (!row) return out;
    ModelPromotion p;
    p.id = st.ColumnInt(0);
    p.version = st.ColumnInt(1);
    p.previous_version = st.ColumnIsNull(2) ? 0 : st.ColumnInt(2);
    p.source = st.ColumnText(3);
    p.reason = st.ColumnText(4);
    p.at = st.ColumnInt(5);
    p.pinned = st.ColumnInt(6) != 0;
    out.push_back(std::move(p));
  }
}

Status SetActiveModel(Db* db, int64_t version, bool pin) {
  ROLLWEAR_RETURN_IF_ERROR(
      db->Exec("UPDATE models SET active = 0, pinned = 0 WHERE active = 1"));
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st,
      db->Prepare(
          "UPDATE models SET active = 1, pinned = ? WHERE version = ?"));
  st.BindInt(1, pin ? 1 : 0).BindInt(2, version);
  ROLLWEAR_RETURN_IF_ERROR(st.Run());
  if (db->Changes() != 1) {
    return Status::NotFound("model version " + std::to_string(version) +
                            ": unknown model version");
  }
  return Status::Ok();
}

Status UpsertDiagnosis(Db* db, const StoredDiagnosis& d) {
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st,
      db->Prepare("INSERT OR REPLACE INTO diagnoses (id, status, adopt, "
                  "queued_at, started_at, finished_at, verdict, message, "
                  "calibration, report_json, report_html) "
                  "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)"));
  st.BindInt(1, d.id)
      .BindText(2, d.status)
      .BindInt(3, d.adopt ? 1 : 0)
      .BindInt(4, d.queued_at)
      .BindInt(5, d.started_at)
      .BindInt(6, d.finished_at)
      .BindText(8, d.message);
  if (d.verdict.empty()) {
    st.BindNull(7);
  } else {
    st.BindText(7, d.verdict);
  }
  if (d.calibration_id > 0) {
    st.BindInt(9, d.calibration_id);
  } else {
    st.BindNull(9);
  }
  if (d.report_json.empty()) {
    st.BindNull(10);
  } else {
    st.BindText(10, d.report_json);
  }
  if (d.report_html.empty()) {
    st.BindNull(11);
  } else {
    st.BindText(11, d.report_html);
  }
  return st.Run();
}

StatusOr<std::vector<StoredDiagnosis>> LoadDiagnoses(Db* db, int64_t id,
                                                     int limit, bool report) {
  const std::string sql =
      std::string(
          "SELECT id, status, adopt, queued_at, started_at, "
          "finished_at, verdict, message, calibration, ") +
      (report ? "report_json, report_html" : "NULL, NULL") +
      " FROM diagnoses " + (id > 0 ? "WHERE id = ? " : "WHERE ? = 0 ") +
      "ORDER BY id DESC LIMIT ?";
  ROLLWEAR_ASSIGN_OR_RETURN(Statement st, db->Prepare(sql));
  st.BindInt(1, id).BindInt(2, limit > 0 ? limit : -1);
  std::vector<StoredDiagnosis> out;
  while (true) {
    ROLLWEAR_ASSIGN_OR_RETURN(const bool row, st.Step());
    if (!row) return out;
    StoredDiagnosis d;
    d.id = st.ColumnInt(0);
    d.status = st.ColumnText(1);
    d.adopt = st.ColumnInt(2) != 0;
    d.queued_at = st.ColumnInt(3);
    d.started_at = st.ColumnIsNull(4) ? 0 : st.ColumnInt(4);
    d.finished_at = st.ColumnInt(5);
    d.verdict = st.ColumnIsNull(6) ? "" : st.ColumnText(6);
    d.message = st.ColumnText(7);
    d.calibration_id = st.ColumnIsNull(8) ? 0 : st.ColumnInt(8);
    d.report_json = st.ColumnIsNull(9) ? "" : st.ColumnText(9);
    d.report_html = st.ColumnIsNull(10) ? "" : st.ColumnText(10);
    out.push_back(std::move(d));
  }
}

}  // namespace rollwear::storage::internal
