// RequestParser: an incremental HTTP/1.1 request parser (RFC 9112) for the
// daemon's epoll server, with no sockets, so that tests and the fuzzer can
// drive it with any byte split. It reads the request line, the header
// fields and a body framed by Content-Length or chunked transfer coding,
// and enforces the server's limits before the body is read: request line
// length (414), header count and bytes (431), body size (413), chunk
// extensions (4 KiB in all) and chunk framing on the wire (413). Anything
// that could be read two ways by two parsers (request smuggling) is a 400:
// both Content-Length and Transfer-Encoding, two different Content-Length
// values, white space before a field's colon, obsolete line folding, a
// bare LF or CR, chunked framing on HTTP/1.0, junk after a chunk size, an
// HTTP/1.1 request without a Host field or any with two. Absolute-form
// targets (http://host/path) are routed on their path. A
// transfer coding other than chunked is a 501, a version other than
// HTTP/1.0 or 1.1 a 505. "Connection: close" wins over "keep-alive".
//
// Use: append what the socket gives to one buffer and call Parse() on the
// unconsumed part (the buffer must keep the bytes already seen); kDone
// gives a request and how many bytes it took; call Reset() before parsing
// the next request on the same connection. Work is linear in the bytes
// received, however they are split.
//
// Thread-safety: none; one parser per connection, used by one thread.
#ifndef ROLLWEAR_API_HTTP_PARSER_H_
#define ROLLWEAR_API_HTTP_PARSER_H_

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "api/router.h"

namespace rollwear::api {

struct HttpParserLimits {
  size_t max_request_line = 8192;       // longer: 414
  size_t max_header_count = 64;         // more fields: 431
  size_t max_header_bytes = 32 * 1024;  // field section bytes: 431
  size_t max_body_bytes = 1 << 20;      // larger body: 413
};

// The most bytes a chunked body may take on the wire (chunk framing
// included): twice the body limit plus 64 KiB; more is a 413.
size_t MaxChunkedWireBytes(const HttpParserLimits& limits);
// The most bytes one request can take before the parser answers kDone or
// kError: a reader may stop reading a connection's input there.
size_t MaxRequestBytes(const HttpParserLimits& limits);

class RequestParser {
 public:
  enum class Result { kNeedMore, kDone, kError };

  explicit RequestParser(HttpParserLimits limits = {});

  // Parses `data`, which starts at this request's first byte and holds
  // every byte received since (the same prefix on every call).
  Result Parse(std::string_view data);
  // Forgets the request, for the next one on the connection.
  void Reset();

  // After kDone: the request. Parameters are percent-decoded; so is the
  // path, except "%2F" and "%25", which stay encoded (upper case) so that
  // routing sees the client's segments: "/v1%2Fcalibrations" is not
  // "/v1/calibrations". Router decodes its path parameters itself.
  HttpRequest& request() { return request_; }
  // After kDone: the bytes of `data` the request took.
  size_t consumed() const { return consumed_; }
  // After kDone: whether the connection may serve another request
  // (HTTP/1.1 without "Connection: close", or HTTP/1.0 with keep-alive).
  bool keep_alive() const { return keep_alive_; }
  // The request line says HTTP/1.0 (its kept-alive answer must say so).
  bool http10() const { return http10_; }
  // The request is a HEAD (its answer has no body).
  bool head() const { return request_.method == "HEAD"; }
  // The field section is complete and the client waits for "100 Continue"
  // before it sends the body (Expect: 100-continue, body not yet in).
  bool expects_continue() const { return expects_continue_; }
  // The field section is complete (the body may still be coming).
  bool headers_done() const { return phase_ != Phase::kHead; }
  // After kError: the status to answer (400, 413, 414, 431, 501, 505) and
  // a sentence naming what was wrong.
  int error_status() const { return error_status_; }
  const std::string& error_message() const { return error_message_; }

 private:
  enum class Phase { kHead, kBody, kChunkSize, kChunkData, kTrailer, kDone };

  // What the header fields said so far about the body's framing and the
  // connection (ParseHead).
  struct FieldFlags {
    bool has_length = false;
    bool saw_close = false;
    bool chunked = false;
    bool has_coding = false;
  };

  Result Fail(int status, std::string message);
  // The path and query of an absolute-form target (may point into
  // absolute_query_); other targets unchanged.
  std::string_view OriginForm(std::string_view target);
  size_t ScanHead(std::string_view data);
  Result ParseHead(std::string_view head);
  Result ParseRequestLine(std::string_view line);
  // The helpers below return kError (after Fail) or kNeedMore (go on).
  Result ParseFieldLine(std::string_view line, std::string_view* name,
                        std::string_view* value);
  Result ApplyField(std::string_view name, std::string_view value,
                    FieldFlags* flags);
  Result FinishHead(const FieldFlags& flags);
  Result ParseChunked(std::string_view data);
  // ParseChunked's phases: nullopt when the phase is complete and parsing
  // goes on, else the result to return.
  std::optional<Result> ParseChunkSizeLine(std::string_view data);
  std::optional<Result> ReadChunkData(std::string_view data);
  Result ParseTrailer(std::string_view data);

  HttpParserLimits limits_;
  Phase phase_ = Phase::kHead;
  HttpRequest request_;
  size_t head_scanned_ = 0;  // bytes searched for the end of the head
  size_t body_start_ = 0;    // offset of the body in the data
  size_t content_length_ = 0;
  size_t chunk_pos_ = 0;        // offset of the next chunk-size line/data
  size_t chunk_left_ = 0;       // bytes of the current chunk not yet copied
  size_t trailer_start_ = 0;    // offset of the trailer fields
  size_t trailer_scanned_ = 0;  // where the search for CRLF resumes
  size_t chunk_ext_bytes_ = 0;  // chunk extensions so far (capped)
  int host_fields_ = 0;
  std::string absolute_query_;  // "/?q" for "http://h?q"
  bool http10_ = false;
  size_t first_crlf_ = std::string_view::npos;  // end of the request line
  size_t consumed_ = 0;
  bool keep_alive_ = true;
  bool expects_continue_ = false;
  int error_status_ = 0;
  std::string error_message_;
};

// PercentDecode (api/routes.h) for a request path, except that "%2F" and
// "%25" (any case) stay encoded, spelled "%2F" and "%25".
bool DecodePath(std::string_view in, std::string* out);

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_HTTP_PARSER_H_
