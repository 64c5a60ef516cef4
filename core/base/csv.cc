#include "core/base/csv.h"

#include <array>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <system_error>
#include <thread>

namespace rollwear::csv {
namespace {

// Characters that end an unquoted field; NUL marks the end of the buffer
// (std::string keeps one after the last character).
constexpr std::array<bool, 256> kFieldEnd = [] {
  std::array<bool, 256> a{};
  a[static_cast<unsigned char>(',')] = true;
  a[static_cast<unsigned char>('\n')] = true;
  a[static_cast<unsigned char>('\r')] = true;
  a[0] = true;
  return a;
}();

// Exact powers of ten representable in a double.
constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                             1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                             1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

// Plain decimals ("-123.45") with at most 19 digits, whose digits as an
// integer m fit in 53 bits and with at most 22 decimals: m / 10^k is then
// one correctly rounded IEEE division of two exact doubles, so the result
// equals std::from_chars' (Clinger's fast path). Anything else -> false.
bool ParseSimpleDecimal(std::string_view t, double* out) {
  size_t i = 0;
  const bool negative = !t.empty() && t[0] == '-';
  if (negative) ++i;
  uint64_t mantissa = 0;
  int digits = 0;
  int decimals = 0;
  bool dot = false;
  for (; i < t.size(); ++i) {
    const char c = t[i];
    if (c >= '0' && c <= '9') {
      if (++digits > 19) return false;
      mantissa = mantissa * 10 + static_cast<uint64_t>(c - '0');
      decimals += dot;
    } else if (c == '.' && !dot) {
      dot = true;
    } else {
      return false;
    }
  }
  if (digits == 0 || mantissa > (uint64_t{1} << 53) || decimals > 22) {
    return false;
  }
  auto v = static_cast<double>(mantissa);
  if (decimals > 0) v /= kPow10[decimals];
  *out = negative ? -v : v;
  return true;
}

Status SyntaxError(std::string_view file, int line, size_t column,
                   const std::vector<std::string>& header,
                   std::string_view rule) {
  std::string field = "header";
  if (!header.empty()) {
    field = column >= 1 && column <= header.size()
                ? header[column - 1]
                : std::string("(extra field)");
  }
  std::string message(file);
  message += ':' + std::to_string(line) + ':' + std::to_string(column) + ' ' +
             field + ": ";
  message += rule;
  return Status::InvalidArgument(std::move(message));
}

// The parse stages below read the buffer s[0, n) (plus the NUL that
// std::string keeps after it) from *i on and count physical lines in *line.

// Skips one blank line (LF, CRLF or a lone CR) at *i and counts it; false
// when *i is not on one.
bool SkipBlankLine(const char* s, size_t n, size_t* i, uint32_t* line) {
  if (s[*i] == '\n') {
    ++*line;
    ++*i;
    return true;
  }
  if (s[*i] == '\r') {
    *i += (*i + 1 < n && s[*i + 1] == '\n') ? 2 : 1;
    ++*line;
    return true;
  }
  return false;
}

// Reads the quoted field whose opening quote is at *i and leaves *i after
// its closing quote. Unescapes in place (the write index never passes the
// read index): the field is s[start, start + *size) with start one past the
// opening quote. Counts the line breaks inside. False when the buffer ends
// before the closing quote.
bool ReadQuotedField(char* s, size_t n, size_t* i, uint32_t* line,
                     size_t* size) {
  size_t r = *i + 1;
  const size_t start = r;
  size_t w = start;
  uint32_t breaks = 0;  // a local count: the writes to s may alias *line
  for (;;) {
    if (r >= n) return false;
    const char c = s[r];
    if (c == '"') {
      if (r + 1 < n && s[r + 1] == '"') {
        s[w++] = '"';
        r += 2;
        continue;
      }
      ++r;
      break;
    }
    if (c == '\n' || (c == '\r' && !(r + 1 < n && s[r + 1] == '\n'))) {
      ++breaks;
    }
    s[w++] = c;
    ++r;
  }
  *i = r;
  *line += breaks;
  *size = w - start;
  return true;
}

// Moves *i to the end of the unquoted field at it: a ',', CR, LF or the end
// of the buffer (NUL bytes inside the data are field text).
void SkipUnquotedField(const char* s, size_t n, size_t* i) {
  size_t r = *i;
  for (;;) {
    while (!kFieldEnd[static_cast<unsigned char>(s[r])]) ++r;
    if (s[r] != '\0' || r >= n) break;
    ++r;  // a NUL byte inside the data
  }
  *i = r;
}

}  // namespace

Status Table::ReadRecord(char* s, size_t n, size_t* i, uint32_t* line,
                         std::string_view file, uint32_t record_line,
                         const std::vector<std::string>& header,
                         std::vector<Span>* fields) {
  const size_t first_field = fields->size();
  // Local copies: the stores into *fields may alias *i and *line.
  size_t r = *i;
  uint32_t ln = *line;
  for (;;) {
    if (r < n && s[r] == '"') {
      const size_t start = r + 1;
      size_t size = 0;
      if (!ReadQuotedField(s, n, &r, &ln, &size)) {
        return SyntaxError(file, static_cast<int>(record_line),
                           fields->size() - first_field + 1, header,
                           "unterminated quoted field");
      }
      fields->push_back(
          {static_cast<uint32_t>(start), static_cast<uint32_t>(size)});
      if (r < n && s[r] != ',' && s[r] != '\n' && s[r] != '\r') {
        return SyntaxError(file, static_cast<int>(ln),
                           fields->size() - first_field, header,
                           "unexpected character after closing quote");
      }
    } else {
      const size_t start = r;
      SkipUnquotedField(s, n, &r);
      fields->push_back(
          {static_cast<uint32_t>(start), static_cast<uint32_t>(r - start)});
    }
    if (r >= n) break;
    if (s[r] == ',') {
      ++r;
      continue;
    }
    // End of line.
    r += (s[r] == '\r' && r + 1 < n && s[r + 1] == '\n') ? 2 : 1;
    ++ln;
    break;
  }
  *i = r;
  *line = ln;
  return Status::Ok();
}

Status Table::ReadRecords(char* s, size_t n, size_t begin, size_t end,
                          uint32_t* line, std::string_view file,
                          const std::vector<std::string>& header,
                          std::vector<Span>* fields,
                          std::vector<Record>* records) {
  size_t i = begin;
  while (i < end) {
    // Blank line: skip (keeps counting lines).
    if (SkipBlankLine(s, n, &i, line)) continue;
    const uint32_t record_line = *line;
    const size_t first_field = fields->size();
    ROLLWEAR_RETURN_IF_ERROR(
        ReadRecord(s, n, &i, line, file, record_line, header, fields));
    const auto count = static_cast<uint32_t>(fields->size() - first_field);
    records->push_back(
        {static_cast<uint32_t>(first_field), count, record_line});
  }
  return Status::Ok();
}

void Table::TakeHeader(size_t first_field, uint32_t record_line) {
  header_line_ = static_cast<int>(record_line);
  header_.reserve(fields_.size() - first_field);
  for (size_t f = first_field; f < fields_.size(); ++f) {
    const Span& sp = fields_[f];
    header_.emplace_back(
        Trim(std::string_view(buffer_.data() + sp.begin, sp.size)));
  }
  fields_.resize(first_field);
}

namespace {

// Where the records after `begin` may be read in two halves: just after
// the line end nearest the middle, for a file of 1 MB or more with no
// quote in it (a quote may hide a line break, so only such a file can be
// cut without reading it first); n when it may not be cut.
size_t HalfwaySplit(const char* s, size_t begin, size_t n) {
  constexpr size_t kMinSplitBytes = size_t{1} << 20;
  if (n - begin < kMinSplitBytes) return n;
  if (std::memchr(s + begin, '"', n - begin) != nullptr) return n;
  const size_t mid = begin + (n - begin) / 2;
  const void* lf = std::memchr(s + mid, '\n', n - mid);
  if (lf == nullptr) return n;
  return static_cast<size_t>(static_cast<const char*>(lf) - s) + 1;
}

}  // namespace

StatusOr<Table> Table::Parse(std::string text, std::string_view file) {
  if (text.size() >= std::numeric_limits<uint32_t>::max()) {
    return Status::InvalidArgument(std::string(file) +
                                   ":0:0 file: file too large (4 GiB or more)");
  }
  Table t;
  t.buffer_ = std::move(text);
  char* s = t.buffer_.data();
  const size_t n = t.buffer_.size();
  size_t i = 0;
  if (n >= 3 && static_cast<unsigned char>(s[0]) == 0xEF &&
      static_cast<unsigned char>(s[1]) == 0xBB &&
      static_cast<unsigned char>(s[2]) == 0xBF) {
    i = 3;
  }
  uint32_t line = 1;
  // The header: the first record after any blank lines.
  while (i < n && SkipBlankLine(s, n, &i, &line)) {
  }
  if (i < n) {
    const uint32_t record_line = line;
    ROLLWEAR_RETURN_IF_ERROR(
        ReadRecord(s, n, &i, &line, file, record_line, t.header_, &t.fields_));
    t.TakeHeader(0, record_line);
  }
  // A rough guess that avoids most reallocations: >= 5 bytes per field.
  const size_t split = HalfwaySplit(s, i, n);
  t.fields_.reserve((split - i) / 5 + 16);
  t.records_.reserve((split - i) / 64 + 4);
  if (split == n) {
    ROLLWEAR_RETURN_IF_ERROR(ReadRecords(s, n, i, n, &line, file, t.header_,
                                         &t.fields_, &t.records_));
    return t;
  }
  // Two halves on two threads (a paper-size coils.csv is 10 MB), the
  // second numbering its lines from 1 until the first says where it
  // starts. Without quotes no record can fail.
  std::vector<Span> tail_fields;
  std::vector<Record> tail_records;
  tail_fields.reserve((n - split) / 5 + 16);
  tail_records.reserve((n - split) / 64 + 4);
  uint32_t tail_line = 1;
  Status tail;
  std::thread worker;
  try {
    worker = std::thread([&] {
      tail = ReadRecords(s, n, split, n, &tail_line, file, t.header_,
                         &tail_fields, &tail_records);
    });
  } catch (const std::system_error&) {  // no thread: one pass, as below 1 MB
    ROLLWEAR_RETURN_IF_ERROR(ReadRecords(s, n, i, n, &line, file, t.header_,
                                         &t.fields_, &t.records_));
    return t;
  }
  Status head = ReadRecords(s, n, i, split, &line, file, t.header_, &t.fields_,
                            &t.records_);
  worker.join();
  t.read_in_halves_ = true;
  ROLLWEAR_RETURN_IF_ERROR(head);
  ROLLWEAR_RETURN_IF_ERROR(tail);
  const auto field_offset = static_cast<uint32_t>(t.fields_.size());
  for (Record& r : tail_records) {
    r.first_field += field_offset;
    r.line += line - 1;
  }
  t.fields_.insert(t.fields_.end(), tail_fields.begin(), tail_fields.end());
  t.records_.insert(t.records_.end(), tail_records.begin(), tail_records.end());
  return t;
}

int Table::FindColumn(std::string_view name) const {
  for (size_t c = 0; c < header_.size(); ++c) {
    if (header_[c] == name) return static_cast<int>(c);
  }
  return -1;
}

std::string ForeignLayoutHint(const Table& t) {
  if (t.header().size() != 1) return "";
  const std::string& h = t.header()[0];
  constexpr const char* kAdvice = ": export as CSV with ',' and '.'";
  if (h.find(';') != std::string::npos) {
    // With ';' between fields, a comma in a row can only be a decimal one.
    bool decimal_commas = false;
    for (size_t r = 0; r < t.num_records() && !decimal_commas; ++r) {
      decimal_commas = t.num_fields(r) > 1;
    }
    return std::string("looks like a spreadsheet export with ';'") +
           (decimal_commas ? " and decimal commas" : "") + kAdvice;
  }
  if (h.find('\t') != std::string::npos) {
    return std::string("looks tab-separated") + kAdvice;
  }
  return "";
}

bool IsDecimalCommaNumber(std::string_view text) {
  text = Trim(text);
  if (!text.empty() && (text[0] == '-' || text[0] == '+')) {
    text.remove_prefix(1);
  }
  const size_t comma = text.find(',');
  if (comma == std::string_view::npos || comma == 0 ||
      comma + 1 == text.size()) {
    return false;
  }
  for (size_t i = 0; i < text.size(); ++i) {
    if (i != comma && (text[i] < '0' || text[i] > '9')) return false;
  }
  return true;
}

NumberResult ParseDouble(std::string_view text, double* out) {
  text = Trim(text);
  if (!text.empty() && text[0] == '+') {
    text.remove_prefix(1);
    if (!text.empty() && (text[0] == '+' || text[0] == '-')) {
      return NumberResult::kInvalid;
    }
  }
  if (text.empty()) return NumberResult::kInvalid;
  if (ParseSimpleDecimal(text, out)) return NumberResult::kOk;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, *out);
  if (ec == std::errc::result_out_of_range) return NumberResult::kOutOfRange;
  if (ec != std::errc() || ptr != end) return NumberResult::kInvalid;
  return NumberResult::kOk;
}

NumberResult ParseInt64(std::string_view text, int64_t* out) {
  text = Trim(text);
  if (!text.empty() && text[0] == '+') {
    text.remove_prefix(1);
    if (!text.empty() && (text[0] == '+' || text[0] == '-')) {
      return NumberResult::kInvalid;
    }
  }
  if (text.empty()) return NumberResult::kInvalid;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, *out);
  if (ec == std::errc::result_out_of_range) return NumberResult::kOutOfRange;
  if (ec != std::errc() || ptr != end) return NumberResult::kInvalid;
  return NumberResult::kOk;
}

void AppendField(std::string* out, std::string_view text) {
  bool quote = !text.empty() && (text.front() == ' ' || text.front() == '\t' ||
                                 text.back() == ' ' || text.back() == '\t');
  if (!quote) {
    for (char c : text) {
      if (c == ',' || c == '"' || c == '\n' || c == '\r') {
        quote = true;
        break;
      }
    }
  }
  if (!quote) {
    out->append(text);
    return;
  }
  out->push_back('"');
  for (char c : text) {
    if (c == '"') out->push_back('"');
    out->push_back(c);
  }
  out->push_back('"');
}

void AppendDouble(std::string* out, double value) {
  if (std::isnan(value)) return;
  char buf[32];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof(buf), value);
  (void)ec;  // 32 bytes always suffice for the shortest form of a double.
  out->append(buf, ptr);
}

}  // namespace rollwear::csv
