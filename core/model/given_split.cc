#include "core/model/given_split.h"

#include <map>
#include <unordered_map>
#include <utility>

#include "core/base/csv.h"

namespace rollwear {
namespace {

constexpr const char* kCopySuffix = "~validation";

// Appends row `row` of `from` to `to` (same columns).
void AppendExtraRow(const ExtraColumns& from, size_t row, ExtraColumns* to) {
  for (size_t k = 0; k < from.numeric.size(); ++k) {
    to->numeric[k].push_back(from.numeric[k][row]);
  }
  for (size_t k = 0; k < from.factor.size(); ++k) {
    to->factor[k].push_back(from.factor[k][row]);
  }
}

// The columns of `from` without rows.
ExtraColumns EmptyLike(const ExtraColumns& from) {
  ExtraColumns e;
  e.numeric_names = from.numeric_names;
  e.numeric.assign(from.numeric.size(), {});
  e.factor_names = from.factor_names;
  e.factor.assign(from.factor.size(), {});
  e.factor_levels = from.factor_levels;
  return e;
}

Status LineError(std::string_view file, int line, const std::string& what) {
  return Status::InvalidArgument(std::string(file) + ":" +
                                 std::to_string(line) + ": " + what);
}

// Builds the split dataset campaign by campaign (see the header).
class Splitter {
 public:
  Splitter(const Dataset& in,
           const std::map<std::pair<std::string, int>, bool>& sets)
      : in_(in), sets_(sets), index_(in) {
    Dataset& d = out_.data;
    d.grades = in.grades;
    d.roll_types = in.roll_types;
    d.campaign_extra = EmptyLike(in.campaign_extra);
    d.mount_extra = EmptyLike(in.mount_extra);
    d.pass_extra = EmptyLike(in.pass_extra);
    d.measurement_extra = EmptyLike(in.measurement_extra);
    mounts_of_.resize(in.campaigns.size());
    for (size_t m = 0; m < in.mounts.size(); ++m) {
      mounts_of_[in.mounts[m].campaign].push_back(static_cast<int>(m));
    }
  }

  SplitDataset Run() {
    for (size_t c = 0; c < in_.campaigns.size(); ++c)
      SplitCampaign(static_cast<int>(c));
    return std::move(out_);
  }

 private:
  // -1: not listed, 0: validation, 1: train.
  int SetOf(int campaign, int slot) const {
    auto it = sets_.find({in_.campaigns[campaign].id, slot});
    return it == sets_.end() ? -1 : (it->second ? 1 : 0);
  }

  void SplitCampaign(int c) {
    bool has[2] = {false, false};
    for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
      const int me = index_.MeasurementOf(c, slot);
      if (me < 0) continue;
      const int set = SetOf(c, slot);
      if (set < 0) {
        ++out_.readings_not_listed;
      } else {
        has[set] = true;
      }
    }
    if (!(has[0] && has[1])) {
      // One campaign: every roll, the readings of its one set.
      Emit(
          c, /*copy=*/false, [](int) { return true; },
          has[1] ? 1 : (has[0] ? 0 : -1));
      return;
    }
    ++out_.campaigns_split;
    // The validation rolls go to the copy, everything else stays.
    auto in_copy = [this, c](int slot) {
      return index_.MeasurementOf(c, slot) >= 0 && SetOf(c, slot) == 0;
    };
    Emit(
        c, false, [&](int slot) { return !in_copy(slot); }, 1);
    Emit(c, true, in_copy, 0);
  }

  // Emits campaign c (or its copy) with the mounts whose slot `keep` holds,
  // the passes of their stands and the measurements of set `set`.
  template <typename Keep>
  void Emit(int c, bool copy, Keep keep, int set) {
    Dataset& d = out_.data;
    const int nc = static_cast<int>(d.campaigns.size());
    Campaign campaign = in_.campaigns[c];
    if (copy) campaign.id += kCopySuffix;
    d.campaigns.push_back(campaign);
    out_.original_id.push_back(in_.campaigns[c].id);
    AppendExtraRow(in_.campaign_extra, c, &d.campaign_extra);
    bool stand_kept[kMaxStand + 1] = {};
    for (int m : mounts_of_[c]) {
      const Mount& mount = in_.mounts[m];
      const int slot = RollPositionSlot(mount.stand, mount.position);
      if (!keep(slot)) continue;
      Mount out = mount;
      out.campaign = nc;
      d.mounts.push_back(std::move(out));
      AppendExtraRow(in_.mount_extra, m, &d.mount_extra);
      stand_kept[mount.stand] = true;
    }
    for (int stand = kMinStand; stand <= kMaxStand; ++stand) {
      if (!stand_kept[stand]) continue;
      for (int pi : index_.PassesOf(c, stand)) {
        Pass p = in_.passes[pi];
        p.campaign = nc;
        std::string id = in_.coil_ids[p.coil];
        if (copy) id += kCopySuffix;
        auto [it, added] =
            coil_index_.emplace(id, static_cast<int>(d.coil_ids.size()));
        if (added) d.coil_ids.push_back(id);
        p.coil = it->second;
        d.passes.push_back(p);
        AppendExtraRow(in_.pass_extra, pi, &d.pass_extra);
      }
    }
    if (set < 0) return;
    bool measured[kNumRollPositionSlots] = {};
    for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
      const int me = index_.MeasurementOf(c, slot);
      if (me < 0 || !keep(slot) || SetOf(c, slot) != set) continue;
      Measurement m = in_.measurements[me];
      m.campaign = nc;
      d.measurements.push_back(std::move(m));
      AppendExtraRow(in_.measurement_extra, me, &d.measurement_extra);
      measured[slot] = true;
      ++(set == 1 ? out_.readings_train : out_.readings_validation);
    }
    for (const ProfilePoint& p : in_.profile_points) {
      if (p.campaign != c || !measured[RollPositionSlot(p.stand, p.position)])
        continue;
      ProfilePoint q = p;
      q.campaign = nc;
      d.profile_points.push_back(q);
    }
    bool any = false;
    for (bool m : measured) any = any || m;
    if (any)
      (set == 1 ? out_.split.train : out_.split.validation).push_back(nc);
  }

  const Dataset& in_;
  const std::map<std::pair<std::string, int>, bool>& sets_;
  const DatasetIndex index_;
  std::vector<std::vector<int>> mounts_of_;
  std::unordered_map<std::string, int> coil_index_;
  SplitDataset out_;
};

}  // namespace

StatusOr<std::vector<SplitRow>> ParseSplitCsv(std::string text,
                                              std::string_view file) {
  ROLLWEAR_ASSIGN_OR_RETURN(csv::Table table,
                            csv::Table::Parse(std::move(text), file));
  const char* names[] = {"campaign_id", "stand", "position", "set"};
  int col[4];
  for (int k = 0; k < 4; ++k) {
    col[k] = table.FindColumn(names[k]);
    if (col[k] < 0) {
      return LineError(file, table.header_line(),
                       std::string("missing column ") + names[k]);
    }
  }
  std::vector<SplitRow> rows;
  std::map<std::pair<std::string, int>, int> seen;
  for (size_t r = 0; r < table.num_records(); ++r) {
    const int line = table.line(r);
    if (table.num_fields(r) != table.header().size()) {
      return LineError(file, line,
                       "expected " + std::to_string(table.header().size()) +
                           " fields, got " +
                           std::to_string(table.num_fields(r)));
    }
    SplitRow row;
    row.line = line;
    row.campaign_id = std::string(csv::Trim(table.field(r, col[0])));
    if (row.campaign_id.empty())
      return LineError(file, line, "campaign_id: must not be empty");
    const std::string stand(csv::Trim(table.field(r, col[1])));
    row.stand = ParseStand(stand);
    if (row.stand == 0)
      return LineError(file, line,
                       "stand: must be F1..F7, got '" + stand + "'");
    const std::string position(csv::Trim(table.field(r, col[2])));
    if (!ParsePosition(position, &row.position)) {
      return LineError(
          file, line,
          "position: must be top or bottom, got '" + position + "'");
    }
    const std::string set(csv::Trim(table.field(r, col[3])));
    if (set != "train" && set != "validation") {
      return LineError(file, line,
                       "set: must be train or validation, got '" + set + "'");
    }
    row.train = set == "train";
    auto [it, added] =
        seen.emplace(std::make_pair(row.campaign_id,
                                    RollPositionSlot(row.stand, row.position)),
                     line);
    if (!added) {
      return LineError(
          file, line,
          "duplicate reading (campaign_id, stand, position), first on line " +
              std::to_string(it->second));
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

StatusOr<SplitDataset> ApplySplit(const Dataset& data,
                                  const std::vector<SplitRow>& rows) {
  std::map<std::pair<std::string, int>, bool> sets;
  for (const SplitRow& r : rows) {
    sets[{r.campaign_id, RollPositionSlot(r.stand, r.position)}] = r.train;
  }
  const DatasetIndex index(data);
  std::unordered_map<std::string, int> campaign_of;
  for (size_t c = 0; c < data.campaigns.size(); ++c) {
    campaign_of.emplace(data.campaigns[c].id, static_cast<int>(c));
  }
  int not_measured = 0;
  for (const SplitRow& r : rows) {
    auto it = campaign_of.find(r.campaign_id);
    if (it == campaign_of.end() ||
        index.MeasurementOf(it->second, RollPositionSlot(r.stand, r.position)) <
            0) {
      ++not_measured;
    }
  }
  SplitDataset out = Splitter(data, sets).Run();
  out.rows_not_measured = not_measured;
  if (out.split.train.empty() || out.split.validation.empty()) {
    return Status::InvalidArgument(
        "the split leaves no " +
        std::string(out.split.train.empty() ? "training" : "validation") +
        " reading of this dataset (" + std::to_string(not_measured) +
        " of its " + std::to_string(rows.size()) +
        " rows name readings the dataset does not measure)");
  }
  return out;
}

std::string DescribeSplit(const SplitDataset& s, const std::string& file) {
  return "split " + file + ": " + std::to_string(s.readings_train) +
         " training and " + std::to_string(s.readings_validation) +
         " validation readings (" + std::to_string(s.campaigns_split) +
         " campaigns have both; " + std::to_string(s.readings_not_listed) +
         " measured readings not listed, not used; " +
         std::to_string(s.rows_not_measured) + " listed readings not measured)";
}

}  // namespace rollwear
