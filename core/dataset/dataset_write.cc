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

// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's
// days_from_civil, http://howardhinnant.github.io/date_algorithms.html).
int64_t DaysFromCivil(int64_t y, unsigned m, unsigned d) {
  y -= m <= 2;
  const int64_t era = (y >= 0 ? y : y - 399) / 400;
  const auto yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m > 2 ? m - 3 : m + 9) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<int64_t>(doe) - 719468;
}

// Inverse of DaysFromCivil (civil_from_days).
void CivilFromDays(int64_t z, int64_t* y, unsigned* m, unsigned* d) {
  z += 719468;
  const int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const auto doe = static_cast<unsigned>(z - era * 146097);
  const unsigned yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const unsigned doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const unsigned mp = (5 * doy + 2) / 153;
  *d = doy - (153 * mp + 2) / 5 + 1;
  *m = mp < 10 ? mp + 3 : mp - 9;
  *y = static_cast<int64_t>(yoe) + era * 400 + (*m <= 2);
}

bool IsLeap(int64_t y) { return y % 4 == 0 && (y % 100 != 0 || y % 400 == 0); }

unsigned DaysInMonth(int64_t y, unsigned m) {
  static constexpr unsigned kDays[] = {31, 28, 31, 30, 31, 30,
                                       31, 31, 30, 31, 30, 31};
  return m == 2 && IsLeap(y) ? 29 : kDays[m - 1];
}

// Reads exactly `n` digits at text[*pos].
bool Digits(std::string_view text, size_t* pos, int n, int* out) {
  if (*pos + n > text.size()) return false;
  int v = 0;
  for (int i = 0; i < n; ++i) {
    const char c = text[*pos + i];
    if (c < '0' || c > '9') return false;
    v = v * 10 + (c - '0');
  }
  *pos += n;
  *out = v;
  return true;
}

bool Expect(std::string_view text, size_t* pos, char c) {
  if (*pos >= text.size() || text[*pos] != c) return false;
  ++*pos;
  return true;
}

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

}  // namespace

bool ParseTimestampView(std::string_view text, UnixSeconds* out) {
  size_t pos = 0;
  int year, month, day, hour, minute, second;
  if (!Digits(text, &pos, 4, &year) || !Expect(text, &pos, '-') ||
      !Digits(text, &pos, 2, &month) || !Expect(text, &pos, '-') ||
      !Digits(text, &pos, 2, &day) || !Expect(text, &pos, 'T') ||
      !Digits(text, &pos, 2, &hour) || !Expect(text, &pos, ':') ||
      !Digits(text, &pos, 2, &minute) || !Expect(text, &pos, ':') ||
      !Digits(text, &pos, 2, &second)) {
    return false;
  }
  if (month < 1 || month > 12 || day < 1 ||
      day > static_cast<int>(DaysInMonth(year, month)) || hour > 23 ||
      minute > 59 || second > 59) {
    return false;
  }
  // Fractional seconds: at least one digit, truncated.
  if (pos < text.size() && text[pos] == '.') {
    ++pos;
    const size_t start = pos;
    while (pos < text.size() && text[pos] >= '0' && text[pos] <= '9') ++pos;
    if (pos == start) return false;
  }
  if (pos >= text.size()) return false;  // the offset is mandatory
  int offset_s = 0;
  const char sign = text[pos++];
  if (sign == 'Z') {
    if (pos != text.size()) return false;
  } else if (sign == '+' || sign == '-') {
    int oh, om;
    if (!Digits(text, &pos, 2, &oh)) return false;
    if (pos < text.size() && text[pos] == ':') ++pos;  // +HH:MM or +HHMM
    if (!Digits(text, &pos, 2, &om) || pos != text.size()) return false;
    if (oh > 23 || om > 59) return false;
    offset_s = (oh * 3600 + om * 60) * (sign == '-' ? -1 : 1);
  } else {
    return false;
  }
  const int64_t days = DaysFromCivil(year, month, day);
  *out = days * 86400 + int64_t{hour} * 3600 + int64_t{minute} * 60 + second -
         offset_s;
  return true;
}

bool ParseTimestamp(const std::string& text, UnixSeconds* out) {
  return ParseTimestampView(text, out);
}

std::string FormatTimestamp(UnixSeconds t) {
  int64_t days = t / 86400;
  int64_t secs = t % 86400;
  if (secs < 0) {
    secs += 86400;
    --days;
  }
  int64_t y;
  unsigned m, d;
  CivilFromDays(days, &y, &m, &d);
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%04lld-%02u-%02uT%02d:%02d:%02dZ",
                static_cast<long long>(y), m, d, static_cast<int>(secs / 3600),
                static_cast<int>(secs / 60 % 60), static_cast<int>(secs % 60));
  return buf;
}

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
  return Status::Ok();
}

}  // namespace rollwear
