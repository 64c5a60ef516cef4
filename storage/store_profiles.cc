// Grinder profiles across the barrel (schema v7, profile_points): the SQL
// of store_sql.h's profile functions, their import, and MillStore::
// AddProfile. A profile is written in the one transaction of its write, so
// an acknowledged profile is complete on disk or absent, never partial.
#include <map>
#include <tuple>
#include <utility>

#include "core/dataset/input_rules.h"
#include "storage/mill_store_impl.h"
#include "storage/store_sql.h"
#include "storage/validation.h"

namespace rollwear::storage::internal {
namespace {

// "profiles.csv:LINE field" when `lines` has a line per point, else
// "profile_points[i].field".
std::string LocatePoint(const DatasetLines* lines, const Dataset& d, size_t i,
                        const char* field) {
  if (lines != nullptr && lines->profile_points.size() == d.profile_points.size()) {
    return "profiles.csv:" + std::to_string(lines->profile_points[i]) + " " + field;
  }
  return "profile_points[" + std::to_string(i) + "]." + field;
}

// Prefixes a status's message with `where` (the message keeps its field).
Status At(const Status& s, const std::string& where) {
  return s.ok() ? s : Status(s.code(), where + ": " + s.message());
}

}  // namespace

StatusOr<std::optional<ProfileIn>> LookupProfile(Db* db, const ProfileIn& key) {
  ROLLWEAR_ASSIGN_OR_RETURN(Statement * st, db->Cached(kLookupProfileSql));
  const ResetOnExit reset(st);
  st->BindText(1, key.campaign_id)
      .BindInt(2, key.stand)
      .BindInt(3, static_cast<int>(key.position));
  std::optional<ProfileIn> out;
  ROLLWEAR_RETURN_IF_ERROR(ForEachRow(st, [&](const Statement& row) {
    if (!out) {
      out.emplace();
      out->campaign_id = key.campaign_id;
      out->stand = key.stand;
      out->position = key.position;
      out->roll_id = row.ColumnText(0);
      out->measured_at = row.ColumnInt(1);
    }
    out->points.push_back(
        ProfilePointIn{row.ColumnDouble(2), row.ColumnDouble(3)});
  }));
  return out;
}

Status InsertProfile(Db* db, int64_t campaign_row, const ProfileIn& in) {
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement * st,
      db->Cached("INSERT INTO profile_points (campaign, stand, position, "
                 "point, roll_id, measured_at, x_mm, wear_um) "
                 "VALUES (?, ?, ?, ?, ?, ?, ?, ?)"));
  for (size_t i = 0; i < in.points.size(); ++i) {
    st->BindInt(1, campaign_row)
        .BindInt(2, in.stand)
        .BindInt(3, static_cast<int>(in.position))
        .BindInt(4, static_cast<int64_t>(i))
        .BindText(5, in.roll_id)
        .BindInt(6, in.measured_at)
        .BindDouble(7, in.points[i].x_mm)
        .BindDouble(8, in.points[i].wear_um);
    const Status s = st->Run();
    st->Reset();
    ROLLWEAR_RETURN_IF_ERROR(s);
  }
  return Status::Ok();
}

Status WriteImportProfiles(Db* db, const Dataset& d, const DatasetLines* lines,
                           const Catalog& catalog, ImportTableCounts* counts) {
  *counts = ImportTableCounts();
  // Profiles in order of their first point; each with its points' rows.
  std::map<std::tuple<int, int, int>, size_t> index;
  std::vector<std::pair<ProfileIn, std::vector<size_t>>> profiles;
  for (size_t i = 0; i < d.profile_points.size(); ++i) {
    const ProfilePoint& p = d.profile_points[i];
    if (p.campaign < 0 || static_cast<size_t>(p.campaign) >= d.campaigns.size()) {
      return Status::InvalidArgument(LocatePoint(lines, d, i, "campaign_id") +
                                     ": unknown campaign");
    }
    const auto key = std::make_tuple(p.campaign, p.stand, static_cast<int>(p.position));
    auto [it, fresh] = index.emplace(key, profiles.size());
    if (fresh) {
      ProfileIn in;
      in.campaign_id = d.campaigns[p.campaign].id;
      in.stand = p.stand;
      in.position = p.position;
      in.roll_id = p.roll_id;
      in.measured_at = p.measured_at;
      profiles.emplace_back(std::move(in), std::vector<size_t>());
    }
    auto& [in, rows] = profiles[it->second];
    if (p.roll_id != in.roll_id || p.measured_at != in.measured_at) {
      return Status::InvalidArgument(
          LocatePoint(lines, d, i, p.roll_id != in.roll_id ? "roll_id" : "measured_at") +
          ": differs from the first point of the same profile (" +
          LocatePoint(lines, d, rows.front(), "") + ")");
    }
    in.points.push_back(ProfilePointIn{p.x_mm, p.wear_um});
    rows.push_back(i);
  }
  for (const auto& [in, rows] : profiles) {
    const std::string where = LocatePoint(lines, d, rows.front(), "campaign_id");
    ROLLWEAR_ASSIGN_OR_RETURN(const std::optional<ProfileIn> stored,
                              LookupProfile(db, in));
    if (stored.has_value()) {
      if (*stored != in) {
        return Status::AlreadyExists(
            where + ": the profile of " + RollPositionName(in.stand, in.position) +
            " of campaign " + in.campaign_id +
            " is already stored with different content");
      }
      ++counts->unchanged;
      continue;
    }
    ROLLWEAR_RETURN_IF_ERROR(At(AdmitProfile(catalog, in), where));
    ROLLWEAR_ASSIGN_OR_RETURN(const int64_t row, CampaignRow(db, in.campaign_id));
    ROLLWEAR_RETURN_IF_ERROR(InsertProfile(db, row, in));
    ++counts->added;
  }
  return Status::Ok();
}

Status ReadStoredProfiles(Db* db,
                          const std::unordered_map<int64_t, int>& campaign_index,
                          Dataset* data) {
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st,
      db->Prepare("SELECT campaign, stand, position, roll_id, measured_at, "
                  "x_mm, wear_um FROM profile_points ORDER BY campaign, "
                  "stand, position, point"));
  while (true) {
    ROLLWEAR_ASSIGN_OR_RETURN(const bool row, st.Step());
    if (!row) return Status::Ok();
    auto it = campaign_index.find(st.ColumnInt(0));
    if (it == campaign_index.end()) continue;
    ProfilePoint p;
    p.campaign = it->second;
    p.stand = static_cast<int>(st.ColumnInt(1));
    p.position = static_cast<Position>(st.ColumnInt(2));
    p.roll_id = st.ColumnText(3);
    p.measured_at = st.ColumnInt(4);
    p.x_mm = st.ColumnDouble(5);
    p.wear_um = st.ColumnDouble(6);
    data->profile_points.push_back(std::move(p));
  }
}

StatusOr<WriteOutcome> MillStoreImpl::AddProfile(const ProfileIn& in) {
  ROLLWEAR_RETURN_IF_ERROR(CheckProfileFields(in));
  // Decided inside the writer's transaction (tasks run alone in theirs), so
  // two posts of one key are ordered: the second sees the first's rows.
  WriteOutcome outcome = WriteOutcome::kCreated;
  ROLLWEAR_RETURN_IF_ERROR(RunTask(
      [&](Db* db) -> Status {
        ROLLWEAR_ASSIGN_OR_RETURN(const std::optional<ProfileIn> stored,
                                  LookupProfile(db, in));
        if (stored.has_value()) {
          if (*stored != in) {
            return Status::AlreadyExists(
                "campaign_id: the profile of " +
                RollPositionName(in.stand, in.position) + " in campaign " +
                in.campaign_id + " is already stored with different content");
          }
          outcome = WriteOutcome::kUnchanged;
          return Status::Ok();
        }
        {
          std::lock_guard<std::mutex> lock(mu_);
          ROLLWEAR_RETURN_IF_ERROR(AdmitProfile(committed_, in));
        }
        ROLLWEAR_ASSIGN_OR_RETURN(const int64_t row,
                                  CampaignRow(db, in.campaign_id));
        return InsertProfile(db, row, in);
      },
      nullptr));
  return outcome;
}

}  // namespace rollwear::storage::internal
