// Reading a dataset folder: file access, CSV parsing (core/base/csv.h) and the
// rules of the format's bad-input section, file by file (field syntax in
// dataset_checks.cc, the rules of one record in input_rules.cc, the keys
// across rows here). Writing and the timestamp codec live in
// dataset_write.cc.
#include "core/dataset/dataset_io.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <istream>
#include <map>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "core/base/csv.h"
#include "core/base/parallel.h"
#include "core/dataset/dataset_checks.h"
#include "core/dataset/dataset_columns.h"
#include "core/dataset/input_rules.h"

namespace rollwear {
namespace {

// Interns `label` into `table` through `index` (views into stable buffers).
int InternView(std::string_view label, LabelIndex* index,
               std::vector<std::string>* table) {
  bool added = false;
  const int i = index->Insert(label, static_cast<int>(table->size()), &added);
  if (added) table->emplace_back(label);
  return i;
}

// A grinder time, or, where the export does not record it (an empty
// field, data-format.md's real mill exports), the campaign's end: cooling_h
// is then 0 for every such reading and carries no information.
Status MeasuredAtOrEnd(const FileView& f, size_t r, int k,
                       const Campaign& campaign, UnixSeconds* out) {
  if (csv::Trim(f.Raw(r, k)).empty()) {
    *out = campaign.ended_at;
    return Status::Ok();
  }
  return f.Time(r, k, out);
}

Status ReadCampaigns(const FileView& f, Dataset* d, LabelIndex* ids,
                     std::vector<int>* lines) {
  namespace col = campaign_col;
  std::vector<int>& first_line = *lines;
  d->campaigns.reserve(f.rows());
  ids->reserve(f.rows());
  for (size_t r = 0; r < f.rows(); ++r) {
    ROLLWEAR_RETURN_IF_ERROR(f.CheckFieldCount(r));
    Campaign c;
    std::string_view id;
    ROLLWEAR_RETURN_IF_ERROR(f.Text(r, col::kId, &id));
    ROLLWEAR_RETURN_IF_ERROR(f.Time(r, col::kStartedAt, &c.started_at));
    ROLLWEAR_RETURN_IF_ERROR(f.Time(r, col::kEndedAt, &c.ended_at));
    ROLLWEAR_RETURN_IF_ERROR(
        f.Check(r, CampaignRules(id, c.started_at, c.ended_at)));
    bool added = false;
    const int index =
        ids->Insert(id, static_cast<int>(d->campaigns.size()), &added);
    if (!added) {
      return f.Error(r, col::kId,
                     "duplicate campaign_id " + Quote(id) + " (first on line " +
                         std::to_string(first_line[index]) + ")");
    }
    c.id = std::string(id);
    d->campaigns.push_back(std::move(c));
    first_line.push_back(f.line(r));
  }
  f.CollectExtras(&d->campaign_extra);
  return Status::Ok();
}

Status ReadMounts(const FileView& f, LabelIndex* campaigns, Dataset* d,
                  std::vector<int>* mount_of, std::vector<int>* mount_lines) {
  namespace col = mount_col;
  LabelIndex roll_types;
  mount_of->assign(d->campaigns.size() * kNumRollPositionSlots, -1);
  std::vector<int>& lines = *mount_lines;
  for (size_t r = 0; r < f.rows(); ++r) {
    ROLLWEAR_RETURN_IF_ERROR(f.CheckFieldCount(r));
    Mount m;
    ROLLWEAR_RETURN_IF_ERROR(
        f.Campaign(r, col::kCampaign, campaigns, &m.campaign));
    ROLLWEAR_RETURN_IF_ERROR(f.Stand(r, col::kStand, &m.stand));
    ROLLWEAR_RETURN_IF_ERROR(f.PositionOf(r, col::kPosition, &m.position));
    std::string_view roll_id, roll_type;
    ROLLWEAR_RETURN_IF_ERROR(f.Text(r, col::kRollId, &roll_id));
    // Real mill exports (data-format.md): a roll type that is not known is
    // empty or "unknown", one label; an empty hardness is NaN (only the
    // Nikitenko law needs it and refuses then: Aggregate).
    roll_type = csv::Trim(f.Raw(r, col::kRollType));
    if (roll_type.empty()) roll_type = kUnknownRollType;
    ROLLWEAR_RETURN_IF_ERROR(f.Number(r, col::kDiameter, &m.diameter_mm));
    if (csv::Trim(f.Raw(r, col::kHardness)).empty()) {
      m.hardness_hb = std::nan("");
    } else {
      ROLLWEAR_RETURN_IF_ERROR(f.Number(r, col::kHardness, &m.hardness_hb));
    }
    ROLLWEAR_RETURN_IF_ERROR(
        f.Check(r, MountRules({m.stand, m.position, roll_id, roll_type,
                               m.diameter_mm,
                               // not recorded: no rule to break (the
                               // daemon's roll changes still need it)
                               std::isnan(m.hardness_hb) ? 1.0 : m.hardness_hb})));
    int& slot = (*mount_of)[m.campaign * kNumRollPositionSlots +
                            RollPositionSlot(m.stand, m.position)];
    if (slot >= 0) {
      return f.Error(r, col::kCampaign,
                     "duplicate key (campaign_id, stand, position): " +
                         RollPositionName(m.stand, m.position) +
                         " of campaign " + Quote(f.Raw(r, col::kCampaign)) +
                         " already mounted on line " +
                         std::to_string(lines[slot]));
    }
    slot = static_cast<int>(d->mounts.size());
    m.roll_id = std::string(roll_id);
    m.roll_type = InternView(roll_type, &roll_types, &d->roll_types);
    d->mounts.push_back(std::move(m));
    lines.push_back(f.line(r));
  }
  f.CollectExtras(&d->mount_extra);
  return Status::Ok();
}

// What the first row of a coil fixed; its other stands must agree.
struct CoilInfo {
  int campaign;
  int seq;
  int grade;
  int line;
  int stand_line[kMaxStand + 1];  // line of the pass at each stand, 0 if none
};

// Bit RollPositionSlot(...) set for each roll position campaign c mounts.
uint32_t MountedMask(const std::vector<int>& mount_of, int c) {
  uint32_t mask = 0;
  for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
    if (mount_of[c * kNumRollPositionSlots + slot] >= 0) mask |= 1u << slot;
  }
  return mask;
}

// The rules of row r that need no other row (dataset_checks.h, in the
// order the format lists them): fills *p but its grade and coil, which the
// key phase interns. `last_*` cache the previous row's campaign per
// thread (rows of one campaign come together).
Status ReadPassFields(const FileView& f, size_t r, const LabelIndex& campaigns,
                      const std::vector<int>& mount_of, const Dataset& d,
                      std::string_view* last_campaign, int* last_index,
                      Pass* p) {
  namespace col = coil_col;
  ROLLWEAR_RETURN_IF_ERROR(f.CheckFieldCount(r));
  std::string_view campaign, coil_id, grade;
  ROLLWEAR_RETURN_IF_ERROR(f.Text(r, col::kCampaign, &campaign));
  if (*last_index < 0 || campaign != *last_campaign) {
    *last_index = campaigns.Lookup(campaign);
    *last_campaign = campaign;
  }
  p->campaign = *last_index;
  if (p->campaign < 0) {
    return f.Error(
        r, col::kCampaign,
        "unknown campaign " + Quote(campaign) + " (not in campaigns.csv)");
  }
  int64_t seq = 0;
  ROLLWEAR_RETURN_IF_ERROR(f.Text(r, col::kCoil, &coil_id));
  ROLLWEAR_RETURN_IF_ERROR(f.Integer(r, col::kSeq, &seq));
  ROLLWEAR_RETURN_IF_ERROR(f.Time(r, col::kRolledAt, &p->rolled_at));
  ROLLWEAR_RETURN_IF_ERROR(f.Text(r, col::kGrade, &grade));
  ROLLWEAR_RETURN_IF_ERROR(
      f.Check(r, CoilKeyRules(coil_id, campaign, seq, grade)));
  p->seq = static_cast<int>(seq);
  ROLLWEAR_RETURN_IF_ERROR(f.Stand(r, col::kStand, &p->stand));
  ROLLWEAR_RETURN_IF_ERROR(f.Number(r, col::kForce, &p->force_kn));
  ROLLWEAR_RETURN_IF_ERROR(f.Number(r, col::kWidth, &p->width_mm));
  ROLLWEAR_RETURN_IF_ERROR(f.Number(r, col::kLength, &p->length_m));
  ROLLWEAR_RETURN_IF_ERROR(f.Number(r, col::kEntry, &p->entry_thickness_mm));
  ROLLWEAR_RETURN_IF_ERROR(f.Number(r, col::kExit, &p->exit_thickness_mm));
  ROLLWEAR_RETURN_IF_ERROR(f.Number(r, col::kTemperature, &p->temperature_c));
  ROLLWEAR_RETURN_IF_ERROR(f.Number(r, col::kSpeed, &p->speed_mps));
  // Empty where the stand has no lubrication sensor (data-format.md, real
  // mill exports): read as off, so a lubrication term can only be
  // identified where it was recorded.
  const std::string_view lub = csv::Trim(f.Raw(r, col::kLubrication));
  if (!lub.empty() && lub != "0" && lub != "1") {
    return f.Error(r, col::kLubrication, "must be 0 or 1, got " + Quote(lub));
  }
  p->lubrication = lub == "1";
  ROLLWEAR_RETURN_IF_ERROR(f.Number(r, col::kShift, &p->shift_mm));
  ROLLWEAR_RETURN_IF_ERROR(f.Check(r, PassRules(*p)));
  return f.Check(r, PassMountRules(p->stand, d.campaigns[p->campaign].id,
                                   MountedMask(mount_of, p->campaign)));
}

// The first broken row-local rule of coils.csv, by row, as (row, error);
// row = rows() when none. Rows are read in two halves on two threads (a
// paper-size file has ~100,000 rows; docs/performance.md), each stopping
// at its first broken rule, so the answer is the serial one.
std::pair<size_t, Status> ReadAllPassFields(const FileView& f,
                                            const LabelIndex& campaigns,
                                            const std::vector<int>& mount_of,
                                            Dataset* d) {
  const size_t n = f.rows();
  constexpr size_t kRowsPerThread = 8192;
  const int parts = n >= 2 * kRowsPerThread ? 2 : 1;
  std::pair<size_t, Status> first[2] = {{n, Status::Ok()}, {n, Status::Ok()}};
  d->passes.resize(n);
  ParallelFor(parts, parts, [&](int part) {
    const size_t begin = n * part / parts;
    const size_t end = n * (part + 1) / parts;
    std::string_view last_campaign;
    int last_index = -1;
    for (size_t r = begin; r < end; ++r) {
      Status s = ReadPassFields(f, r, campaigns, mount_of, *d, &last_campaign,
                                &last_index, &d->passes[r]);
      if (!s.ok()) {
        first[part] = {r, std::move(s)};
        return;
      }
    }
  });
  return first[0].first < n ? std::move(first[0]) : std::move(first[1]);
}

// coils.csv: the row-local rules (ReadAllPassFields), then the keys across
// rows in row order, so the first broken rule of the file is the one
// reported.
Status ReadCoils(const FileView& f, const LabelIndex& campaigns,
                 const std::vector<int>& mount_of, Dataset* d,
                 std::vector<int>* lines) {
  namespace col = coil_col;
  auto [bad_row, bad] = ReadAllPassFields(f, campaigns, mount_of, d);
  LabelIndex coil_index, grades;
  std::vector<CoilInfo> coils;
  // (campaign, seq) -> coil: seq orders the coils of a campaign.
  std::unordered_map<uint64_t, int> seq_owner;
  coil_index.reserve(f.rows());
  seq_owner.reserve(f.rows());
  lines->reserve(f.rows());
  for (size_t r = 0; r < f.rows(); ++r) {
    if (r == bad_row) return bad;
    Pass& p = d->passes[r];
    const std::string_view coil_id = f.Raw(r, col::kCoil);
    p.grade = InternView(f.Raw(r, col::kGrade), &grades, &d->grades);

    bool added = false;
    p.coil = coil_index.Insert(coil_id, static_cast<int>(coils.size()), &added);
    if (added) {
      const uint64_t key = (static_cast<uint64_t>(p.campaign) << 32) |
                           static_cast<uint32_t>(p.seq);
      auto [owner, fresh] = seq_owner.emplace(key, p.coil);
      if (!fresh) {
        const CoilInfo& other = coils[owner->second];
        return f.Error(r, col::kSeq,
                       "seq " + std::to_string(p.seq) + " of campaign " +
                           Quote(f.Raw(r, col::kCampaign)) +
                           " is already used by coil_id " +
                           Quote(d->coil_ids[owner->second]) + " (line " +
                           std::to_string(other.line) + ")");
      }
      CoilInfo info{p.campaign, p.seq, p.grade, f.line(r), {}};
      coils.push_back(info);
      d->coil_ids.emplace_back(coil_id);
    } else {
      const CoilInfo& info = coils[p.coil];
      auto where = [&] {
        return " on line " + std::to_string(info.line) + " (same coil_id " +
               Quote(coil_id) + " at another stand)";
      };
      if (info.campaign != p.campaign) {
        return f.Error(r, col::kCampaign,
                       "coil has campaign_id " +
                           Quote(d->campaigns[info.campaign].id) + where());
      }
      if (info.seq != p.seq) {
        return f.Error(r, col::kSeq,
                       "coil has seq " + std::to_string(info.seq) + where());
      }
      if (info.grade != p.grade) {
        return f.Error(
            r, col::kGrade,
            "coil has grade " + Quote(d->grades[info.grade]) + where());
      }
      if (info.stand_line[p.stand] != 0) {
        return f.Error(r, col::kCoil,
                       "duplicate key (coil_id, stand): coil_id " +
                           Quote(coil_id) + " at F" + std::to_string(p.stand) +
                           " already on line " +
                           std::to_string(info.stand_line[p.stand]));
      }
    }
    coils[p.coil].stand_line[p.stand] = f.line(r);
    lines->push_back(f.line(r));
  }
  f.CollectExtras(&d->pass_extra);
  return Status::Ok();
}

// A measurement or profile point of row r names the roll mounted there
// (`mount`, -1 when none) in its campaign.
Status MountedRoll(const FileView& f, size_t r, int stand_col, int roll_col,
                   const Dataset& d, int mount, std::string_view roll_id,
                   const std::string& where) {
  if (mount < 0) {
    return f.Error(r, stand_col, "no mount for " + where + " in mounts.csv");
  }
  if (d.mounts[mount].roll_id != roll_id) {
    return f.Error(r, roll_col,
                   "roll_id must match mounts.csv: " + where + " mounted " +
                       Quote(d.mounts[mount].roll_id) + ", got " +
                       Quote(roll_id));
  }
  return Status::Ok();
}

Status ReadMeasurements(const FileView& f, LabelIndex* campaigns,
                        const std::vector<int>& mount_of, Dataset* d,
                        std::vector<int>* lines) {
  namespace col = measurement_col;
  std::vector<int> measured(mount_of.size(), 0);  // line, 0 if none
  for (size_t r = 0; r < f.rows(); ++r) {
    ROLLWEAR_RETURN_IF_ERROR(f.CheckFieldCount(r));
    Measurement m;
    std::string_view roll_id;
    ROLLWEAR_RETURN_IF_ERROR(
        f.Campaign(r, col::kCampaign, campaigns, &m.campaign));
    ROLLWEAR_RETURN_IF_ERROR(f.Stand(r, col::kStand, &m.stand));
    ROLLWEAR_RETURN_IF_ERROR(f.PositionOf(r, col::kPosition, &m.position));
    ROLLWEAR_RETURN_IF_ERROR(f.Text(r, col::kRollId, &roll_id));
    ROLLWEAR_RETURN_IF_ERROR(
        MeasuredAtOrEnd(f, r, col::kMeasuredAt, d->campaigns[m.campaign],
                        &m.measured_at));
    ROLLWEAR_RETURN_IF_ERROR(f.Number(r, col::kWear, &m.wear_center_um));
    ROLLWEAR_RETURN_IF_ERROR(
        f.Check(r, MeasurementRules(f.Raw(r, col::kCampaign), m.stand,
                                    m.position, roll_id, m.wear_center_um)));
    const Campaign& campaign = d->campaigns[m.campaign];
    ROLLWEAR_RETURN_IF_ERROR(f.Check(
        r,
        MeasurementTimeRules(campaign.id, m.measured_at, campaign.ended_at)));
    const size_t key = m.campaign * kNumRollPositionSlots +
                       RollPositionSlot(m.stand, m.position);
    const std::string where = RollPositionName(m.stand, m.position) +
                              " of campaign " + Quote(f.Raw(r, col::kCampaign));
    if (measured[key] != 0) {
      return f.Error(r, col::kCampaign,
                     "duplicate key (campaign_id, stand, position): " + where +
                         " already measured on line " +
                         std::to_string(measured[key]));
    }
    ROLLWEAR_RETURN_IF_ERROR(MountedRoll(f, r, col::kStand, col::kRollId,
                                         *d, mount_of[key], roll_id, where));
    measured[key] = f.line(r);
    m.roll_id = std::string(roll_id);
    d->measurements.push_back(std::move(m));
    lines->push_back(f.line(r));
  }
  f.CollectExtras(&d->measurement_extra);
  return Status::Ok();
}

// profiles.csv: each point of a roll measured after its campaign, at most
// one point per barrel coordinate of a roll.
Status ReadProfiles(const FileView& f, LabelIndex* campaigns,
                    const std::vector<int>& mount_of, Dataset* d,
                    std::vector<int>* lines) {
  namespace col = profile_col;
  std::map<std::pair<size_t, double>, int> seen;  // (campaign slot, x) -> line
  for (size_t r = 0; r < f.rows(); ++r) {
    ROLLWEAR_RETURN_IF_ERROR(f.CheckFieldCount(r));
    ProfilePoint p;
    std::string_view roll_id;
    ROLLWEAR_RETURN_IF_ERROR(
        f.Campaign(r, col::kCampaign, campaigns, &p.campaign));
    ROLLWEAR_RETURN_IF_ERROR(f.Stand(r, col::kStand, &p.stand));
    ROLLWEAR_RETURN_IF_ERROR(f.PositionOf(r, col::kPosition, &p.position));
    ROLLWEAR_RETURN_IF_ERROR(f.Text(r, col::kRollId, &roll_id));
    ROLLWEAR_RETURN_IF_ERROR(
        MeasuredAtOrEnd(f, r, col::kMeasuredAt, d->campaigns[p.campaign],
                        &p.measured_at));
    ROLLWEAR_RETURN_IF_ERROR(f.Number(r, col::kX, &p.x_mm));
    ROLLWEAR_RETURN_IF_ERROR(f.Number(r, col::kWear, &p.wear_um));
    ROLLWEAR_RETURN_IF_ERROR(f.Check(
        r, ProfilePointRules(f.Raw(r, col::kCampaign), p.stand, p.position,
                             roll_id, p.x_mm, p.wear_um)));
    const Campaign& campaign = d->campaigns[p.campaign];
    ROLLWEAR_RETURN_IF_ERROR(f.Check(
        r,
        MeasurementTimeRules(campaign.id, p.measured_at, campaign.ended_at)));
    const size_t key = p.campaign * kNumRollPositionSlots +
                       RollPositionSlot(p.stand, p.position);
    const std::string where = RollPositionName(p.stand, p.position) +
                              " of campaign " + Quote(f.Raw(r, col::kCampaign));
    ROLLWEAR_RETURN_IF_ERROR(MountedRoll(f, r, col::kStand, col::kRollId,
                                         *d, mount_of[key], roll_id, where));
    auto [it, fresh] = seen.emplace(std::make_pair(key, p.x_mm), f.line(r));
    if (!fresh) {
      return f.Error(r, col::kX,
                     "duplicate key (campaign_id, stand, position, x_mm): " +
                         where + " has a point at x_mm " +
                         std::string(f.Raw(r, col::kX)) + " on line " +
                         std::to_string(it->second));
    }
    p.roll_id = std::string(roll_id);
    d->profile_points.push_back(std::move(p));
    lines->push_back(f.line(r));
  }
  return Status::Ok();
}

// Validates and converts the four file contents (in DatasetFile order) and
// profiles.csv's when `profiles` is not null.
StatusOr<Dataset> ParseDataset(std::string (&texts)[kNumDatasetFiles],
                               std::string* profiles, DatasetLines* lines,
                               const DatasetReadOptions& options) {
  DatasetLines unused;
  if (lines == nullptr) lines = &unused;
  *lines = DatasetLines();
  // All four tables stay alive until the end: label maps view their buffers.
  std::vector<csv::Table> tables;
  tables.reserve(kNumDatasetFiles);
  for (int i = 0; i < kNumDatasetFiles; ++i) {
    ROLLWEAR_ASSIGN_OR_RETURN(
        csv::Table t,
        csv::Table::Parse(std::move(texts[i]), kDatasetFileNames[i]));
    tables.push_back(std::move(t));
  }
  std::vector<FileView> files;
  files.reserve(kNumDatasetFiles);
  for (int i = 0; i < kNumDatasetFiles; ++i) {
    files.emplace_back(tables[i], kDatasetFileNames[i], kDatasetColumns[i]);
    files.back().set_local_utc_offset(options.local_utc_offset_s);
    ROLLWEAR_RETURN_IF_ERROR(files.back().Bind());
  }
  Dataset d;
  LabelIndex campaigns;
  std::vector<int> mount_of;
  ROLLWEAR_RETURN_IF_ERROR(
      ReadCampaigns(files[kCampaignsFile], &d, &campaigns, &lines->campaigns));
  ROLLWEAR_RETURN_IF_ERROR(ReadMounts(files[kMountsFile], &campaigns, &d,
                                      &mount_of, &lines->mounts));
  ROLLWEAR_RETURN_IF_ERROR(
      ReadCoils(files[kCoilsFile], campaigns, mount_of, &d, &lines->passes));
  ROLLWEAR_RETURN_IF_ERROR(ReadMeasurements(files[kMeasurementsFile],
                                            &campaigns, mount_of, &d,
                                            &lines->measurements));
  if (profiles != nullptr) {
    ROLLWEAR_ASSIGN_OR_RETURN(
        csv::Table t, csv::Table::Parse(std::move(*profiles), kProfilesFileName));
    FileView f(t, kProfilesFileName, kProfileColumns);
    f.set_local_utc_offset(options.local_utc_offset_s);
    ROLLWEAR_RETURN_IF_ERROR(f.Bind());
    ROLLWEAR_RETURN_IF_ERROR(ReadProfiles(f, &campaigns, mount_of, &d,
                                          &lines->profile_points));
  }
  return d;
}

// Reads the rest of `fp`, sizing the buffer once when the size is known.
bool ReadAll(std::FILE* fp, std::string* out) {
  const long start = std::ftell(fp);
  if (start >= 0 && std::fseek(fp, 0, SEEK_END) == 0) {
    const long end = std::ftell(fp);
    if (std::fseek(fp, start, SEEK_SET) != 0) return false;
    if (end > start) {
      out->resize(static_cast<size_t>(end - start));
      out->resize(std::fread(out->data(), 1, out->size(), fp));
    }
  }
  char buf[1 << 16];
  size_t got;
  while ((got = std::fread(buf, 1, sizeof(buf), fp)) > 0) out->append(buf, got);
  return std::ferror(fp) == 0;
}

// The same for a stream (string streams and files know their size).
bool ReadAll(std::istream* in, std::string* out) {
  const std::istream::pos_type start = in->tellg();
  if (start != std::istream::pos_type(-1) && in->seekg(0, std::ios::end)) {
    const std::istream::pos_type end = in->tellg();
    in->seekg(start);
    if (end != std::istream::pos_type(-1) && end > start) {
      out->resize(static_cast<size_t>(end - start));
      in->read(out->data(), static_cast<std::streamsize>(out->size()));
      out->resize(static_cast<size_t>(in->gcount()));
    }
  }
  in->clear(in->rdstate() & ~(std::ios::failbit | std::ios::eofbit));
  char buf[1 << 16];
  while (in->read(buf, sizeof(buf)) || in->gcount() > 0) {
    out->append(buf, static_cast<size_t>(in->gcount()));
  }
  return !in->bad();
}

Status MissingFile(int file, const std::string& detail) {
  return Status::InvalidArgument(std::string(kDatasetFileNames[file]) +
                                 ":0:0 " + kDatasetFileNames[file] +
                                 ": missing file" + detail);
}

}  // namespace

StatusOr<Dataset> ReadDataset(const std::string& dir, DatasetLines* lines,
                              const DatasetReadOptions& options) {
  std::string texts[kNumDatasetFiles];
  for (int i = 0; i < kNumDatasetFiles; ++i) {
    const std::string path = dir + "/" + kDatasetFileNames[i];
    std::FILE* fp = std::fopen(path.c_str(), "rb");
    if (fp == nullptr) {
      const int err = errno;
      if (err == ENOENT || err == ENOTDIR) {
        return MissingFile(i, " (" + path + ")");
      }
      return Status::IoError("cannot open " + path + ": " + std::strerror(err));
    }
    const bool ok = ReadAll(fp, &texts[i]);
    std::fclose(fp);
    if (!ok) return Status::IoError("cannot read " + path);
  }
  // profiles.csv is optional.
  const std::string profiles_path = dir + "/" + kProfilesFileName;
  std::FILE* fp = std::fopen(profiles_path.c_str(), "rb");
  if (fp == nullptr) {
    const int err = errno;
    if (err == ENOENT) return ParseDataset(texts, nullptr, lines, options);
    return Status::IoError("cannot open " + profiles_path + ": " +
                           std::strerror(err));
  }
  std::string profiles;
  const bool ok = ReadAll(fp, &profiles);
  std::fclose(fp);
  if (!ok) return Status::IoError("cannot read " + profiles_path);
  return ParseDataset(texts, &profiles, lines, options);
}

StatusOr<Dataset> ReadDatasetStreams(const DatasetStreams& in,
                                     DatasetLines* lines,
                                     const DatasetReadOptions& options) {
  std::istream* streams[kNumDatasetFiles] = {in.campaigns, in.mounts, in.coils,
                                             in.measurements};
  std::string texts[kNumDatasetFiles];
  for (int i = 0; i < kNumDatasetFiles; ++i) {
    if (streams[i] == nullptr) return MissingFile(i, " (no stream given)");
    if (!ReadAll(streams[i], &texts[i])) {
      return Status::IoError(std::string("cannot read ") +
                             kDatasetFileNames[i]);
    }
  }
  if (in.profiles == nullptr) return ParseDataset(texts, nullptr, lines, options);
  std::string profiles;
  if (!ReadAll(in.profiles, &profiles)) {
    return Status::IoError(std::string("cannot read ") + kProfilesFileName);
  }
  return ParseDataset(texts, &profiles, lines, options);
}

}  // namespace rollwear
