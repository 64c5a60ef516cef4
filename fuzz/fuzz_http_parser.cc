// libFuzzer target: the daemon's incremental HTTP/1.1 request parser
// (api/http_parser.h). The first input byte picks the limits (the
// defaults, or small ones so that every limit is reachable within
// -max_len) and seeds the split points; the rest is a byte stream of one
// or more pipelined requests.
//
// The stream is parsed three ways: each request in one piece, each request
// fed as growing prefixes cut at points drawn from the seed, and (for short
// inputs) each request fed one byte at a time; after every kDone the
// parser is Reset() and continues on the remainder. All three must give
// the same sequence of requests (result, error status, method, path,
// parameters, headers, body, consumed bytes, keep-alive, HEAD). Besides, a
// prefix never gives kDone with consumed() larger than itself, kDone
// respects the limits, an error carries one of the documented statuses and
// a message, and short of an error expects_continue() implies
// headers_done(). Anything else
// (a crash, a sanitizer report, a leak) is a bug too.
//
// Thread-safety: libFuzzer calls the entry point from one thread.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "api/http_parser.h"

namespace {

using rollwear::api::HttpParserLimits;
using rollwear::api::RequestParser;
using Result = RequestParser::Result;

// Requests read from one stream at most (each takes >= 16 bytes anyway).
constexpr int kMaxRequests = 64;
// Inputs up to this size are also fed one byte at a time.
constexpr size_t kByteByByteMax = 2048;

struct Outcome {
  Result result = Result::kNeedMore;
  int error_status = 0;
  size_t consumed = 0;
  bool keep_alive = false;
  bool head = false;
  std::string method;
  std::string path;
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;
  std::map<std::string, std::string> params;

  bool operator==(const Outcome&) const = default;
};

[[noreturn]] void Die(const char* what, size_t request, size_t at) {
  std::fprintf(stderr,
               "fuzz_http_parser: %s (request %zu at stream offset %zu)\n",
               what, request, at);
  __builtin_trap();
}

void Require(bool ok, const char* what, size_t request = 0, size_t at = 0) {
  if (!ok) Die(what, request, at);
}

Outcome Snapshot(RequestParser& p, Result result) {
  Outcome o;
  o.result = result;
  if (result == Result::kError) {
    o.error_status = p.error_status();
    return o;
  }
  if (result != Result::kDone) return o;
  o.consumed = p.consumed();
  o.keep_alive = p.keep_alive();
  o.head = p.head();
  o.method = p.request().method;
  o.path = p.request().path;
  o.body = p.request().body;
  o.headers = p.request().headers;
  o.params = p.request().params;
  return o;
}

// Invariants of one Parse() call on `data`.
void CheckCall(RequestParser& p, Result r, std::string_view data,
               const HttpParserLimits& limits) {
  if (r != Result::kError && p.expects_continue()) {
    Require(p.headers_done(), "expects_continue() before headers_done()");
  }
  if (r == Result::kError) {
    const int s = p.error_status();
    Require(
        s == 400 || s == 413 || s == 414 || s == 431 || s == 501 || s == 505,
        "undocumented error status");
    Require(!p.error_message().empty(), "error without a message");
    return;
  }
  if (r != Result::kDone) return;
  Require(p.consumed() > 0, "kDone with consumed() == 0");
  Require(p.consumed() <= data.size(), "kDone consumed more than it was given");
  Require(p.headers_done(), "kDone before headers_done()");
  const rollwear::api::HttpRequest& req = p.request();
  Require(!req.method.empty(), "kDone with an empty method");
  Require(!req.path.empty() && req.path.front() == '/',
          "kDone with a path not starting with '/'");
  Require(req.body.size() <= limits.max_body_bytes, "body over the limit");
  Require(req.headers.size() <= limits.max_header_count,
          "more header fields than the limit");
  Require(p.head() == (req.method == "HEAD"), "head() disagrees with method");
}

// A tiny deterministic generator for the cut points.
struct Cuts {
  uint32_t state;
  uint32_t Next() {
    state ^= state << 13;
    state ^= state >> 17;
    state ^= state << 5;
    return state;
  }
};

enum class Feed { kWhole, kCuts, kBytes };

// Parses the stream `data` request after request; returns each request's
// outcome, ending with the first kNeedMore or kError.
std::vector<Outcome> ParseStream(std::string_view data,
                                 const HttpParserLimits& limits, Feed feed,
                                 uint32_t seed) {
  std::vector<Outcome> out;
  RequestParser p(limits);
  Cuts cuts{seed | 1u};
  size_t offset = 0;
  for (int n = 0; n < kMaxRequests; ++n) {
    const std::string_view rest = data.substr(offset);
    Result r = Result::kNeedMore;
    if (feed == Feed::kWhole) {
      r = p.Parse(rest);
      CheckCall(p, r, rest, limits);
    } else {
      size_t cut = 0;
      while (r == Result::kNeedMore && cut < rest.size()) {
        if (feed == Feed::kBytes) {
          cut += 1;
        } else {
          // Mostly short steps, sometimes long ones.
          const uint32_t x = cuts.Next();
          const uint32_t span = (x & 3) == 0 ? 4096 : (x & 3) == 1 ? 64 : 8;
          cut += 1 + (x >> 8) % span;
        }
        if (cut > rest.size()) cut = rest.size();
        const std::string_view prefix = rest.substr(0, cut);
        r = p.Parse(prefix);
        CheckCall(p, r, prefix, limits);
      }
    }
    out.push_back(Snapshot(p, r));
    if (r != Result::kDone) break;
    offset += p.consumed();
    p.Reset();
    Require(!p.headers_done() && !p.expects_continue(),
            "Reset() kept the state", out.size(), offset);
    if (offset == data.size()) break;
  }
  return out;
}

void Compare(const std::vector<Outcome>& a, const std::vector<Outcome>& b,
             const char* what) {
  const size_t n = a.size() < b.size() ? a.size() : b.size();
  size_t at = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!(a[i] == b[i])) {
      std::fprintf(stderr,
                   "request %zu: whole: result %d status %d consumed %zu; "
                   "%s: result %d status %d consumed %zu\n",
                   i, static_cast<int>(a[i].result), a[i].error_status,
                   a[i].consumed, what, static_cast<int>(b[i].result),
                   b[i].error_status, b[i].consumed);
      Die("a split changed the parse", i, at);
    }
    at += a[i].consumed;
  }
  if (a.size() != b.size()) Die("a split changed the request count", n, at);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint8_t config = data[0];
  const std::string_view stream(reinterpret_cast<const char*>(data) + 1,
                                size - 1);
  HttpParserLimits limits;
  if (config & 1) {
    // Small limits, all reachable within the fuzzer's input size.
    limits.max_request_line = 32 + (config >> 4);
    limits.max_header_count = 2 + ((config >> 1) & 7);
    limits.max_header_bytes = 64 + 16 * ((config >> 4) & 15);
    limits.max_body_bytes = 16 + 8 * ((config >> 1) & 31);
  }
  uint32_t seed = 0x9e3779b9u ^ (static_cast<uint32_t>(config) * 0x85ebca6bu);
  for (size_t i = 0; i < stream.size() && i < 4; ++i) {
    seed = seed * 31 + static_cast<uint8_t>(stream[i]);
  }

  const std::vector<Outcome> whole =
      ParseStream(stream, limits, Feed::kWhole, seed);
  Compare(whole, ParseStream(stream, limits, Feed::kCuts, seed), "cuts");
  if (stream.size() <= kByteByByteMax) {
    Compare(whole, ParseStream(stream, limits, Feed::kBytes, seed),
            "byte by byte");
  }

  // PercentDecode never grows its input.
  std::string decoded;
  if (rollwear::api::PercentDecode(stream, (config & 2) != 0, &decoded)) {
    Require(decoded.size() <= stream.size(), "PercentDecode grew its input");
  }
  return 0;
}
