// Internal CSV helpers of core (used by the dataset reader/writer; not a
// public API). csv::Table parses a whole file held in memory following
// RFC 4180: quoted fields, doubled quotes, commas and line breaks inside
// quotes, LF or CRLF line ends, an optional UTF-8 byte-order mark. Quoted
// fields are unescaped in place, so a parsed table is one buffer plus an
// (offset, size) pair per field; every record remembers the physical line
// (1-based, counting line breaks inside quoted fields) on which it starts.
// Completely empty lines are skipped (their lines still count). A file of
// 1 MB or more without a quote is parsed in two halves on two threads.
//
// The number parsers use std::from_chars and accept the whole field only.
//
// Thread-safety: a Table is immutable after Parse and may be read from any
// thread; the free functions are pure.
#ifndef ROLLWEAR_CORE_BASE_CSV_H_
#define ROLLWEAR_CORE_BASE_CSV_H_

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/status.h"

namespace rollwear::csv {

class Table {
 public:
  // Parses `text`; `file` labels errors ("coils.csv:12:3 shift_mm:
  // unterminated quoted field"). Fails only on malformed quoting or a file
  // of 4 GiB or more.
  static StatusOr<Table> Parse(std::string text, std::string_view file);

  // Header names (surrounding spaces and tabs removed). Empty for an empty
  // file.
  const std::vector<std::string>& header() const { return header_; }
  // Physical line of the header row (1 unless blank lines precede it).
  int header_line() const { return header_line_; }
  // 0-based index of the header column called `name`, or -1.
  int FindColumn(std::string_view name) const;
  // Whether Parse read the records in two halves on two threads (a
  // quote-free file of 1 MB or more; for the tests).
  bool read_in_halves() const { return read_in_halves_; }

  // Data records (the header is not one of them).
  size_t num_records() const { return records_.size(); }
  size_t num_fields(size_t record) const { return records_[record].num_fields; }
  int line(size_t record) const {
    return static_cast<int>(records_[record].line);
  }
  // Unescaped field text; valid while the Table lives (and is not moved
  // from).
  std::string_view field(size_t record, size_t column) const {
    const Span& s = fields_[records_[record].first_field + column];
    return std::string_view(buffer_.data() + s.begin, s.size);
  }

 private:
  struct Span {
    uint32_t begin;
    uint32_t size;
  };
  struct Record {
    uint32_t first_field;
    uint32_t num_fields;
    uint32_t line;
  };

  // Parse stages, on the buffer s[0, n). ReadRecord appends the fields of
  // the record that starts at s[*i] (on physical line `record_line`),
  // leaves *i after its line end and counts lines in *line; fails on
  // malformed quoting (`header` names the field). ReadRecords reads the
  // records from `begin` (a record's start) to `end` (a record's start or
  // n), skipping blank lines. TakeHeader makes the fields from
  // `first_field` on the header.
  static Status ReadRecord(char* s, size_t n, size_t* i, uint32_t* line,
                           std::string_view file, uint32_t record_line,
                           const std::vector<std::string>& header,
                           std::vector<Span>* fields);
  static Status ReadRecords(char* s, size_t n, size_t begin, size_t end,
                            uint32_t* line, std::string_view file,
                            const std::vector<std::string>& header,
                            std::vector<Span>* fields,
                            std::vector<Record>* records);
  void TakeHeader(size_t first_field, uint32_t record_line);

  std::string buffer_;
  std::vector<Span> fields_;
  std::vector<Record> records_;
  std::vector<std::string> header_;
  int header_line_ = 1;
  bool read_in_halves_ = false;
};

// Removes leading and trailing spaces and tabs.
inline std::string_view Trim(std::string_view text) {
  size_t b = 0;
  size_t e = text.size();
  while (b < e && (text[b] == ' ' || text[b] == '\t')) ++b;
  while (e > b && (text[e - 1] == ' ' || text[e - 1] == '\t')) --e;
  return text.substr(b, e - b);
}

// Advice when `t` does not look like comma-separated text: a header that
// is one field holding ';' (a spreadsheet export in a European locale; when
// data rows split at commas, those are decimal commas) or tabs. Returns
// e.g. "looks like a spreadsheet export with ';' and decimal commas: export
// as CSV with ',' and '.'", or "" when nothing is recognised.
std::string ForeignLayoutHint(const Table& t);
// True when `text` (after Trim) is a number written with a decimal comma
// ("12,5", "-0,25").
bool IsDecimalCommaNumber(std::string_view text);

enum class NumberResult { kOk, kInvalid, kOutOfRange };
// Parses the whole of `text` (after Trim) as a decimal floating-point number;
// one leading '+' is accepted. "nan"/"inf" parse (kOk, non-finite value): the
// caller decides whether that is acceptable.
NumberResult ParseDouble(std::string_view text, double* out);
// Parses the whole of `text` (after Trim) as a decimal integer.
NumberResult ParseInt64(std::string_view text, int64_t* out);

// Appends `text` as one CSV field, quoted when it holds a comma, quote, CR
// or LF, or starts or ends with a space or tab.
void AppendField(std::string* out, std::string_view text);
// Appends the shortest decimal form that reads back to exactly `value`
// (std::to_chars); NaN becomes an empty field.
void AppendDouble(std::string* out, double value);

}  // namespace rollwear::csv

#endif  // ROLLWEAR_CORE_BASE_CSV_H_
