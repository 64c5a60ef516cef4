#include "core/dataset/dataset_checks.h"

#include <cmath>
#include <string>
#include <utility>

namespace rollwear {

using csv::NumberResult;

std::string Quote(std::string_view text) {
  constexpr size_t kMax = 40;
  std::string out = "'";
  if (text.size() > kMax) {
    out.append(text.substr(0, kMax));
    out += "...";
  } else {
    out.append(text);
  }
  out += '\'';
  return out;
}

Status FileView::Bind() {
  const std::vector<std::string>& header = table_.header();
  if (header.empty()) {
    std::string want;
    for (const char* name : columns_) {
      want += want.empty() ? "" : ",";
      want += name;
    }
    return Fail(1, 1, "file",
                "the file is empty; want a header row (" + want +
                    ") and one row per record");
  }
  for (size_t c = 0; c < header.size(); ++c) {
    for (size_t e = 0; e < c; ++e) {
      if (header[e] == header[c]) {
        return Fail(table_.header_line(), c + 1, header[c],
                    "duplicate column name (also column " +
                        std::to_string(e + 1) + ")");
      }
    }
  }
  cols_.assign(columns_.size(), -1);
  for (size_t k = 0; k < columns_.size(); ++k) {
    cols_[k] = table_.FindColumn(columns_[k]);
    if (cols_[k] < 0) {
      const std::string hint = csv::ForeignLayoutHint(table_);
      if (!hint.empty()) return Fail(table_.header_line(), 1, "file", hint);
      return Fail(1, 0, columns_[k],
                  std::string("missing required column '") + columns_[k] + "'");
    }
  }
  for (size_t c = 0; c < header.size(); ++c) {
    bool known = false;
    for (int col : cols_) known = known || col == static_cast<int>(c);
    if (!known) extra_.push_back(static_cast<int>(c));
  }
  return Status::Ok();
}

Status FileView::CheckFieldCount(size_t r) const {
  const size_t have = table_.num_fields(r);
  const size_t want = table_.header().size();
  if (have == want) return Status::Ok();
  const size_t column = have < want ? have + 1 : want + 1;
  return Fail(line(r), column,
              column <= want ? table_.header()[column - 1] : "(extra field)",
              "wrong field count: " + std::to_string(have) +
                  " fields, header has " + std::to_string(want));
}

Status FileView::Text(size_t r, int k, std::string_view* out) const {
  *out = Raw(r, k);
  if (csv::Trim(*out).empty()) return Error(r, k, "required field is empty");
  return Status::Ok();
}

Status FileView::Number(size_t r, int k, double* out) const {
  const std::string_view raw = Raw(r, k);
  switch (csv::ParseDouble(raw, out)) {
    case NumberResult::kOk:
      break;
    case NumberResult::kOutOfRange:
      return Error(r, k, "number out of range " + Quote(raw));
    case NumberResult::kInvalid:
      if (csv::Trim(raw).empty()) {
        return Error(r, k, "required field is empty");
      }
      if (csv::IsDecimalCommaNumber(raw)) {
        return Error(r, k,
                     "unparsable number " + Quote(raw) +
                         ": decimal comma; write numbers with '.' (export "
                         "as CSV with ',' and '.')");
      }
      return Error(r, k, "unparsable number " + Quote(raw));
  }
  if (!std::isfinite(*out)) {
    return Error(r, k, "must be a finite number, got " + Quote(raw));
  }
  return Status::Ok();
}

Status FileView::Check(size_t r, const RuleViolations& broken) const {
  if (broken.empty()) return Status::Ok();
  const RuleViolation& v = broken.front();
  for (size_t k = 0; k < columns_.size(); ++k) {
    if (v.field != columns_[k]) continue;
    const int column = static_cast<int>(k);
    return Error(
        r, column,
        v.cites_value ? v.rule + ", got " + Quote(Raw(r, column)) : v.rule);
  }
  return Fail(line(r), 0, v.field, RuleMessage(v));  // not a column
}

Status FileView::Integer(size_t r, int k, int64_t* out) const {
  const std::string_view raw = Raw(r, k);
  switch (csv::ParseInt64(raw, out)) {
    case NumberResult::kOk:
      return Status::Ok();
    case NumberResult::kOutOfRange:
      return Error(r, k, "integer out of range " + Quote(raw));
    case NumberResult::kInvalid:
      break;
  }
  if (csv::Trim(raw).empty()) return Error(r, k, "required field is empty");
  return Error(r, k, "unparsable integer " + Quote(raw));
}

Status FileView::Time(size_t r, int k, UnixSeconds* out) const {
  const std::string_view raw = csv::Trim(Raw(r, k));
  if (raw.empty()) return Error(r, k, "required field is empty");
  const int* local = local_utc_offset_s_ ? &*local_utc_offset_s_ : nullptr;
  if (!ParseTimestampView(raw, out, local)) {
    return Error(r, k,
                 "unparsable timestamp " + Quote(raw) +
                     " (want ISO 8601 with offset, e.g. "
                     "2026-03-01T06:12:00Z; local times without an offset "
                     "need the setting ROLLWEAR_UTC_OFFSET=+HH:MM)");
  }
  return Status::Ok();
}

Status FileView::Stand(size_t r, int k, int* out) const {
  const std::string_view raw = csv::Trim(Raw(r, k));
  if (raw.empty()) return Error(r, k, "required field is empty");
  *out = ParseStand(std::string(raw));
  if (*out == 0) {
    return Error(r, k, "unknown stand " + Quote(raw) + " (want F1..F7)");
  }
  return Status::Ok();
}

Status FileView::PositionOf(size_t r, int k, Position* out) const {
  const std::string_view raw = csv::Trim(Raw(r, k));
  if (raw.empty()) return Error(r, k, "required field is empty");
  if (!ParsePosition(std::string(raw), out)) {
    return Error(r, k,
                 "unknown position " + Quote(raw) + " (want top or bottom)");
  }
  return Status::Ok();
}

Status FileView::Campaign(size_t r, int k, LabelIndex* campaigns,
                          int* out) const {
  std::string_view id;
  ROLLWEAR_RETURN_IF_ERROR(Text(r, k, &id));
  *out = campaigns->Find(id);
  if (*out < 0) {
    return Error(r, k,
                 "unknown campaign " + Quote(id) + " (not in campaigns.csv)");
  }
  return Status::Ok();
}

void FileView::CollectExtras(ExtraColumns* out) const {
  const size_t n = rows();
  for (int c : extra_) {
    const std::string& name = table_.header()[c];
    std::vector<double> values(n);
    bool numeric = true;
    for (size_t r = 0; r < n && numeric; ++r) {
      const std::string_view raw = table_.field(r, c);
      if (csv::Trim(raw).empty()) {
        values[r] = std::nan("");
      } else {
        numeric = csv::ParseDouble(raw, &values[r]) == NumberResult::kOk &&
                  std::isfinite(values[r]);
      }
    }
    if (numeric) {
      out->numeric_names.push_back(name);
      out->numeric.push_back(std::move(values));
      continue;
    }
    LabelIndex index;
    std::vector<std::string> levels;
    std::vector<int> codes(n);
    for (size_t r = 0; r < n; ++r) {
      const std::string_view raw = table_.field(r, c);
      bool added = false;
      codes[r] = index.Insert(raw, static_cast<int>(levels.size()), &added);
      if (added) levels.emplace_back(raw);
    }
    out->factor_names.push_back(name);
    out->factor.push_back(std::move(codes));
    out->factor_levels.push_back(std::move(levels));
  }
}

Status FileView::Fail(int line, size_t column, std::string_view field,
                      std::string_view rule) const {
  std::string m = file_;
  m += ':' + std::to_string(line) + ':' + std::to_string(column) + ' ';
  m.append(field);
  m += ": ";
  m.append(rule);
  return Status::InvalidArgument(std::move(m));
}

}  // namespace rollwear
