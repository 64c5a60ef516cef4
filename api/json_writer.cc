#include "api/json_writer.h"

#include <charconv>
#include <cmath>

// For nlohmann::detail::to_chars only: the answers must print doubles with
// the very routine that dump() uses (see json_writer.h).
#include <nlohmann/json.hpp>

namespace rollwear::api {
namespace {

// Bytes that go out as they are: printable ASCII and DEL, but not '"' and
// '\'. Bytes from 0x80 on are checked as UTF-8 first.
constexpr bool IsPlain(unsigned char c) {
  return c >= 0x20 && c < 0x80 && c != '"' && c != '\\';
}

// At a byte >= 0x80: the length of the well-formed UTF-8 sequence that
// starts at `p` (Unicode table 3-7, the sequences nlohmann's decoder
// accepts), or 0 when there is none. Then `*skip` is how many bytes
// nlohmann replaces by one U+FFFD: the lead byte alone when it cannot start
// a sequence, else the bytes before the first one that does not continue it
// (that byte is read again as a new start), or the rest of the string when
// it ends inside the sequence.
size_t Utf8Sequence(const unsigned char* p, const unsigned char* end,
                    size_t* skip) {
  const unsigned char lead = p[0];
  size_t length = 0;
  // The range of the second byte; later ones are 0x80..0xBF.
  unsigned char lo = 0x80, hi = 0xBF;
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    if (lead == 0xE0) lo = 0xA0;  // overlong
    if (lead == 0xED) hi = 0x9F;  // UTF-16 surrogates
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    if (lead == 0xF0) lo = 0x90;  // overlong
    if (lead == 0xF4) hi = 0x8F;  // above U+10FFFF
  } else {
    *skip = 1;
    return 0;
  }
  for (size_t i = 1; i < length; ++i) {
    if (p + i == end || p[i] < lo || p[i] > hi) {
      *skip = i;
      return 0;
    }
    lo = 0x80;
    hi = 0xBF;
  }
  return length;
}

void AppendEscaped(unsigned char c, std::string* out) {
  switch (c) {
    case '"':
      out->append("\\\"");
      return;
    case '\\':
      out->append("\\\\");
      return;
    case '\b':
      out->append("\\b");
      return;
    case '\t':
      out->append("\\t");
      return;
    case '\n':
      out->append("\\n");
      return;
    case '\f':
      out->append("\\f");
      return;
    case '\r':
      out->append("\\r");
      return;
    default: {
      static constexpr char kHex[] = "0123456789abcdef";
      const char escape[6] = {'\\', 'u', '0', '0', kHex[c >> 4], kHex[c & 15]};
      out->append(escape, sizeof(escape));
      return;
    }
  }
}

}  // namespace

void AppendJsonString(std::string_view value, std::string* out) {
  const auto* p = reinterpret_cast<const unsigned char*>(value.data());
  const auto* const end = p + value.size();
  out->push_back('"');
  while (p < end) {
    const unsigned char* run = p;
    while (p < end && IsPlain(*p)) ++p;
    if (p > run) {
      out->append(reinterpret_cast<const char*>(run),
                  static_cast<size_t>(p - run));
    }
    if (p == end) break;
    if (*p < 0x80) {
      AppendEscaped(*p, out);
      ++p;
      continue;
    }
    size_t skip = 0;
    const size_t length = Utf8Sequence(p, end, &skip);
    if (length > 0) {
      out->append(reinterpret_cast<const char*>(p), length);
      p += length;
    } else {
      out->append("\xEF\xBF\xBD");  // U+FFFD
      p += skip;
    }
  }
  out->push_back('"');
}

void AppendJsonDouble(double value, std::string* out) {
  if (!std::isfinite(value)) {
    out->append("null");
    return;
  }
  char buffer[64];  // nlohmann's number buffer has 64 bytes as well
  const char* end =
      nlohmann::detail::to_chars(buffer, buffer + sizeof(buffer), value);
  out->append(buffer, static_cast<size_t>(end - buffer));
}

void AppendJsonInt(int64_t value, std::string* out) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out->append(buffer, static_cast<size_t>(result.ptr - buffer));
}

}  // namespace rollwear::api
