// Internal to core's dataset reader (dataset_io.cc): typed, checked access
// to the fields of one parsed dataset file. FileView binds the format's
// columns by header name and every accessor reports a broken rule as
// InvalidArgument "<file>:<line>:<column> <field>: <rule>" (line = physical
// line of the record, column = 1-based field position). LabelIndex maps
// labels to indices with views into the parsed buffers.
//
// Thread-safety: a FileView only reads its csv::Table (which must outlive
// it), so several threads may read one; a LabelIndex is a mutable value,
// one thread at a time, except Lookup (const, no cache).
#ifndef ROLLWEAR_CORE_DATASET_DATASET_CHECKS_H_
#define ROLLWEAR_CORE_DATASET_DATASET_CHECKS_H_

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "core/base/csv.h"
#include "core/base/status.h"
#include "core/dataset/dataset.h"
#include "core/dataset/dataset_columns.h"
#include "core/dataset/input_rules.h"

namespace rollwear {

// Label -> index, holding views (the viewed text must outlive it), with a
// one-entry cache: rows of one campaign, coil or grade usually come
// together.
class LabelIndex {
 public:
  void reserve(size_t n) { map_.reserve(n); }

  // Index of `label`, or -1.
  int Find(std::string_view label) {
    if (last_ >= 0 && label == last_label_) return last_;
    auto it = map_.find(label);
    if (it == map_.end()) return -1;
    last_label_ = label;
    last_ = it->second;
    return last_;
  }

  // Index of `label`, or -1, without the cache: safe from several threads
  // at once while nothing inserts.
  int Lookup(std::string_view label) const {
    auto it = map_.find(label);
    return it == map_.end() ? -1 : it->second;
  }

  // Index of `label`; adds it as `next` when new (then *added is true).
  int Insert(std::string_view label, int next, bool* added) {
    *added = false;
    if (last_ >= 0 && label == last_label_) return last_;
    auto [it, fresh] = map_.emplace(label, next);
    *added = fresh;
    last_label_ = label;
    last_ = it->second;
    return last_;
  }

 private:
  std::unordered_map<std::string_view, int> map_;
  std::string_view last_label_;
  int last_ = -1;
};

// "'value'" for messages, shortened to 40 characters.
std::string Quote(std::string_view text);

// One parsed file of a dataset. Column k below is the index into the
// file's ColumnList (dataset_columns.h), not a field position.
class FileView {
 public:
  FileView(const csv::Table& table, const char* file, ColumnList columns)
      : table_(table), file_(file), columns_(columns) {}

  // Finds the format's columns (all required) and the extra ones; rejects a
  // header naming a column twice.
  Status Bind();

  // Set: Time() reads a timestamp without offset as local time at this
  // offset (seconds east of UTC); unset: it is an error.
  void set_local_utc_offset(std::optional<int> offset_s) {
    local_utc_offset_s_ = offset_s;
  }

  size_t rows() const { return table_.num_records(); }
  int line(size_t r) const { return table_.line(r); }

  // Record r has as many fields as the header.
  Status CheckFieldCount(size_t r) const;

  // Error at column k of record r.
  Status Error(size_t r, int k, std::string_view rule) const {
    return Fail(line(r), cols_[k] + 1, columns_[k], rule);
  }

  std::string_view Raw(size_t r, int k) const {
    return table_.field(r, cols_[k]);
  }

  // Non-blank text, returned verbatim.
  Status Text(size_t r, int k, std::string_view* out) const;
  // Finite number.
  Status Number(size_t r, int k, double* out) const;
  Status Integer(size_t r, int k, int64_t* out) const;
  Status Time(size_t r, int k, UnixSeconds* out) const;
  Status Stand(size_t r, int k, int* out) const;
  Status PositionOf(size_t r, int k, Position* out) const;
  // The first of `broken` (input_rules.h) as the error of record r, at the
  // column the violation names, citing the field's text as written; Ok
  // when `broken` is empty.
  Status Check(size_t r, const RuleViolations& broken) const;
  // A campaign_id present in `campaigns`.
  Status Campaign(size_t r, int k, LabelIndex* campaigns, int* out) const;

  // The extra columns: numeric when every non-empty value is a finite
  // number (empty -> NaN), otherwise a factor with levels in first-seen
  // order (the empty text is a level).
  void CollectExtras(ExtraColumns* out) const;

 private:
  Status Fail(int line, size_t column, std::string_view field,
              std::string_view rule) const;

  const csv::Table& table_;
  const char* file_;
  ColumnList columns_;
  std::optional<int> local_utc_offset_s_;
  std::vector<int> cols_;   // column k -> 0-based field index
  std::vector<int> extra_;  // field indices of unknown columns
};

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_DATASET_DATASET_CHECKS_H_
