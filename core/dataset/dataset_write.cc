// Writing a dataset folder (WriteDataset) and the ISO 8601 timestamp codec
// of dataset_io.h. Reading lives in dataset_io.cc.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string_view>
#include <system_error>

#include "core/base/csv.h"
#include "core/dataset/dataset_columns.h"
#include "core/dataset/dataset_io.h"

namespace rollwear {
namespace {

// Formats the rows of one file: header, then `rows` lines produced by
// `row(i, &out)`, each followed by the extra columns.
template <typename RowFn>
std::string FormatFile(ColumnList columns, const ExtraColumns& extra,
                       size_t rows, RowFn row) {
  std::string out;
  out.reserve(64 + rows * 16 * (columns.size() + 2));
  bool first = true;
  auto name = [&](std::string_view n) {
    if (!first) out += ',';
    first = false;
    csv::AppendField(&out, n);
  };
  for (const char* c : columns) name(c);
  for (const std::string& n : extra.numeric_names) name(n);
  for (const std::string& n : extra.factor_names) name(n);
  out += '\n';
  for (size_t i = 0; i < rows; ++i) {
    row(i, &out);
    for (const std::vector<double>& v : extra.numeric) {
      out += ',';
      csv::AppendDouble(&out, v[i]);
    }
    for (size_t f = 0; f < extra.factor.size(); ++f) {
      out += ',';
      csv::AppendField(&out, extra.factor_levels[f][extra.factor[f][i]]);
    }
    out += '\n';
  }
  return out;
}

Status CheckExtra(const ExtraColumns& e, size_t rows, const char* file) {
  const std::string where = std::string("WriteDataset: ") + file + ": ";
  if (e.numeric_names.size() != e.numeric.size() ||
      e.factor_names.size() != e.factor.size() ||
      e.factor.size() != e.factor_levels.size()) {
    return Status::InvalidArgument(where +
                                   "extra column names and values "
                                   "do not match");
  }
  for (const std::vector<double>& v : e.numeric) {
    if (v.size() != rows) {
      return Status::InvalidArgument(where + "numeric extra column length " +
                                     std::to_string(v.size()) + " != rows " +
                                     std::to_string(rows));
    }
  }
  for (size_t f = 0; f < e.factor.size(); ++f) {
    if (e.factor[f].size() != rows) {
      return Status::InvalidArgument(where + "factor extra column length " +
                                     std::to_string(e.factor[f].size()) +
                                     " != rows " + std::to_string(rows));
    }
    for (int level : e.factor[f]) {
      if (level < 0 || level >= static_cast<int>(e.factor_levels[f].size())) {
        return Status::InvalidArgument(where + "factor level out of range");
      }
    }
  }
  return Status::Ok();
}

bool ValidRef(int index, size_t size) {
  return index >= 0 && static_cast<size_t>(index) < size;
}
bool ValidStand(int stand) { return stand >= kMinStand && stand <= kMaxStand; }

// Checks every index the writer dereferences.
Status CheckRefs(const Dataset& d) {
  const size_t nc = d.campaigns.size();
  for (size_t i = 0; i < d.mounts.size(); ++i) {
    const Mount& m = d.mounts[i];
    if (!ValidRef(m.campaign, nc) || !ValidStand(m.stand) ||
        !ValidRef(m.roll_type, d.roll_types.size())) {
      return Status::InvalidArgument("WriteDataset: mount " +
                                     std::to_string(i) +
                                     " has an invalid campaign, stand or "
                                     "roll_type");
    }
  }
  for (size_t i = 0; i < d.passes.size(); ++i) {
    const Pass& p = d.passes[i];
    if (!ValidRef(p.campaign, nc) || !ValidStand(p.stand) ||
        !ValidRef(p.coil, d.coil_ids.size()) ||
        !ValidRef(p.grade, d.grades.size())) {
      return Status::InvalidArgument("WriteDataset: pass " + std::to_string(i) +
                                     " has an invalid campaign, stand, coil "
                                     "or grade");
    }
  }
  for (size_t i = 0; i < d.measurements.size(); ++i) {
    const Measurement& m = d.measurements[i];
    if (!ValidRef(m.campaign, nc) || !ValidStand(m.stand)) {
      return Status::InvalidArgument("WriteDataset: measurement " +
                                     std::to_string(i) +
                                     " has an invalid campaign or stand");
    }
  }
  for (size_t i = 0; i < d.profile_points.size(); ++i) {
    const ProfilePoint& p = d.profile_points[i];
    if (!ValidRef(p.campaign, nc) || !ValidStand(p.stand)) {
      return Status::InvalidArgument("WriteDataset: profile point " +
                                     std::to_string(i) +
                                     " has an invalid campaign or stand");
    }
  }
  ROLLWEAR_RETURN_IF_ERROR(CheckExtra(d.campaign_extra, nc, "campaigns.csv"));
  ROLLWEAR_RETURN_IF_ERROR(
      CheckExtra(d.mount_extra, d.mounts.size(), "mounts.csv"));
  ROLLWEAR_RETURN_IF_ERROR(
      CheckExtra(d.pass_extra, d.passes.size(), "coils.csv"));
  return CheckExtra(d.measurement_extra, d.measurements.size(),
                    "measurements.csv");
}

// Writes `text` to `path` through a temporary file and a rename, so a crash
// never leaves a half-written file under the final name.
Status WriteFileAtomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  std::FILE* fp = std::fopen(tmp.c_str(), "wb");
  if (fp == nullptr) {
    return Status::IoError("cannot create " + tmp + ": " +
                           std::strerror(errno));
  }
  const bool wrote =
      std::fwrite(text.data(), 1, text.size(), fp) == text.size();
  const int write_errno = errno;
  const bool closed = std::fclose(fp) == 0;
  if (!wrote || !closed) {
    std::remove(tmp.c_str());
    const int err = wrote ? errno : write_errno;
    std::string m = "cannot write " + path + ": " + std::strerror(err);
    return err == ENOSPC ? Status::Unavailable(std::move(m))
                         : Status::IoError(std::move(m));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    std::remove(tmp.c_str());
    return Status::IoError("cannot rename " + tmp + ": " + std::strerror(err));
  }
  return Status::Ok();
}

void AppendInt(std::string* out, int64_t v) { *out += std::to_string(v); }

// profiles.csv when the dataset has profile points; otherwise no such file
// (a stale one from an earlier write of the same folder is removed).
Status WriteProfiles(const Dataset& d, const std::string& dir) {
  std::error_code ec;
  const std::string profiles_path = dir + "/" + kProfilesFileName;
  if (d.profile_points.empty()) {
    std::filesystem::remove(profiles_path, ec);
    return Status::Ok();
  }
  const ExtraColumns no_extra;
  const std::string profiles = FormatFile(
      kProfileColumns, no_extra, d.profile_points.size(),
      [&](size_t i, std::string* out) {
        const ProfilePoint& p = d.profile_points[i];
        csv::AppendField(out, d.campaigns[p.campaign].id);
        *out += ",F";
        AppendInt(out, p.stand);
        *out += ',';
        *out += PositionName(p.position);
        *out += ',';
        csv::AppendField(out, p.roll_id);
        *out += ',' + FormatTimestamp(p.measured_at) + ',';
        csv::AppendDouble(out, p.x_mm);
        *out += ',';
        csv::AppendDouble(out, p.wear_um);
      });
  return WriteFileAtomically(profiles_path, profiles);
}

}  // namespace

Status WriteDataset(const Dataset& data, const std::string& dir) {
  ROLLWEAR_RETURN_IF_ERROR(CheckRefs(data));
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    return Status::IoError("cannot create directory " + dir + ": " +
                           ec.message());
  }
  const Dataset& d = data;
  std::string texts[kNumDatasetFiles];
  texts[kCampaignsFile] =
      FormatFile(kCampaignColumns, d.campaign_extra, d.campaigns.size(),
                 [&](size_t i, std::string* out) {
                   const Campaign& c = d.campaigns[i];
                   csv::AppendField(out, c.id);
                   *out += ',' + FormatTimestamp(c.started_at);
                   *out += ',' + FormatTimestamp(c.ended_at);
                 });
  texts[kMountsFile] =
      FormatFile(kMountColumns, d.mount_extra, d.mounts.size(),
                 [&](size_t i, std::string* out) {
                   const Mount& m = d.mounts[i];
                   csv::AppendField(out, d.campaigns[m.campaign].id);
                   *out += ",F";
                   AppendInt(out, m.stand);
                   *out += ',';
                   *out += PositionName(m.position);
                   *out += ',';
                   csv::AppendField(out, m.roll_id);
                   *out += ',';
                   csv::AppendField(out, d.roll_types[m.roll_type]);
                   *out += ',';
                   csv::AppendDouble(out, m.diameter_mm);
                   *out += ',';
                   csv::AppendDouble(out, m.hardness_hb);
                 });
  texts[kCoilsFile] =
      FormatFile(kCoilColumns, d.pass_extra, d.passes.size(),
                 [&](size_t i, std::string* out) {
                   const Pass& p = d.passes[i];
                   csv::AppendField(out, d.campaigns[p.campaign].id);
                   *out += ',';
                   csv::AppendField(out, d.coil_ids[p.coil]);
                   *out += ',';
                   AppendInt(out, p.seq);
                   *out += ',' + FormatTimestamp(p.rolled_at) + ',';
                   csv::AppendField(out, d.grades[p.grade]);
                   *out += ",F";
                   AppendInt(out, p.stand);
                   for (double v : {p.force_kn, p.width_mm, p.length_m,
                                    p.entry_thickness_mm, p.exit_thickness_mm,
                                    p.temperature_c, p.speed_mps}) {
                     *out += ',';
                     csv::AppendDouble(out, v);
                   }
                   *out += p.lubrication ? ",1," : ",0,";
                   csv::AppendDouble(out, p.shift_mm);
                 });
  texts[kMeasurementsFile] =
      FormatFile(kMeasurementColumns, d.measurement_extra,
                 d.measurements.size(), [&](size_t i, std::string* out) {
                   const Measurement& m = d.measurements[i];
                   csv::AppendField(out, d.campaigns[m.campaign].id);
                   *out += ",F";
                   AppendInt(out, m.stand);
                   *out += ',';
                   *out += PositionName(m.position);
                   *out += ',';
                   csv::AppendField(out, m.roll_id);
                   *out += ',' + FormatTimestamp(m.measured_at) + ',';
                   csv::AppendDouble(out, m.wear_center_um);
                 });
  for (int i = 0; i < kNumDatasetFiles; ++i) {
    ROLLWEAR_RETURN_IF_ERROR(
        WriteFileAtomically(dir + "/" + kDatasetFileNames[i], texts[i]));
  }
  return WriteProfiles(d, dir);
}

}  // namespace rollwear
