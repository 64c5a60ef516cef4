#include "storage/store_sql.h"

#include <bit>
#include <cstring>
#include <functional>
#include <string_view>
#include <utility>

#include "storage/extra_json.h"

namespace rollwear::storage::internal {
namespace {

// `var` names the declared variable, so it cannot be parenthesised.
// NOLINTBEGIN(bugprone-macro-parentheses)
#define ROLLWEAR_ASSIGN_STMT(var, db, sql)                      \
  ROLLWEAR_ASSIGN_OR_RETURN(Statement* var, (db)->Cached(sql)); \
  ResetOnExit var##_reset(var)
// NOLINTEND(bugprone-macro-parentheses)

void BindExtra(Statement* st, int i, const std::string& extra_json) {
  if (extra_json.empty()) {
    st->BindNull(i);
  } else {
    st->BindText(i, extra_json);
  }
}

}  // namespace

Status ForEachRow(Statement* st,
                  const std::function<void(const Statement&)>& visit) {
  while (true) {
    ROLLWEAR_ASSIGN_OR_RETURN(const bool row, st->Step());
    if (!row) return Status::Ok();
    visit(*st);
  }
}

void ReadPassMeasures(const Statement& st, int first, PassMeasures* measures,
                      UnixSeconds* rolled_at) {
  measures->stand = static_cast<int>(st.ColumnInt(first));
  *rolled_at = st.ColumnInt(first + 1);
  measures->force_kn = st.ColumnDouble(first + 2);
  measures->width_mm = st.ColumnDouble(first + 3);
  measures->length_m = st.ColumnDouble(first + 4);
  measures->entry_thickness_mm = st.ColumnDouble(first + 5);
  measures->exit_thickness_mm = st.ColumnDouble(first + 6);
  measures->temperature_c = st.ColumnDouble(first + 7);
  measures->speed_mps = st.ColumnDouble(first + 8);
  measures->lubrication = st.ColumnInt(first + 9) != 0;
  measures->shift_mm = st.ColumnDouble(first + 10);
}

StatusOr<int64_t> InsertCampaign(Db* db, const std::string& campaign_id,
                                 UnixSeconds started_at,
                                 std::optional<UnixSeconds> ended_at,
                                 const std::string& extra_json) {
  ROLLWEAR_ASSIGN_STMT(st, db,
                       "INSERT INTO campaigns (campaign_id, started_at, "
                       "ended_at, extra) VALUES (?, ?, ?, ?)");
  st->BindText(1, campaign_id).BindInt(2, started_at);
  if (ended_at.has_value()) {
    st->BindInt(3, *ended_at);
  } else {
    st->BindNull(3);
  }
  BindExtra(st, 4, extra_json);
  ROLLWEAR_RETURN_IF_ERROR(st->Run());
  return db->LastInsertRowId();
}

StatusOr<int64_t> CampaignRow(Db* db, const std::string& campaign_id) {
  ROLLWEAR_ASSIGN_STMT(st, db, kCampaignRowSql);
  st->BindText(1, campaign_id);
  ROLLWEAR_ASSIGN_OR_RETURN(const bool row, st->Step());
  if (!row) return Status::NotFound("unknown campaign " + campaign_id);
  return st->ColumnInt(0);
}

Status SetCampaignEnded(Db* db, const std::string& campaign_id,
                        UnixSeconds ended_at) {
  ROLLWEAR_ASSIGN_STMT(
      st, db, "UPDATE campaigns SET ended_at = ? WHERE campaign_id = ?");
  st->BindInt(1, ended_at).BindText(2, campaign_id);
  ROLLWEAR_RETURN_IF_ERROR(st->Run());
  if (db->Changes() != 1) {
    return Status::Internal("end campaign " + campaign_id + ": not stored");
  }
  return Status::Ok();
}

Status EndOpenCampaigns(Db* db, UnixSeconds ended_at) {
  ROLLWEAR_ASSIGN_STMT(
      st, db, "UPDATE campaigns SET ended_at = ? WHERE ended_at IS NULL");
  st->BindInt(1, ended_at);
  return st->Run();
}

Status InsertMount(Db* db, int64_t campaign_row, const MountedRollIn& m,
                   const std::string& extra_json) {
  ROLLWEAR_ASSIGN_STMT(
      st, db,
      "INSERT INTO mounts (campaign, stand, position, roll_id, roll_type, "
      "diameter_mm, hardness_hb, extra) VALUES (?, ?, ?, ?, ?, ?, ?, ?)");
  st->BindInt(1, campaign_row)
      .BindInt(2, m.stand)
      .BindInt(3, static_cast<int>(m.position))
      .BindText(4, m.roll_id)
      .BindText(5, m.roll_type)
      .BindDouble(6, m.diameter_mm)
      .BindDouble(7, m.hardness_hb);
  BindExtra(st, 8, extra_json);
  return st->Run();
}

StatusOr<int64_t> InsertCoil(Db* db, int64_t campaign_row,
                             const StoredCoil& coil,
                             const std::string* wear_blob) {
  ROLLWEAR_ASSIGN_STMT(
      st, db,
      "INSERT INTO coils (coil_id, campaign, seq, grade, wear) "
      "VALUES (?, ?, ?, ?, ?)");
  st->BindText(1, coil.coil_id)
      .BindInt(2, campaign_row)
      .BindInt(3, coil.seq)
      .BindText(4, coil.grade);
  if (wear_blob != nullptr) {
    st->BindBlob(5, *wear_blob);
  } else {
    st->BindNull(5);
  }
  ROLLWEAR_RETURN_IF_ERROR(st->Run());
  return db->LastInsertRowId();
}

Status InsertPass(Db* db, int64_t coil_row, int64_t campaign_row,
                  const StoredPass& p, const std::string& extra_json) {
  ROLLWEAR_ASSIGN_STMT(
      st, db,
      "INSERT INTO passes (coil, campaign, stand, rolled_at, force_kn, "
      "width_mm, length_m, entry_thickness_mm, exit_thickness_mm, "
      "temperature_c, speed_mps, lubrication, shift_mm, extra) "
      "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  st->BindInt(1, coil_row)
      .BindInt(2, campaign_row)
      .BindInt(3, p.stand)
      .BindInt(4, p.rolled_at)
      .BindDouble(5, p.force_kn)
      .BindDouble(6, p.width_mm)
      .BindDouble(7, p.length_m)
      .BindDouble(8, p.entry_thickness_mm)
      .BindDouble(9, p.exit_thickness_mm)
      .BindDouble(10, p.temperature_c)
      .BindDouble(11, p.speed_mps)
      .BindInt(12, p.lubrication ? 1 : 0)
      .BindDouble(13, p.shift_mm);
  BindExtra(st, 14, extra_json);
  return st->Run();
}

Status InsertCoilWithPasses(Db* db, const StoredCoil& coil,
                            const std::string* wear_blob) {
  ROLLWEAR_ASSIGN_OR_RETURN(const int64_t campaign,
                            CampaignRow(db, coil.campaign_id));
  ROLLWEAR_ASSIGN_OR_RETURN(const int64_t row,
                            InsertCoil(db, campaign, coil, wear_blob));
  for (const StoredPass& p : coil.passes) {
    ROLLWEAR_RETURN_IF_ERROR(
        InsertPass(db, row, campaign, p, ExtraFieldsJson(p.extra)));
  }
  return Status::Ok();
}

Status InsertMeasurement(Db* db, int64_t campaign_row, const MeasurementIn& m,
                         const std::string& extra_json) {
  ROLLWEAR_ASSIGN_STMT(
      st, db,
      "INSERT INTO measurements (campaign, stand, position, roll_id, "
      "measured_at, wear_center_um, extra, suspect) "
      "VALUES (?, ?, ?, ?, ?, ?, ?, ?)");
  st->BindInt(1, campaign_row)
      .BindInt(2, m.stand)
      .BindInt(3, static_cast<int>(m.position))
      .BindText(4, m.roll_id)
      .BindInt(5, m.measured_at)
      .BindDouble(6, m.wear_center_um);
  BindExtra(st, 7, extra_json);
  BindExtra(st, 8, m.suspect);  // NULL when empty
  return st->Run();
}

StatusOr<std::optional<StoredCoil>> LookupCoil(Db* db,
                                               const std::string& coil_id) {
  ROLLWEAR_ASSIGN_STMT(st, db, kLookupCoilSql);
  st->BindText(1, coil_id);
  std::optional<StoredCoil> out;
  while (true) {
    ROLLWEAR_ASSIGN_OR_RETURN(const bool row, st->Step());
    if (!row) break;
    if (!out.has_value()) {
      out.emplace();
      out->coil_id = coil_id;
      out->campaign_id = st->ColumnText(0);
      out->seq = static_cast<int>(st->ColumnInt(1));
      out->grade = st->ColumnText(2);
    }
    StoredPass p;
    p.stand = static_cast<int>(st->ColumnInt(3));
    p.rolled_at = st->ColumnInt(4);
    p.force_kn = st->ColumnDouble(5);
    p.width_mm = st->ColumnDouble(6);
    p.length_m = st->ColumnDouble(7);
    p.entry_thickness_mm = st->ColumnDouble(8);
    p.exit_thickness_mm = st->ColumnDouble(9);
    p.temperature_c = st->ColumnDouble(10);
    p.speed_mps = st->ColumnDouble(11);
    p.lubrication = st->ColumnInt(12) != 0;
    p.shift_mm = st->ColumnDouble(13);
    ROLLWEAR_ASSIGN_OR_RETURN(p.extra, ParseExtraFields(st->ColumnText(14)));
    out->passes.push_back(std::move(p));
  }
  return out;
}

Status ForEachCoilId(Db* db,
                     const std::function<void(const std::string&)>& visit) {
  // Once per open: not cached. Reads the coil_id index, not the table.
  ROLLWEAR_ASSIGN_OR_RETURN(Statement st,
                            db->Prepare("SELECT coil_id FROM coils"));
  return ForEachRow(&st,
                    [&](const Statement& row) { visit(row.ColumnText(0)); });
}

StatusOr<std::optional<std::string>> LookupSeq(Db* db,
                                               const std::string& campaign_id,
                                               int seq) {
  ROLLWEAR_ASSIGN_STMT(st, db, kLookupSeqSql);
  st->BindText(1, campaign_id).BindInt(2, seq);
  ROLLWEAR_ASSIGN_OR_RETURN(const bool row, st->Step());
  std::optional<std::string> out;
  if (row) out = st->ColumnText(0);
  return out;
}

namespace {

// The fields of a stored `extra`; on a bad one, none, and *bad (when still
// OK) says why - for the row visitors, which return nothing.
ExtraFields ExtraOrNote(std::string_view text, Status* bad) {
  StatusOr<ExtraFields> f = ParseExtraFields(text);
  if (f.ok()) return std::move(f).value();
  if (bad->ok()) *bad = f.status();
  return {};
}

// Row id -> campaign_id, for the rows that refer to campaigns by row id.
using CampaignByRow = std::unordered_map<int64_t, std::string>;

// The campaigns, and which one is open.
Status LoadCampaigns(Db* db, Catalog* catalog, CampaignByRow* by_row_out) {
  Catalog& c = *catalog;
  CampaignByRow& by_row = *by_row_out;
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st,
      db->Prepare("SELECT id, campaign_id, started_at, ended_at, extra FROM "
                  "campaigns ORDER BY id"));
  UnixSeconds open_start = 0;
  Status bad;
  ROLLWEAR_RETURN_IF_ERROR(ForEachRow(&st, [&](const Statement& row) {
    CampaignRec rec;
    rec.id = row.ColumnText(1);
    rec.started_at = row.ColumnInt(2);
    if (!row.ColumnIsNull(3)) rec.ended_at = row.ColumnInt(3);
    rec.extra = ExtraOrNote(row.ColumnText(4), &bad);
    // At most one campaign is open; should a file hold several, the
    // latest start is the one coils go to.
    if (!rec.ended_at &&
        (c.open_campaign.empty() || rec.started_at >= open_start)) {
      c.open_campaign = rec.id;
      open_start = rec.started_at;
    }
    by_row[row.ColumnInt(0)] = rec.id;
    c.order.push_back(rec.id);
    c.campaigns[rec.id] = std::move(rec);
  }));
  return bad;
}

// Each campaign's mounted rolls, and the roll positions seen.
Status LoadMounts(Db* db, CampaignByRow* by_row, Catalog* c) {
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st,
      db->Prepare("SELECT campaign, stand, position, roll_id, roll_type, "
                  "diameter_mm, hardness_hb, extra FROM mounts ORDER BY id"));
  Status bad;
  ROLLWEAR_RETURN_IF_ERROR(ForEachRow(&st, [&](const Statement& row) {
    MountedRollIn m;
    m.stand = static_cast<int>(row.ColumnInt(1));
    m.position = static_cast<Position>(row.ColumnInt(2));
    m.roll_id = row.ColumnText(3);
    m.roll_type = row.ColumnText(4);
    m.diameter_mm = row.ColumnDouble(5);
    m.hardness_hb = row.ColumnDouble(6);
    m.extra = ExtraOrNote(row.ColumnText(7), &bad);
    const int slot = RollPositionSlot(m.stand, m.position);
    c->positions_seen |= 1u << slot;
    c->campaigns[(*by_row)[row.ColumnInt(0)]].mounts[slot] = std::move(m);
  }));
  return bad;
}

// Each campaign's grinder measurements.
Status LoadMeasurements(Db* db, CampaignByRow* by_row, Catalog* c) {
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st,
      db->Prepare("SELECT campaign, stand, position, roll_id, measured_at, "
                  "wear_center_um, extra, suspect FROM measurements "
                  "ORDER BY id"));
  Status bad;
  ROLLWEAR_RETURN_IF_ERROR(ForEachRow(&st, [&](const Statement& row) {
    MeasurementIn m;
    m.campaign_id = (*by_row)[row.ColumnInt(0)];
    m.stand = static_cast<int>(row.ColumnInt(1));
    m.position = static_cast<Position>(row.ColumnInt(2));
    m.roll_id = row.ColumnText(3);
    m.measured_at = row.ColumnInt(4);
    m.wear_center_um = row.ColumnDouble(5);
    m.extra = ExtraOrNote(row.ColumnText(6), &bad);
    m.suspect = row.ColumnText(7);  // "" for NULL
    const int slot = RollPositionSlot(m.stand, m.position);
    c->campaigns[m.campaign_id].measurements[slot] = std::move(m);
  }));
  return bad;
}

// Each campaign's per-stand load and rolled length (CampaignRec::load),
// summed pass by pass in row order (AddExposure sums a coil's passes as it
// commits: the same sums to the last bit or two).
Status LoadExposures(Db* db, CampaignByRow* by_row, Catalog* c) {
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st,
      db->Prepare("SELECT campaign, stand, force_kn, width_mm, length_m FROM "
                  "passes ORDER BY id"));
  int64_t last_row = -1;
  CampaignRec* rec = nullptr;
  return ForEachRow(&st, [&](const Statement& row) {
    if (row.ColumnInt(0) != last_row) {
      last_row = row.ColumnInt(0);
      const auto id = by_row->find(last_row);
      const auto it = id == by_row->end() ? c->campaigns.end()
                                          : c->campaigns.find(id->second);
      rec = it == c->campaigns.end() ? nullptr : &it->second;
    }
    if (rec == nullptr) return;  // the foreign key keeps this from happening
    const int stand = static_cast<int>(row.ColumnInt(1));
    PassMeasures p;
    p.force_kn = row.ColumnDouble(2);
    p.width_mm = row.ColumnDouble(3);
    p.length_m = row.ColumnDouble(4);
    rec->load[stand] += PassLoad(p);
    rec->length_m[stand] += p.length_m;
  });
}

// The coils of the open campaign by sequence number.
Status LoadOpenSeqs(Db* db, Catalog* c) {
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st,
      db->Prepare("SELECT c.seq, c.coil_id FROM coils c JOIN campaigns g ON "
                  "g.id = c.campaign WHERE g.campaign_id = ?"));
  st.BindText(1, c->open_campaign);
  return ForEachRow(&st, [&](const Statement& row) {
    c->open_seqs[static_cast<int>(row.ColumnInt(0))] = row.ColumnText(1);
  });
}

}  // namespace

StatusOr<Catalog> LoadCatalog(Db* db) {
  Catalog c;
  CampaignByRow by_row;
  ROLLWEAR_RETURN_IF_ERROR(LoadCampaigns(db, &c, &by_row));
  ROLLWEAR_RETURN_IF_ERROR(LoadMounts(db, &by_row, &c));
  ROLLWEAR_RETURN_IF_ERROR(LoadMeasurements(db, &by_row, &c));
  ROLLWEAR_RETURN_IF_ERROR(LoadExposures(db, &by_row, &c));
  if (!c.open_campaign.empty()) {
    ROLLWEAR_RETURN_IF_ERROR(LoadOpenSeqs(db, &c));
  }
  return c;
}

StatusOr<StoredCounts> LoadCounts(Db* db) {
  ROLLWEAR_ASSIGN_OR_RETURN(
      Statement st,
      db->Prepare(
          "SELECT (SELECT COUNT(*) FROM campaigns), "
          "(SELECT COUNT(*) FROM coils), (SELECT COUNT(*) FROM measurements), "
          "(SELECT COUNT(*) FROM measurements WHERE id > "
          "  (SELECT IFNULL(MAX(measurement_watermark), 0) "
          "FROM calibrations)), "
          "(SELECT COUNT(*) FROM measurements WHERE suspect IS NOT NULL)"));
  ROLLWEAR_RETURN_IF_ERROR(st.Step().status());
  StoredCounts n;
  n.campaigns = st.ColumnInt(0);
  n.coils = st.ColumnInt(1);
  n.measurements = st.ColumnInt(2);
  n.measurements_since_last_calibration = st.ColumnInt(3);
  n.suspect_measurements = st.ColumnInt(4);
  return n;
}

// ------------------------------------------------------- coil wear answers

// Format 1: a format byte, then per entry the slot (one byte) and the two
// doubles' IEEE-754 bytes, little-endian (the byte order of every machine
// rollwear runs on; checked at compile time).
static_assert(std::endian::native == std::endian::little,
              "coil wear encoding assumes a little-endian machine");
constexpr char kCoilWearFormat = 1;
constexpr size_t kCoilWearEntryBytes = 1 + 2 * sizeof(double);

std::string EncodeCoilWear(const std::vector<CoilWearEntry>& entries) {
  std::string out(1 + entries.size() * kCoilWearEntryBytes, '\0');
  out[0] = kCoilWearFormat;
  char* p = out.data() + 1;
  for (const CoilWearEntry& e : entries) {
    *p++ = static_cast<char>(e.slot);
    std::memcpy(p, &e.wear_um, sizeof(double));
    p += sizeof(double);
    std::memcpy(p, &e.total_um, sizeof(double));
    p += sizeof(double);
  }
  return out;
}

bool DecodeCoilWear(std::string_view blob, std::vector<CoilWearEntry>* out) {
  out->clear();
  if (blob.empty() || blob[0] != kCoilWearFormat ||
      (blob.size() - 1) % kCoilWearEntryBytes != 0) {
    return false;
  }
  const char* p = blob.data() + 1;
  const size_t n = (blob.size() - 1) / kCoilWearEntryBytes;
  out->resize(n);
  for (size_t i = 0; i < n; ++i) {
    CoilWearEntry& e = (*out)[i];
    e.slot = static_cast<unsigned char>(*p++);
    if (e.slot >= kNumRollPositionSlots) return false;
    std::memcpy(&e.wear_um, p, sizeof(double));
    p += sizeof(double);
    std::memcpy(&e.total_um, p, sizeof(double));
    p += sizeof(double);
  }
  return true;
}

StatusOr<std::optional<std::string>> LookupCoilWear(
    Db* db, const std::string& coil_id) {
  ROLLWEAR_ASSIGN_STMT(st, db, kCoilWearSql);
  st->BindText(1, coil_id);
  ROLLWEAR_ASSIGN_OR_RETURN(const bool row, st->Step());
  if (!row || st->ColumnIsNull(0)) return std::optional<std::string>();
  return std::optional<std::string>(st->ColumnBlob(0));
}

std::vector<PerRequestQuery> PerRequestQueries() {
  return {
      {"LookupCoil", kLookupCoilSql, {}},
      {"LookupSeq", kLookupSeqSql, {}},
      {"LookupCoilWear", kCoilWearSql, {}},
      {"CampaignRow", kCampaignRowSql, {}},
      {"LookupProfile", kLookupProfileSql, {}},
      {"CampaignsWithProfiles", kCampaignsWithProfilesSql, {"c"}},
      {"ReplayCampaign", ReplayCampaignQuery(), {}},
  };
}

std::string ReplayCampaignQuery() {
  return std::string("SELECT c.coil_id, c.grade, ") + kPassMeasureColumns +
         ", c.id, c.wear IS NULL, p.extra "
         "FROM passes p JOIN coils c ON c.id = p.coil "
         "WHERE c.campaign = (SELECT id FROM campaigns WHERE campaign_id = ?) "
         "ORDER BY c.id, p.id";
}

StatusOr<RollStates> ReplayCampaignCoils(Db* db, const WearPredictor& predictor,
                                         const CampaignRec& campaign,
                                         const WearModel& model,
                                         const CoilVisitor& visit,
                                         bool track_profiles) {
  RollStates states;
  for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
    const auto& m = campaign.mounts[slot];
    if (!m.has_value()) continue;
    states[slot] = predictor.Mount(model, *m, campaign.started_at,
                                   campaign.extra, track_profiles);
  }
  ROLLWEAR_ASSIGN_OR_RETURN(Statement st, db->Prepare(ReplayCampaignQuery()));
  st.BindText(1, campaign.id);
  // A coil's passes are stored together, so a coil ends where the next
  // row's coil differs.
  ReplayedCoil coil;
  coil.row = -1;
  Status visit_status;
  auto flush = [&] {
    if (coil.row >= 0 && visit && visit_status.ok()) {
      visit_status = visit(coil);
    }
    coil.entries.clear();
  };
  StoredPass pass;
  while (true) {
    ROLLWEAR_ASSIGN_OR_RETURN(const bool row, st.Step());
    if (!row) break;
    const int64_t coil_row = st.ColumnInt(13);
    if (coil_row != coil.row) {
      flush();
      coil.row = coil_row;
      coil.coil_id = st.ColumnText(0);
      coil.wear_missing = st.ColumnInt(14) != 0;
    }
    ReadPassMeasures(st, 2, &pass, &pass.rolled_at);
    ROLLWEAR_ASSIGN_OR_RETURN(pass.extra, ParseExtraFields(st.ColumnText(15)));
    const PassInput in = ToPassInput(st.ColumnText(1), pass);
    for (Position p : {Position::kTop, Position::kBottom}) {
      const int slot = RollPositionSlot(pass.stand, p);
      auto& s = states[slot];
      if (!s.has_value()) continue;
      const double wear = predictor.AddPass(model, in, &*s);
      coil.entries.push_back(
          CoilWearEntry{slot, wear, s->wear_um, s->rolled_length_m});
    }
  }
  flush();
  ROLLWEAR_RETURN_IF_ERROR(visit_status);
  return states;
}

StatusOr<RollStates> ReplayCampaign(Db* db, const WearPredictor& predictor,
                                    const CampaignRec& campaign,
                                    const WearModel& model,
                                    bool track_profiles) {
  return ReplayCampaignCoils(db, predictor, campaign, model, nullptr,
                             track_profiles);
}

StatusOr<int> BackfillCoilWear(Db* db, const WearPredictor& predictor,
                               const Catalog& catalog, const WearModel& model) {
  std::vector<std::string> campaigns;
  {
    ROLLWEAR_ASSIGN_STMT(
        st, db,
        "SELECT DISTINCT k.campaign_id FROM coils c "
        "JOIN campaigns k ON k.id = c.campaign WHERE c.wear IS NULL");
    while (true) {
      ROLLWEAR_ASSIGN_OR_RETURN(const bool row, st->Step());
      if (!row) break;
      campaigns.push_back(st->ColumnText(0));
    }
  }
  int filled = 0;
  for (const std::string& id : campaigns) {
    auto it = catalog.campaigns.find(id);
    if (it == catalog.campaigns.end()) {
      return Status::Internal("campaign " + id + " is not in the catalog");
    }
    const auto fill = [&](const ReplayedCoil& coil) -> Status {
      if (!coil.wear_missing) return Status::Ok();
      ROLLWEAR_ASSIGN_STMT(up, db, "UPDATE coils SET wear = ? WHERE id = ?");
      up->BindBlob(1, EncodeCoilWear(coil.entries)).BindInt(2, coil.row);
      ++filled;
      return up->Run();
    };
    ROLLWEAR_RETURN_IF_ERROR(
        ReplayCampaignCoils(db, predictor, it->second, model, fill).status());
  }
  return filled;
}

}  // namespace rollwear::storage::internal
