#include "api/http_parser.h"

#include <algorithm>
#include <charconv>
#include <optional>
#include <utility>

#include <strings.h>

namespace rollwear::api {
namespace {

// Longest chunk-size line (size and extensions).
constexpr size_t kMaxChunkLine = 1024;
// The chunk extensions of one request, all lines together (RFC 9112 7.1.1:
// a server ought to limit them); they carry nothing the API reads.
constexpr size_t kMaxChunkExtBytes = 4096;

// RFC 9110 5.6.2: tchar.
bool IsTokenChar(char c) {
  if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
      (c >= '0' && c <= '9')) {
    return true;
  }
  switch (c) {
    case '!':
    case '#':
    case '$':
    case '%':
    case '&':
    case '\'':
    case '*':
    case '+':
    case '-':
    case '.':
    case '^':
    case '_':
    case '`':
    case '|':
    case '~':
      return true;
    default:
      return false;
  }
}

bool EqualsNoCase(std::string_view a, std::string_view b) {
  return a.size() == b.size() && strncasecmp(a.data(), b.data(), a.size()) == 0;
}

std::string_view TrimOws(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t'))
    s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t'))
    s.remove_suffix(1);
  return s;
}

// Whether the comma-separated list `value` holds `token` (any case).
bool ListHas(std::string_view value, std::string_view token) {
  while (!value.empty()) {
    const size_t comma = value.find(',');
    if (EqualsNoCase(TrimOws(value.substr(0, comma)), token)) return true;
    if (comma == std::string_view::npos) break;
    value.remove_prefix(comma + 1);
  }
  return false;
}

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// Lines end in CRLF; a CR or LF anywhere else is refused.
bool HasStrayLineBreak(std::string_view line) {
  return line.find_first_of("\r\n") != std::string_view::npos;
}

}  // namespace

size_t MaxChunkedWireBytes(const HttpParserLimits& limits) {
  return 2 * limits.max_body_bytes + (64 << 10);
}

size_t MaxRequestBytes(const HttpParserLimits& limits) {
  // Head, framing up to the last chunk-size line, that chunk's data and
  // CRLF, the trailer.
  return limits.max_request_line + 2 + limits.max_header_bytes + 4 +
         MaxChunkedWireBytes(limits) + kMaxChunkLine + 2 +
         limits.max_body_bytes + 2 + limits.max_header_bytes + 2;
}

bool PercentDecode(std::string_view in, bool plus_is_space, std::string* out) {
  out->clear();
  out->reserve(in.size());
  for (size_t i = 0; i < in.size(); ++i) {
    const char c = in[i];
    if (c == '%') {
      if (i + 2 >= in.size()) return false;
      const int hi = HexValue(in[i + 1]);
      const int lo = HexValue(in[i + 2]);
      if (hi < 0 || lo < 0) return false;
      out->push_back(static_cast<char>(hi * 16 + lo));
      i += 2;
    } else if (c == '+' && plus_is_space) {
      out->push_back(' ');
    } else {
      out->push_back(c);
    }
  }
  return true;
}

bool DecodePath(std::string_view in, std::string* out) {
  out->clear();
  out->reserve(in.size());
  for (size_t i = 0; i < in.size(); ++i) {
    if (in[i] != '%') {
      out->push_back(in[i]);
      continue;
    }
    if (i + 2 >= in.size()) return false;
    const int hi = HexValue(in[i + 1]);
    const int lo = HexValue(in[i + 2]);
    if (hi < 0 || lo < 0) return false;
    const char c = static_cast<char>(hi * 16 + lo);
    if (c == '/' || c == '%') {
      out->append(c == '/' ? "%2F" : "%25");  // one spelling for routing
    } else {
      out->push_back(c);
    }
    i += 2;
  }
  return true;
}

RequestParser::RequestParser(HttpParserLimits limits) : limits_(limits) {}

void RequestParser::Reset() {
  phase_ = Phase::kHead;
  request_ = HttpRequest();
  head_scanned_ = 0;
  body_start_ = 0;
  content_length_ = 0;
  chunk_pos_ = 0;
  chunk_left_ = 0;
  trailer_start_ = 0;
  trailer_scanned_ = 0;
  chunk_ext_bytes_ = 0;
  host_fields_ = 0;
  http10_ = false;
  first_crlf_ = std::string_view::npos;
  consumed_ = 0;
  keep_alive_ = true;
  expects_continue_ = false;
  error_status_ = 0;
  error_message_.clear();
}

RequestParser::Result RequestParser::Fail(int status, std::string message) {
  error_status_ = status;
  error_message_ = std::move(message);
  expects_continue_ = false;
  return Result::kError;
}

RequestParser::Result RequestParser::Parse(std::string_view data) {
  if (error_status_ != 0) return Result::kError;
  if (phase_ == Phase::kDone) return Result::kDone;
  if (phase_ == Phase::kHead) {
    const size_t end = ScanHead(data);
    if (error_status_ != 0) return Result::kError;
    if (end == std::string_view::npos) return Result::kNeedMore;
    const Result head = ParseHead(data.substr(0, end + 2));
    if (head == Result::kError) return head;
    body_start_ = end + 4;
    chunk_pos_ = body_start_;
  }
  if (phase_ == Phase::kBody) {
    if (data.size() - body_start_ < content_length_) return Result::kNeedMore;
    request_.body.assign(data.substr(body_start_, content_length_));
    consumed_ = body_start_ + content_length_;
    phase_ = Phase::kDone;
    expects_continue_ = false;
    return Result::kDone;
  }
  return ParseChunked(data);
}

// Looks at the head's bytes once each, in order, as if they arrived one by
// one: the errors that show before the head is complete (a bare CR or LF,
// a request line or field section over its limit) are found at the same
// byte however the data is split, so the answer does not depend on the
// split. Returns the offset of the head's final CRLFCRLF, or npos.
size_t RequestParser::ScanHead(std::string_view data) {
  for (size_t i = head_scanned_; i < data.size(); ++i) {
    const char c = data[i];
    const char prev = i > 0 ? data[i - 1] : '\0';
    head_scanned_ = i + 1;
    if ((c == '\n' && prev != '\r') || (prev == '\r' && c != '\n')) {
      Fail(400, "bare CR or LF in the request head");
      return std::string_view::npos;
    }
    if (c == '\n') {
      if (first_crlf_ == std::string_view::npos) {
        first_crlf_ = i - 1;
      } else if (i >= 3 && data[i - 2] == '\n') {
        return i - 3;  // "\r\n\r\n" ends here
      }
    }
    // Limits, with one byte of grace for a CR whose LF has not come yet.
    if (first_crlf_ == std::string_view::npos &&
        i + 1 > limits_.max_request_line + 1) {
      Fail(414, "the request line is longer than " +
                    std::to_string(limits_.max_request_line) + " bytes");
      return std::string_view::npos;
    }
    if (first_crlf_ != std::string_view::npos &&
        i + 1 - (first_crlf_ + 2) > limits_.max_header_bytes + 2) {
      Fail(431, "the header fields are larger than " +
                    std::to_string(limits_.max_header_bytes) + " bytes");
      return std::string_view::npos;
    }
  }
  return std::string_view::npos;
}

// RFC 9112 3.2.2: an absolute-form target ("http://host:port/v1/wear?x")
// is routed on its path and query ("/v1/wear?x"; "/" when it has none).
// Other targets are returned as they are.
std::string_view RequestParser::OriginForm(std::string_view target) {
  size_t scheme_end = 0;
  if (target.size() > 7 && EqualsNoCase(target.substr(0, 7), "http://")) {
    scheme_end = 7;
  } else if (target.size() > 8 &&
             EqualsNoCase(target.substr(0, 8), "https://")) {
    scheme_end = 8;
  } else {
    return target;
  }
  const size_t path = target.find_first_of("/?#", scheme_end);
  if (path == scheme_end) return std::string_view();  // no authority
  if (path == std::string_view::npos) return "/";
  if (target[path] != '/') {
    absolute_query_ = "/";
    absolute_query_.append(target.substr(path));
    return absolute_query_;
  }
  return target.substr(path);
}

RequestParser::Result RequestParser::ParseRequestLine(std::string_view line) {
  if (line.size() > limits_.max_request_line) {
    return Fail(414, "the request line is longer than " +
                         std::to_string(limits_.max_request_line) + " bytes");
  }
  const size_t sp1 = line.find(' ');
  const size_t sp2 =
      sp1 == std::string_view::npos ? sp1 : line.find(' ', sp1 + 1);
  if (sp1 == 0 || sp2 == std::string_view::npos ||
      line.find(' ', sp2 + 1) != std::string_view::npos) {
    return Fail(400, "malformed request line");
  }
  const std::string_view method = line.substr(0, sp1);
  std::string_view target = line.substr(sp1 + 1, sp2 - sp1 - 1);
  const std::string_view version = line.substr(sp2 + 1);
  for (char c : method) {
    if (!IsTokenChar(c)) return Fail(400, "malformed request method");
  }
  if (version.size() != 8 || version.substr(0, 5) != "HTTP/" ||
      version[6] != '.' || version[5] < '0' || version[5] > '9' ||
      version[7] < '0' || version[7] > '9') {
    return Fail(400, "malformed HTTP version");
  }
  if (version != "HTTP/1.1" && version != "HTTP/1.0") {
    return Fail(505, "HTTP version not supported (HTTP/1.0 and 1.1 are)");
  }
  http10_ = version == "HTTP/1.0";
  keep_alive_ = !http10_;
  target = OriginForm(target);
  if (target.empty() || target.front() != '/') {
    return Fail(400,
                "the request target must be an absolute path or an "
                "absolute URI (http://host/path)");
  }
  for (char c : target) {
    if (static_cast<unsigned char>(c) <= 0x20 || c == 0x7f) {
      return Fail(400, "the request target has a control character");
    }
  }
  request_.method.assign(method);
  const size_t q = target.find('?');
  if (!DecodePath(target.substr(0, q), &request_.path)) {
    return Fail(400, "malformed percent escape in the path");
  }
  if (q != std::string_view::npos) {
    std::string_view query = target.substr(q + 1);
    const size_t hash = query.find('#');
    if (hash != std::string_view::npos) query = query.substr(0, hash);
    std::string key, value;
    while (!query.empty()) {
      const size_t amp = query.find('&');
      const std::string_view pair = query.substr(0, amp);
      const size_t eq = pair.find('=');
      if (!pair.empty()) {
        if (!PercentDecode(pair.substr(0, eq), true, &key) ||
            !PercentDecode(eq == std::string_view::npos ? std::string_view()
                                                        : pair.substr(eq + 1),
                           true, &value)) {
          return Fail(400, "malformed percent escape in the query");
        }
        request_.params.emplace(key, value);  // the first one wins
      }
      if (amp == std::string_view::npos) break;
      query.remove_prefix(amp + 1);
    }
  }
  return Result::kNeedMore;
}

// `head` is the request line and the field lines, each ending in CRLF.
RequestParser::Result RequestParser::ParseHead(std::string_view head) {
  size_t line_end = head.find("\r\n");
  const std::string_view request_line = head.substr(0, line_end);
  if (HasStrayLineBreak(request_line)) {
    return Fail(400, "bare CR or LF in the request line");
  }
  if (ParseRequestLine(request_line) == Result::kError) return Result::kError;

  FieldFlags flags;
  size_t header_bytes = 0;
  size_t pos = line_end + 2;
  while (pos < head.size()) {
    line_end = head.find("\r\n", pos);
    const std::string_view line = head.substr(pos, line_end - pos);
    pos = line_end + 2;
    header_bytes += line.size() + 2;
    if (request_.headers.size() >= limits_.max_header_count) {
      return Fail(431, "more than " + std::to_string(limits_.max_header_count) +
                           " header fields");
    }
    if (header_bytes > limits_.max_header_bytes) {
      return Fail(431, "the header fields are larger than " +
                           std::to_string(limits_.max_header_bytes) + " bytes");
    }
    std::string_view name, value;
    if (ParseFieldLine(line, &name, &value) == Result::kError ||
        ApplyField(name, value, &flags) == Result::kError) {
      return Result::kError;
    }
    request_.headers.emplace_back(std::string(name), std::string(value));
  }
  return FinishHead(flags);
}

// One field line: name ":" OWS value OWS, with a token name and no control
// characters in the value; no line folding.
RequestParser::Result RequestParser::ParseFieldLine(std::string_view line,
                                                    std::string_view* name,
                                                    std::string_view* value) {
  if (HasStrayLineBreak(line)) {
    return Fail(400, "bare CR or LF in a header field");
  }
  if (line.front() == ' ' || line.front() == '\t') {
    return Fail(400, "obsolete line folding in the header fields");
  }
  const size_t colon = line.find(':');
  if (colon == std::string_view::npos || colon == 0) {
    return Fail(400, "malformed header field");
  }
  *name = line.substr(0, colon);
  for (char c : *name) {
    if (!IsTokenChar(c)) {
      return Fail(400,
                  "malformed header field name '" + std::string(*name) + "'");
    }
  }
  *value = TrimOws(line.substr(colon + 1));
  for (char c : *value) {
    if ((static_cast<unsigned char>(c) < 0x20 && c != '\t') || c == 0x7f) {
      return Fail(400, "control character in header field '" +
                           std::string(*name) + "'");
    }
  }
  return Result::kNeedMore;
}

// The fields the parser acts on: Content-Length, Transfer-Encoding,
// Connection, Host and Expect.
RequestParser::Result RequestParser::ApplyField(std::string_view name,
                                                std::string_view value,
                                                FieldFlags* flags) {
  if (EqualsNoCase(name, "Content-Length")) {
    size_t length = 0;
    const auto [end, ec] =
        std::from_chars(value.data(), value.data() + value.size(), length);
    if (value.empty() || ec != std::errc() ||
        end != value.data() + value.size()) {
      return Fail(400, "malformed Content-Length");
    }
    if (flags->has_length && length != content_length_) {
      return Fail(400, "two different Content-Length values");
    }
    flags->has_length = true;
    content_length_ = length;
  } else if (EqualsNoCase(name, "Transfer-Encoding")) {
    flags->has_coding = true;
    if (!EqualsNoCase(value, "chunked") || flags->chunked) {
      return Fail(501, "transfer coding '" + std::string(value) +
                           "' is not supported (only chunked)");
    }
    flags->chunked = true;
  } else if (EqualsNoCase(name, "Connection")) {
    // "close" wins over "keep-alive", in any field line.
    if (ListHas(value, "close")) flags->saw_close = true;
    if (ListHas(value, "keep-alive")) keep_alive_ = true;
  } else if (EqualsNoCase(name, "Host")) {
    ++host_fields_;
  } else if (EqualsNoCase(name, "Expect")) {
    // RFC 9110 10.1.1: an HTTP/1.0 client's expectation is ignored.
    expects_continue_ = !http10_ && EqualsNoCase(value, "100-continue");
  }
  return Result::kNeedMore;
}

// The checks on the fields as a whole, then the body's framing.
RequestParser::Result RequestParser::FinishHead(const FieldFlags& flags) {
  if (flags.saw_close) keep_alive_ = false;
  // RFC 9112 3.2: an HTTP/1.1 request has exactly one Host field; any
  // request with more than one is refused.
  if (host_fields_ > 1) return Fail(400, "more than one Host header field");
  if (host_fields_ == 0 && !http10_) {
    return Fail(400, "an HTTP/1.1 request must have a Host header field");
  }
  if (flags.chunked && http10_) {
    // RFC 9112 6.1: chunked framing on HTTP/1.0 is faulty.
    return Fail(400, "Transfer-Encoding on an HTTP/1.0 request");
  }
  if (flags.has_length && flags.has_coding) {
    return Fail(400, "both Content-Length and Transfer-Encoding");
  }
  if (flags.has_length && content_length_ > limits_.max_body_bytes) {
    return Fail(413, "the body is larger than " +
                         std::to_string(limits_.max_body_bytes) + " bytes");
  }
  // RFC 9112 6.3: without either, a request has no body.
  phase_ = flags.chunked ? Phase::kChunkSize : Phase::kBody;
  if (!flags.chunked && content_length_ == 0) expects_continue_ = false;
  return Result::kNeedMore;
}

// RFC 9112 7.1: chunk = chunk-size [ chunk-ext ] CRLF chunk-data CRLF;
// last-chunk = 1*"0" [ chunk-ext ] CRLF; then trailer fields and CRLF.
RequestParser::Result RequestParser::ParseChunked(std::string_view data) {
  // Every check is made on a whole line, or on a partial line with one
  // byte of grace for its CR, in the order the bytes come: the answer does
  // not depend on how the data is split.
  while (true) {
    if (phase_ == Phase::kChunkSize) {
      const std::optional<Result> result = ParseChunkSizeLine(data);
      if (result.has_value()) return *result;
    }
    if (phase_ == Phase::kChunkData) {
      const std::optional<Result> result = ReadChunkData(data);
      if (result.has_value()) return *result;
      continue;
    }
    if (phase_ == Phase::kTrailer) return ParseTrailer(data);
    return Result::kNeedMore;
  }
}

// The chunk-size line at chunk_pos_; on success moves to kChunkData, or to
// kTrailer after the last chunk.
std::optional<RequestParser::Result> RequestParser::ParseChunkSizeLine(
    std::string_view data) {
  const size_t eol = data.find("\r\n", chunk_pos_);
  if (eol == std::string_view::npos) {
    if (data.size() - chunk_pos_ > kMaxChunkLine + 1)
      return Fail(400, "chunk-size line too long");
    return Result::kNeedMore;
  }
  const std::string_view line = data.substr(chunk_pos_, eol - chunk_pos_);
  if (line.size() > kMaxChunkLine) {
    return Fail(400, "chunk-size line too long");
  }
  if (HasStrayLineBreak(line)) return Fail(400, "bare CR or LF in a chunk");
  // Framing counts too: tiny chunks may not make a small body take
  // more than twice the body limit on the wire.
  if (eol + 2 - body_start_ > MaxChunkedWireBytes(limits_)) {
    return Fail(413, "the chunked body takes more than " +
                         std::to_string(MaxChunkedWireBytes(limits_)) +
                         " bytes on the wire");
  }
  // chunk-size [ BWS ";" chunk-ext ]: after the hex digits only blanks
  // and then ";" (or the end of the line).
  const size_t digits_end = line.find_first_of("; \t");
  const std::string_view digits = line.substr(0, digits_end);
  if (digits_end != std::string_view::npos) {
    chunk_ext_bytes_ += line.size() - digits_end;
    if (chunk_ext_bytes_ > kMaxChunkExtBytes) {
      return Fail(413, "the chunk extensions take more than " +
                           std::to_string(kMaxChunkExtBytes) + " bytes");
    }
    const size_t after = line.find_first_not_of(" \t", digits_end);
    if (after != std::string_view::npos && line[after] != ';') {
      return Fail(400, "malformed chunk size");
    }
  }
  size_t size = 0;
  const auto [end, ec] =
      std::from_chars(digits.data(), digits.data() + digits.size(), size, 16);
  if (digits.empty() || ec != std::errc() ||
      end != digits.data() + digits.size()) {
    return Fail(400, "malformed chunk size");
  }
  if (size > limits_.max_body_bytes - request_.body.size()) {
    return Fail(413, "the body is larger than " +
                         std::to_string(limits_.max_body_bytes) + " bytes");
  }
  chunk_pos_ = eol + 2;
  if (size == 0) {
    phase_ = Phase::kTrailer;
    trailer_start_ = chunk_pos_;
    trailer_scanned_ = chunk_pos_;
  } else {
    chunk_left_ = size;
    phase_ = Phase::kChunkData;
  }
  expects_continue_ = false;
  return std::nullopt;
}

// Copies the current chunk's data; once it and its CRLF are in, moves back
// to kChunkSize.
std::optional<RequestParser::Result> RequestParser::ReadChunkData(
    std::string_view data) {
  const size_t available = data.size() - chunk_pos_;
  const size_t take = std::min(available, chunk_left_);
  request_.body.append(data.substr(chunk_pos_, take));
  chunk_pos_ += take;
  chunk_left_ -= take;
  if (chunk_left_ > 0 || data.size() - chunk_pos_ < 2) return Result::kNeedMore;
  if (data.substr(chunk_pos_, 2) != "\r\n")
    return Fail(400, "chunk data not followed by CRLF");
  chunk_pos_ += 2;
  phase_ = Phase::kChunkSize;
  return std::nullopt;
}

// Trailer fields are read and dropped; an empty line ends them.
RequestParser::Result RequestParser::ParseTrailer(std::string_view data) {
  while (true) {
    // Resume the search where the last call stopped (linear work).
    const size_t eol =
        data.find("\r\n", std::max(chunk_pos_, trailer_scanned_));
    if (eol == std::string_view::npos) {
      trailer_scanned_ = data.size() - 1;
      if (data.size() - trailer_start_ > limits_.max_header_bytes + 1)
        return Fail(431, "trailer fields too large");
      return Result::kNeedMore;
    }
    // Lines and their CRLFs must fit the limit, as in the head; the
    // final empty line is measured like the others (a partial line is
    // given one byte of grace for its CR above).
    if (eol - trailer_start_ > limits_.max_header_bytes) {
      return Fail(431, "trailer fields too large");
    }
    if (eol == chunk_pos_) {
      consumed_ = eol + 2;
      phase_ = Phase::kDone;
      return Result::kDone;
    }
    if (HasStrayLineBreak(data.substr(chunk_pos_, eol - chunk_pos_))) {
      return Fail(400, "bare CR or LF in a trailer field");
    }
    chunk_pos_ = eol + 2;
  }
}

}  // namespace rollwear::api
