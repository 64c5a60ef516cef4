// Datasets in and out of the database: writing an import plan's rows and
// reading everything back as a core Dataset, including the extra columns a
// dataset folder may carry (stored per row as a JSON object in `extra`).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>

#include <nlohmann/json.hpp>

#include "storage/store_sql.h"

namespace rollwear::storage::internal {
namespace {

using Json = nlohmann::ordered_json;

// Row `row` of the extra columns as a JSON object ("" when there are none):
// numeric columns as numbers (null for NaN = empty), factors as their text.
std::string ExtraRowJson(const ExtraColumns& e, size_t row) {
  if (e.numeric_names.empty() && e.factor_names.empty()) return "";
  Json obj = Json::object();
  for (size_t c = 0; c < e.numeric_names.size(); ++c) {
    const double v = e.numeric[c][row];
    obj[e.numeric_names[c]] = std::isfinite(v) ? Json(v) : Json(nullptr);
  }
  for (size_t c = 0; c < e.factor_names.size(); ++c) {
    obj[e.factor_names[c]] = e.factor_levels[c][e.factor[c][row]];
  }
  return obj.dump();
}

// Rebuilds ExtraColumns from the rows' JSON objects, the way the dataset
// reader classifies columns: numeric when every value is a number or
// empty, otherwise a factor whose levels are in first-seen order.
class ExtraBuilder {
 public:
  Status AddRow(const std::string& text) {
    const size_t row = rows_++;
    if (text.empty()) return Status::Ok();
    Json obj = Json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (obj.is_discarded() || !obj.is_object()) {
      return Status::IoError("stored extra columns are not a JSON object");
    }
    for (auto& [name, value] : obj.items()) {
      auto [it, fresh] = index_.emplace(name, cols_.size());
      if (fresh) cols_.push_back(Column{name, {}});
      Column& col = cols_[it->second];
      col.values.resize(row + 1);
      col.values[row] = std::move(value);
    }
    return Status::Ok();
  }

  ExtraColumns Finish() {
    ExtraColumns out;
    for (Column& col : cols_) {
      col.values.resize(rows_);
      bool numeric = true;
      for (const auto& v : col.values) {
        numeric = numeric && (!v.has_value() || v->is_null() || v->is_number());
      }
      if (numeric) {
        std::vector<double> values(rows_, std::nan(""));
        for (size_t r = 0; r < rows_; ++r) {
          const auto& v = col.values[r];
          if (v.has_value() && v->is_number()) values[r] = v->get<double>();
        }
        out.numeric_names.push_back(col.name);
        out.numeric.push_back(std::move(values));
        continue;
      }
      std::vector<std::string> levels;
      std::unordered_map<std::string, int> level_index;
      std::vector<int> codes(rows_);
      for (size_t r = 0; r < rows_; ++r) {
        const auto& v = col.values[r];
        std::string text;
        if (v.has_value() && v->is_string()) {
          text = v->get<std::string>();
        } else if (v.has_value() && !v->is_null()) {
          text = v->dump();
        }
        auto [it, fresh] =
            level_index.emplace(text, static_cast<int>(levels.size()));
        if (fresh) levels.push_back(text);
        codes[r] = it->second;
      }
      out.factor_names.push_back(col.name);
      out.factor.push_back(std::move(codes));
      out.factor_levels.push_back(std::move(levels));
    }
    return out;
  }

 private:
  struct Column {
    std::string name;
    std::vector<std::optional<Json>> values;  // per row; empty = absent
  };
  size_t rows_ = 0;
  std::vector<Column> cols_;
  std::unordered_map<std::string, size_t> index_;
};

template <typename F>
Status ForEachRow(Db* db, const std::string& sql, F&& f) {
  ROLLWEAR_ASSIGN_OR_RETURN(Statement st, db->Prepare(sql));
  while (true) {
    ROLLWEAR_ASSIGN_OR_RETURN(const bool row, st.Step());
    if (!row) return Status::Ok();
    ROLLWEAR_RETURN_IF_ERROR(f(st));
  }
}

}  // namespace

Status WriteImport(Db* db, const Dataset& d,
                   const std::vector<StoredCoil>& coils, const ImportPlan& plan,
                   const std::vector<std::string>& suspect) {
  std::vector<int64_t> campaign_rows(d.campaigns.size());
  for (size_t i = 0; i < d.campaigns.size(); ++i) {
    const Campaign& c = d.campaigns[i];
    ROLLWEAR_ASSIGN_OR_RETURN(
        campaign_rows[i],
        plan.new_campaign[i]
            ? InsertCampaign(db, c.id, c.started_at, c.ended_at,
                             ExtraRowJson(d.campaign_extra, i))
            : CampaignRow(db, c.id));
  }
  for (size_t i = 0; i < d.mounts.size(); ++i) {
    if (!plan.new_mount[i]) continue;
    const Mount& m = d.mounts[i];
    const MountedRollIn in{m.stand,       m.position,
                           m.roll_id,     d.roll_types[m.roll_type],
                           m.diameter_mm, m.hardness_hb,
                           /*extra=*/{}};  // stored from mount_extra below
    ROLLWEAR_RETURN_IF_ERROR(InsertMount(db, campaign_rows[m.campaign], in,
                                         ExtraRowJson(d.mount_extra, i)));
  }
  std::vector<int64_t> coil_rows(d.coil_ids.size(), -1);
  for (size_t i = 0; i < d.passes.size(); ++i) {
    const Pass& p = d.passes[i];
    if (!plan.new_coil[p.coil]) continue;
    if (coil_rows[p.coil] < 0) {
      ROLLWEAR_ASSIGN_OR_RETURN(
          coil_rows[p.coil],
          InsertCoil(db, campaign_rows[p.campaign], coils[p.coil]));
    }
    const StoredPass sp{static_cast<const PassMeasures&>(p), p.rolled_at,
                        /*extra=*/{}};  // stored from pass_extra below
    ROLLWEAR_RETURN_IF_ERROR(InsertPass(db, coil_rows[p.coil],
                                        campaign_rows[p.campaign], sp,
                                        ExtraRowJson(d.pass_extra, i)));
  }
  for (size_t i = 0; i < d.measurements.size(); ++i) {
    if (!plan.new_measurement[i]) continue;
    const Measurement& m = d.measurements[i];
    const MeasurementIn in{d.campaigns[m.campaign].id,
                           m.stand,
                           m.position,
                           m.roll_id,
                           m.measured_at,
                           m.wear_center_um,
                           {},
                           i < suspect.size() ? suspect[i] : ""};
    ROLLWEAR_RETURN_IF_ERROR(
        InsertMeasurement(db, campaign_rows[m.campaign], in,
                          ExtraRowJson(d.measurement_extra, i)));
  }
  return Status::Ok();
}

namespace {

// The four queries ReadStoredDataset runs, in its order (campaigns, mounts,
// passes, measurements): each scans its table in row order (every row is
// wanted).
std::array<std::string, 4> StoredDatasetQueries() {
  return {
      "SELECT id, campaign_id, started_at, ended_at, extra FROM campaigns "
      "ORDER BY id",
      "SELECT campaign, stand, position, roll_id, roll_type, diameter_mm, "
      "hardness_hb, extra FROM mounts ORDER BY id",
      std::string("SELECT p.campaign, c.coil_id, c.seq, c.grade, ") +
          kPassMeasureColumns +
          ", p.extra FROM passes p JOIN coils c ON c.id = p.coil ORDER BY "
          "p.id",
      "SELECT campaign, stand, position, roll_id, measured_at, "
      "wear_center_um, extra, suspect FROM measurements ORDER BY id"};
}

}  // namespace

StatusOr<Dataset> ReadStoredDataset(Db* db, std::vector<std::string>* suspect) {
  const std::array<std::string, 4> queries = StoredDatasetQueries();
  // One read transaction, so the four tables are read at one instant.
  ROLLWEAR_RETURN_IF_ERROR(db->Exec("BEGIN"));
  struct EndRead {
    Db* db;
    ~EndRead() { db->Exec("COMMIT"); }
  } end_read{db};

  Dataset d;
  std::unordered_map<int64_t, int> campaign_index;
  std::vector<int> open;
  ExtraBuilder campaign_extra, mount_extra, pass_extra, measurement_extra;
  ROLLWEAR_RETURN_IF_ERROR(ForEachRow(db, queries[0], [&](Statement& st) {
    Campaign c;
    c.id = st.ColumnText(1);
    c.started_at = st.ColumnInt(2);
    if (st.ColumnIsNull(3)) {
      open.push_back(static_cast<int>(d.campaigns.size()));
      c.ended_at = c.started_at;
    } else {
      c.ended_at = st.ColumnInt(3);
    }
    campaign_index[st.ColumnInt(0)] = static_cast<int>(d.campaigns.size());
    d.campaigns.push_back(std::move(c));
    return campaign_extra.AddRow(st.ColumnText(4));
  }));
  std::unordered_map<std::string, int> roll_types;
  ROLLWEAR_RETURN_IF_ERROR(ForEachRow(db, queries[1], [&](Statement& st) {
    Mount m;
    m.campaign = campaign_index.at(st.ColumnInt(0));
    m.stand = static_cast<int>(st.ColumnInt(1));
    m.position = static_cast<Position>(st.ColumnInt(2));
    m.roll_id = st.ColumnText(3);
    auto [it, fresh] = roll_types.emplace(
        st.ColumnText(4), static_cast<int>(d.roll_types.size()));
    if (fresh) d.roll_types.push_back(it->first);
    m.roll_type = it->second;
    m.diameter_mm = st.ColumnDouble(5);
    m.hardness_hb = st.ColumnDouble(6);
    d.mounts.push_back(std::move(m));
    return mount_extra.AddRow(st.ColumnText(7));
  }));
  std::unordered_map<std::string, int> coils, grades;
  ROLLWEAR_RETURN_IF_ERROR(ForEachRow(db, queries[2], [&](Statement& st) {
    Pass p;
    p.campaign = campaign_index.at(st.ColumnInt(0));
    auto [coil, new_coil] =
        coils.emplace(st.ColumnText(1), static_cast<int>(d.coil_ids.size()));
    if (new_coil) d.coil_ids.push_back(coil->first);
    p.coil = coil->second;
    p.seq = static_cast<int>(st.ColumnInt(2));
    auto [grade, new_grade] =
        grades.emplace(st.ColumnText(3), static_cast<int>(d.grades.size()));
    if (new_grade) d.grades.push_back(grade->first);
    p.grade = grade->second;
    ReadPassMeasures(st, 4, &p, &p.rolled_at);
    Campaign& c = d.campaigns[p.campaign];
    if (std::find(open.begin(), open.end(), p.campaign) != open.end()) {
      c.ended_at = std::max(c.ended_at, p.rolled_at);
    }
    d.passes.push_back(p);
    return pass_extra.AddRow(st.ColumnText(15));
  }));
  ROLLWEAR_RETURN_IF_ERROR(ForEachRow(db, queries[3], [&](Statement& st) {
    Measurement m;
    m.campaign = campaign_index.at(st.ColumnInt(0));
    m.stand = static_cast<int>(st.ColumnInt(1));
    m.position = static_cast<Position>(st.ColumnInt(2));
    m.roll_id = st.ColumnText(3);
    m.measured_at = st.ColumnInt(4);
    m.wear_center_um = st.ColumnDouble(5);
    d.measurements.push_back(std::move(m));
    if (suspect != nullptr) {
      suspect->push_back(st.ColumnText(7));
    }
    return measurement_extra.AddRow(st.ColumnText(6));
  }));
  ROLLWEAR_RETURN_IF_ERROR(ReadStoredProfiles(db, campaign_index, &d));
  d.campaign_extra = campaign_extra.Finish();
  d.mount_extra = mount_extra.Finish();
  d.pass_extra = pass_extra.Finish();
  d.measurement_extra = measurement_extra.Finish();
  return d;
}

}  // namespace rollwear::storage::internal
