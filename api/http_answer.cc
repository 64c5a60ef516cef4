#include "api/http_answer.h"

#include <sys/socket.h>

#include <cerrno>
#include <cstdlib>

namespace rollwear::api {
namespace {

// Case-insensitive "does `line` start with `prefix`" (prefix lower case).
bool StartsWithLower(std::string_view line, std::string_view prefix) {
  if (line.size() < prefix.size()) return false;
  for (size_t i = 0; i < prefix.size(); ++i) {
    char c = line[i];
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    if (c != prefix[i]) return false;
  }
  return true;
}

}  // namespace

bool ParseAnswerHead(std::string_view in, AnswerHead* head, bool* bad) {
  const size_t end = in.find("\r\n\r\n");
  if (end == std::string_view::npos) return false;
  head->head_length = end + 4;
  const std::string_view text = in.substr(0, end + 2);
  const size_t line_end = text.find("\r\n");
  const std::string_view status_line = text.substr(0, line_end);
  if (status_line.size() < 12 || status_line.substr(0, 5) != "HTTP/") {
    *bad = true;
    return true;
  }
  head->status = std::atoi(std::string(status_line.substr(9, 3)).c_str());
  size_t pos = line_end + 2;
  while (pos < text.size()) {
    const size_t next = text.find("\r\n", pos);
    const std::string_view line = text.substr(pos, next - pos);
    if (StartsWithLower(line, "content-length:")) {
      head->body_length =
          std::strtoull(std::string(line.substr(15)).c_str(), nullptr, 10);
    } else if (StartsWithLower(line, "connection:")) {
      head->close = line.find("close") != std::string_view::npos;
    } else if (StartsWithLower(line, "transfer-encoding:")) {
      head->chunked = line.find("chunked") != std::string_view::npos;
    }
    pos = next + 2;
  }
  return true;
}

int ReadAvailable(int fd, std::string* in, bool* closed) {
  char buf[16384];
  *closed = false;
  for (;;) {
    const ssize_t k = recv(fd, buf, sizeof(buf), 0);
    if (k > 0) {
      in->append(buf, static_cast<size_t>(k));
    } else if (k == 0) {
      *closed = true;
      return 0;
    } else {
      return errno == EAGAIN || errno == EWOULDBLOCK ? 0 : errno;
    }
  }
}

int ChunkedBody(std::string_view in, size_t start, std::string* body,
                size_t* end) {
  body->clear();
  size_t pos = start;
  for (;;) {
    const size_t line_end = in.find("\r\n", pos);
    if (line_end == std::string_view::npos) return 0;
    // chunk-size [ chunk-ext ] CRLF; the extension is ignored.
    const std::string size_text(in.substr(pos, line_end - pos));
    char* parsed = nullptr;
    const unsigned long long size =
        std::strtoull(size_text.c_str(), &parsed, 16);
    if (parsed == size_text.c_str() || (*parsed != '\0' && *parsed != ';' &&
                                        *parsed != ' ' && *parsed != '\t')) {
      return -1;
    }
    pos = line_end + 2;
    if (size == 0) {
      // Trailer fields, then the blank line.
      for (;;) {
        const size_t trailer_end = in.find("\r\n", pos);
        if (trailer_end == std::string_view::npos) return 0;
        const bool blank = trailer_end == pos;
        pos = trailer_end + 2;
        if (blank) {
          *end = pos;
          return 1;
        }
      }
    }
    if (size > in.size() || in.size() - pos < size + 2) return 0;
    body->append(in.substr(pos, size));
    pos += size;
    if (in.substr(pos, 2) != "\r\n") return -1;
    pos += 2;
  }
}

}  // namespace rollwear::api
