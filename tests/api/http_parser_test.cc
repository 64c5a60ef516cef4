// RequestParser (api/http_parser.h) driven in memory: request line, query
// and path decoding, header fields as sent, Content-Length and chunked
// bodies under every byte split, pipelining with Reset(), keep-alive,
// Expect: 100-continue, HEAD, and every error with the status the header
// promises (400, 413, 414, 431, 501, 505).
#include "api/http_parser.h"

#include <cstdio>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace rollwear::api {
namespace {

using Result = RequestParser::Result;

const char* Name(Result r) {
  switch (r) {
    case Result::kNeedMore:
      return "kNeedMore";
    case Result::kDone:
      return "kDone";
    case Result::kError:
      return "kError";
  }
  return "?";
}

// Everything of a parsed request that a split must not change.
struct Parsed {
  Result result = Result::kNeedMore;
  int error_status = 0;
  size_t consumed = 0;
  bool keep_alive = false;
  bool head = false;
  std::string method;
  std::string path;
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;
  std::vector<std::pair<std::string, std::string>> params;

  std::string error_message;  // not compared

  bool operator==(const Parsed& o) const {
    return result == o.result && error_status == o.error_status &&
           consumed == o.consumed && keep_alive == o.keep_alive &&
           head == o.head && method == o.method && path == o.path &&
           body == o.body && headers == o.headers && params == o.params;
  }
};

void PrintTo(const Parsed& s, std::ostream* os) {
  *os << "{" << Name(s.result) << " " << s.error_status << " '"
      << s.error_message << "' consumed=" << s.consumed
      << " keep_alive=" << s.keep_alive << " head=" << s.head << " " << s.method
      << " " << s.path << " body=" << s.body.size() << "B " << s.headers.size()
      << " headers " << s.params.size() << " params}";
}

Parsed Snapshot(RequestParser& p, Result result) {
  Parsed s;
  s.result = result;
  if (result == Result::kError) {
    s.error_status = p.error_status();
    s.error_message = p.error_message();
    return s;
  }
  if (result != Result::kDone) return s;
  s.consumed = p.consumed();
  s.keep_alive = p.keep_alive();
  s.head = p.head();
  const HttpRequest& r = p.request();
  s.method = r.method;
  s.path = r.path;
  s.body = r.body;
  s.headers = r.headers;
  s.params.assign(r.params.begin(), r.params.end());
  return s;
}

Parsed ParseWhole(std::string_view data, HttpParserLimits limits = {}) {
  RequestParser p(limits);
  const Result r = p.Parse(data);
  return Snapshot(p, r);
}

// Parses `data` in one piece and expects an error with `status`.
void ExpectError(std::string_view data, int status,
                 HttpParserLimits limits = {}) {
  RequestParser p(limits);
  const Result r = p.Parse(data);
  ASSERT_EQ(r, Result::kError) << Name(r) << " for: " << data;
  EXPECT_EQ(p.error_status(), status) << data;
  EXPECT_FALSE(p.error_message().empty()) << data;
}

// Grows the prefix one byte at a time on one parser: kNeedMore until the
// last byte, then kDone; returns the snapshot at kDone.
Parsed ParseByteByByte(std::string_view data, HttpParserLimits limits = {}) {
  RequestParser p(limits);
  for (size_t n = 1; n < data.size(); ++n) {
    const Result r = p.Parse(data.substr(0, n));
    if (r != Result::kNeedMore) {
      ADD_FAILURE() << Name(r) << " after " << n << " of " << data.size()
                    << " bytes (error " << p.error_status() << " "
                    << p.error_message() << ")";
      return Snapshot(p, r);
    }
  }
  const Result r = p.Parse(data);
  EXPECT_EQ(r, Result::kDone) << Name(r) << " " << p.error_message();
  return Snapshot(p, r);
}

// Grows the prefix one byte at a time until the parser answers (kDone or
// kError, unlike ParseByteByByte an early error is allowed) and returns
// the snapshot then.
Parsed ParseGrowing(std::string_view data, HttpParserLimits limits = {}) {
  RequestParser p(limits);
  Result r = Result::kNeedMore;
  for (size_t n = 1; n <= data.size() && r == Result::kNeedMore; ++n) {
    r = p.Parse(data.substr(0, n));
  }
  return Snapshot(p, r);
}

// ------------------------------------------------------------ basics

TEST(HttpParserTest, GetWithQueryStringIsDecoded) {
  const std::string data =
      "GET /v1/a%20b+c/x?q=a+b%21&empty=&tilde=%7e&k%3D=v%26w HTTP/1.1\r\n"
      "Host: example\r\n"
      "X-Mixed-Case: Value With  Spaces\r\n"
      "accept: */*\r\n"
      "\r\n";
  RequestParser p;
  ASSERT_EQ(p.Parse(data), Result::kDone) << p.error_message();
  EXPECT_EQ(p.consumed(), data.size());
  const HttpRequest& r = p.request();
  EXPECT_EQ(r.method, "GET");
  // '+' is a space only in the query.
  EXPECT_EQ(r.path, "/v1/a b+c/x");
  EXPECT_EQ(r.params.size(), 4u);
  EXPECT_EQ(r.params.at("q"), "a b!");
  EXPECT_EQ(r.params.at("empty"), "");
  EXPECT_EQ(r.params.at("tilde"), "~");
  EXPECT_EQ(r.params.at("k="), "v&w");
  ASSERT_EQ(r.headers.size(), 3u);
  // Names as sent, in order; values without the surrounding white space.
  EXPECT_EQ(r.headers[0].first, "Host");
  EXPECT_EQ(r.headers[0].second, "example");
  EXPECT_EQ(r.headers[1].first, "X-Mixed-Case");
  EXPECT_EQ(r.headers[1].second, "Value With  Spaces");
  EXPECT_EQ(r.headers[2].first, "accept");
  EXPECT_EQ(r.headers[2].second, "*/*");
  EXPECT_TRUE(r.body.empty());
  EXPECT_TRUE(p.keep_alive());
  EXPECT_FALSE(p.head());
  EXPECT_TRUE(p.headers_done());
  EXPECT_FALSE(p.expects_continue());
}

TEST(HttpParserTest, FieldValueWhiteSpaceIsTrimmed) {
  const Parsed s = ParseWhole(
      "GET / HTTP/1.1\r\nHost:x\r\nX-A: \t padded \t \r\nX-Empty:\r\n\r\n");
  ASSERT_EQ(s.result, Result::kDone);
  ASSERT_EQ(s.headers.size(), 3u);
  EXPECT_EQ(s.headers[0].second, "x");
  EXPECT_EQ(s.headers[1].second, "padded");
  EXPECT_EQ(s.headers[2].first, "X-Empty");
  EXPECT_EQ(s.headers[2].second, "");
}

TEST(HttpParserTest, PathWithoutQueryHasNoParams) {
  const Parsed s = ParseWhole("GET /v1/wear HTTP/1.1\r\nHost: x\r\n\r\n");
  ASSERT_EQ(s.result, Result::kDone);
  EXPECT_EQ(s.path, "/v1/wear");
  EXPECT_TRUE(s.params.empty());
}

TEST(HttpParserTest, PercentDecode) {
  std::string out;
  EXPECT_TRUE(PercentDecode("a%20b+c", false, &out));
  EXPECT_EQ(out, "a b+c");
  out.clear();
  EXPECT_TRUE(PercentDecode("a%20b+c", true, &out));
  EXPECT_EQ(out, "a b c");
  out.clear();
  EXPECT_TRUE(PercentDecode("%4a%4A%2f", false, &out));
  EXPECT_EQ(out, "JJ/");
  out.clear();
  EXPECT_TRUE(PercentDecode("", false, &out));
  EXPECT_EQ(out, "");
  for (const char* bad : {"%", "%2", "a%g0", "%0g", "abc%", "%%"}) {
    std::string o;
    EXPECT_FALSE(PercentDecode(bad, false, &o)) << bad;
  }
}

TEST(HttpParserTest, TwoPipelinedRequestsInOneBuffer) {
  const std::string first =
      "POST /v1/coils HTTP/1.1\r\nHost: x\r\nContent-Length: 5\r\n\r\nhello";
  const std::string second = "GET /v1/wear?x=1 HTTP/1.1\r\nHost: y\r\n\r\n";
  const std::string data = first + second;
  RequestParser p;
  ASSERT_EQ(p.Parse(data), Result::kDone) << p.error_message();
  EXPECT_EQ(p.consumed(), first.size());
  EXPECT_EQ(p.request().method, "POST");
  EXPECT_EQ(p.request().body, "hello");
  p.Reset();
  EXPECT_FALSE(p.headers_done());
  const std::string_view rest = std::string_view(data).substr(first.size());
  ASSERT_EQ(p.Parse(rest), Result::kDone) << p.error_message();
  EXPECT_EQ(p.consumed(), second.size());
  EXPECT_EQ(p.request().method, "GET");
  EXPECT_EQ(p.request().path, "/v1/wear");
  EXPECT_EQ(p.request().params.at("x"), "1");
  EXPECT_TRUE(p.request().body.empty());
  ASSERT_EQ(p.request().headers.size(), 1u) << "Reset() kept old headers";
  EXPECT_EQ(p.request().headers[0].second, "y");
}

TEST(HttpParserTest, ChunkedThenPipelinedRequest) {
  const std::string first =
      "POST /c HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n"
      "3\r\nabc\r\n0\r\n\r\n";
  const std::string second = "GET /d HTTP/1.1\r\nHost: x\r\n\r\n";
  const std::string data = first + second;
  RequestParser p;
  ASSERT_EQ(p.Parse(data), Result::kDone) << p.error_message();
  EXPECT_EQ(p.consumed(), first.size());
  EXPECT_EQ(p.request().body, "abc");
  p.Reset();
  ASSERT_EQ(p.Parse(std::string_view(data).substr(first.size())),
            Result::kDone);
  EXPECT_EQ(p.request().path, "/d");
  EXPECT_EQ(p.consumed(), second.size());
}

// ------------------------------------------------------------ splits

const std::string kContentLengthPost =
    "POST /v1/coils?dry=1 HTTP/1.1\r\n"
    "Host: 127.0.0.1:8080\r\n"
    "Content-Type: application/json\r\n"
    "Content-Length: 27\r\n"
    "\r\n"
    "{\"coil_id\":\"K1\",\"seq\":1234}";

const std::string kChunkedPost =
    "POST /v1/coils HTTP/1.1\r\n"
    "Host: x\r\n"
    "Transfer-Encoding: chunked\r\n"
    "\r\n"
    "5;name=value\r\n"
    "{\"coi\r\n"
    "B;a=1;b=\"q\"\r\n"
    "l_id\":\"K1\",\r\n"
    "0f\r\n"
    "\"seq\":1234}    \r\n"
    "0\r\n"
    "X-Trailer: yes\r\n"
    "\r\n";

TEST(HttpParserTest, ContentLengthPostInEveryByteSplit) {
  ASSERT_EQ(kContentLengthPost.size() - kContentLengthPost.find("\r\n\r\n") - 4,
            27u);
  const Parsed whole = ParseWhole(kContentLengthPost);
  ASSERT_EQ(whole.result, Result::kDone);
  EXPECT_EQ(whole.consumed, kContentLengthPost.size());
  EXPECT_EQ(whole.method, "POST");
  EXPECT_EQ(whole.path, "/v1/coils");
  EXPECT_EQ(whole.body, "{\"coil_id\":\"K1\",\"seq\":1234}");
  EXPECT_EQ(whole.params.size(), 1u);
  EXPECT_EQ(ParseByteByByte(kContentLengthPost), whole);
}

TEST(HttpParserTest, ChunkedPostInEveryByteSplit) {
  const Parsed whole = ParseWhole(kChunkedPost);
  ASSERT_EQ(whole.result, Result::kDone) << ::testing::PrintToString(whole);
  EXPECT_EQ(whole.consumed, kChunkedPost.size());
  EXPECT_EQ(whole.body, "{\"coil_id\":\"K1\",\"seq\":1234}    ");
  EXPECT_EQ(ParseByteByByte(kChunkedPost), whole);
}

// Two calls on a fresh parser: a prefix of every length, then the whole.
TEST(HttpParserTest, EveryTwoPieceSplitGivesTheSameRequest) {
  for (const std::string& data : {kContentLengthPost, kChunkedPost}) {
    const Parsed whole = ParseWhole(data);
    ASSERT_EQ(whole.result, Result::kDone);
    for (size_t k = 0; k < data.size(); ++k) {
      RequestParser p;
      const Result first = p.Parse(std::string_view(data).substr(0, k));
      ASSERT_EQ(first, Result::kNeedMore) << "prefix " << k;
      const Result second = p.Parse(data);
      EXPECT_EQ(Snapshot(p, second), whole) << "split at " << k;
    }
  }
}

// Extra bytes after the request (the next one) do not change it.
TEST(HttpParserTest, TrailingBytesAreNotConsumed) {
  for (const std::string& data : {kContentLengthPost, kChunkedPost}) {
    const Parsed whole = ParseWhole(data);
    const Parsed more = ParseWhole(data + "GET / HTTP/1.1\r\n");
    EXPECT_EQ(more, whole);
    EXPECT_EQ(more.consumed, data.size());
  }
}

// ------------------------------------------------------------ keep-alive

TEST(HttpParserTest, KeepAlive) {
  const auto keep = [](const std::string& version,
                       const std::string& connection) {
    std::string data = "GET / " + version + "\r\nHost: x\r\n";
    if (!connection.empty()) data += "Connection: " + connection + "\r\n";
    data += "\r\n";
    RequestParser p;
    EXPECT_EQ(p.Parse(data), Result::kDone) << data;
    return p.keep_alive();
  };
  EXPECT_TRUE(keep("HTTP/1.1", ""));
  EXPECT_TRUE(keep("HTTP/1.1", "keep-alive"));
  EXPECT_FALSE(keep("HTTP/1.1", "close"));
  EXPECT_FALSE(keep("HTTP/1.1", "Close"));
  EXPECT_FALSE(keep("HTTP/1.1", "CLOSE"));
  // "close" as one option of the list (RFC 9112 9.6).
  EXPECT_FALSE(keep("HTTP/1.1", "keep-alive, close"));
  EXPECT_FALSE(keep("HTTP/1.1", "Upgrade,Close"));
  EXPECT_FALSE(keep("HTTP/1.0", ""));
  EXPECT_FALSE(keep("HTTP/1.0", "close"));
  EXPECT_TRUE(keep("HTTP/1.0", "keep-alive"));
  EXPECT_TRUE(keep("HTTP/1.0", "Keep-Alive"));
}

TEST(HttpParserTest, ResetRestoresTheKeepAliveDefault) {
  const std::string close =
      "GET / HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n";
  const std::string plain = "GET / HTTP/1.1\r\nHost: x\r\n\r\n";
  RequestParser p;
  ASSERT_EQ(p.Parse(close), Result::kDone);
  EXPECT_FALSE(p.keep_alive());
  p.Reset();
  ASSERT_EQ(p.Parse(plain), Result::kDone);
  EXPECT_TRUE(p.keep_alive());
}

// ------------------------------------------------------------ continue, HEAD

TEST(HttpParserTest, ExpectContinueAfterTheHead) {
  const std::string head =
      "POST /v1/coils HTTP/1.1\r\nHost: x\r\nExpect: 100-continue\r\n"
      "Content-Length: 4\r\n\r\n";
  RequestParser p;
  // Head not complete yet.
  EXPECT_EQ(p.Parse(std::string_view(head).substr(0, head.size() - 1)),
            Result::kNeedMore);
  EXPECT_FALSE(p.headers_done());
  EXPECT_FALSE(p.expects_continue());
  // Head complete, no body: the client waits for 100 Continue.
  EXPECT_EQ(p.Parse(head), Result::kNeedMore);
  EXPECT_TRUE(p.headers_done());
  EXPECT_TRUE(p.expects_continue());
  // Part of the body.
  EXPECT_EQ(p.Parse(head + "ab"), Result::kNeedMore);
  EXPECT_TRUE(p.headers_done());
  EXPECT_EQ(p.Parse(head + "abcd"), Result::kDone);
  EXPECT_EQ(p.request().body, "abcd");
  EXPECT_EQ(p.consumed(), head.size() + 4);
  // Reset forgets it.
  p.Reset();
  EXPECT_FALSE(p.expects_continue());
  EXPECT_FALSE(p.headers_done());
}

TEST(HttpParserTest, ExpectContinueCaseInsensitiveAndChunked) {
  const std::string head =
      "POST /v1/coils HTTP/1.1\r\nHost: x\r\nexpect: 100-Continue\r\n"
      "Transfer-Encoding: chunked\r\n\r\n";
  RequestParser p;
  EXPECT_EQ(p.Parse(head), Result::kNeedMore);
  EXPECT_TRUE(p.headers_done());
  EXPECT_TRUE(p.expects_continue());
}

TEST(HttpParserTest, NoContinueWithoutBodyOrWhenTheBodyIsIn) {
  {
    // Content-Length: 0: nothing to wait for.
    RequestParser p;
    EXPECT_EQ(p.Parse("POST /a HTTP/1.1\r\nHost: x\r\nExpect: 100-continue\r\n"
                      "Content-Length: 0\r\n\r\n"),
              Result::kDone);
    EXPECT_FALSE(p.expects_continue());
  }
  {
    // The body came with the head.
    RequestParser p;
    EXPECT_EQ(p.Parse("POST /a HTTP/1.1\r\nHost: x\r\nExpect: 100-continue\r\n"
                      "Content-Length: 2\r\n\r\nok"),
              Result::kDone);
    EXPECT_FALSE(p.expects_continue());
  }
  {
    // No Expect field.
    RequestParser p;
    EXPECT_EQ(
        p.Parse("POST /a HTTP/1.1\r\nHost: x\r\nContent-Length: 2\r\n\r\n"),
        Result::kNeedMore);
    EXPECT_TRUE(p.headers_done());
    EXPECT_FALSE(p.expects_continue());
  }
}

TEST(HttpParserTest, HeadRequest) {
  RequestParser p;
  ASSERT_EQ(p.Parse("HEAD /v1/wear HTTP/1.1\r\nHost: x\r\n\r\n"),
            Result::kDone);
  EXPECT_TRUE(p.head());
  EXPECT_EQ(p.request().method, "HEAD");
  EXPECT_EQ(p.request().path, "/v1/wear");
  p.Reset();
  ASSERT_EQ(p.Parse("GET /v1/wear HTTP/1.1\r\nHost: x\r\n\r\n"), Result::kDone);
  EXPECT_FALSE(p.head());
}

TEST(HttpParserTest, PostWithoutLengthHasNoBody) {
  const std::string data = "POST /v1/calibrations HTTP/1.1\r\nHost: x\r\n\r\n";
  RequestParser p;
  ASSERT_EQ(p.Parse(data), Result::kDone) << p.error_message();
  EXPECT_EQ(p.consumed(), data.size());
  EXPECT_EQ(p.request().method, "POST");
  EXPECT_TRUE(p.request().body.empty());
  // What follows is the next request, not a body.
  RequestParser q;
  ASSERT_EQ(q.Parse(data + "GET / HTTP/1.1\r\n\r\n"), Result::kDone);
  EXPECT_EQ(q.consumed(), data.size());
  EXPECT_TRUE(q.request().body.empty());
}

TEST(HttpParserTest, TransferEncodingIsCaseInsensitive) {
  const Parsed s = ParseWhole(
      "POST /a HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: Chunked\r\n\r\n"
      "2\r\nok\r\n0\r\n\r\n");
  ASSERT_EQ(s.result, Result::kDone);
  EXPECT_EQ(s.body, "ok");
}

TEST(HttpParserTest, UppercaseHexChunkSizes) {
  const std::string chunk(0x1A, 'z');
  const Parsed s = ParseWhole(
      "POST /a HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: "
      "chunked\r\n\r\n1A\r\n" +
      chunk + "\r\n0\r\n\r\n");
  ASSERT_EQ(s.result, Result::kDone);
  EXPECT_EQ(s.body, chunk);
}

// ------------------------------------------------------------ limits

TEST(HttpParserTest, RequestLineOverTheLimitIs414) {
  HttpParserLimits limits;
  limits.max_request_line = 64;
  const std::string ok =
      "GET /" + std::string(40, 'a') + " HTTP/1.1\r\nHost: x\r\n\r\n";
  EXPECT_EQ(ParseWhole(ok, limits).result, Result::kDone);
  const std::string line = "GET /" + std::string(200, 'a') + " HTTP/1.1";
  ExpectError(line + "\r\nHost: x\r\n\r\n", 414, limits);
  // Before the line ends: the parser does not wait for the CRLF.
  ExpectError(line, 414, limits);
  // Default limit.
  ExpectError("GET /" + std::string(9000, 'a') + " HTTP/1.1\r\n\r\n", 414);
  ExpectError("GET /" + std::string(9000, 'a'), 414);
}

// A request line of exactly the limit is accepted however it arrives, also
// when its CR and LF come in different reads.
TEST(HttpParserTest, RequestLineAtTheLimitInEverySplit) {
  HttpParserLimits limits;
  limits.max_request_line = 64;
  const std::string line = "GET /" + std::string(64 - 14, 'a') + " HTTP/1.1";
  ASSERT_EQ(line.size(), 64u);
  const std::string data = line + "\r\nHost: x\r\n\r\n";
  const Parsed whole = ParseWhole(data, limits);
  ASSERT_EQ(whole.result, Result::kDone) << ::testing::PrintToString(whole);
  EXPECT_EQ(ParseByteByByte(data, limits), whole);
}

TEST(HttpParserTest, TooManyHeaderFieldsIs431) {
  HttpParserLimits limits;
  limits.max_header_count = 8;
  const auto request = [](int fields) {
    std::string data = "GET / HTTP/1.1\r\nHost: x\r\n";
    for (int i = 1; i < fields; ++i) {
      data += "X-F" + std::to_string(i) + ": v\r\n";
    }
    return data + "\r\n";
  };
  const Parsed s = ParseWhole(request(8), limits);
  ASSERT_EQ(s.result, Result::kDone);
  EXPECT_EQ(s.headers.size(), 8u);
  ExpectError(request(9), 431, limits);
  ExpectError(request(200), 431, limits);
  // Default limit: 64.
  EXPECT_EQ(ParseWhole(request(64)).result, Result::kDone);
  ExpectError(request(65), 431);
  ExpectError(request(1000), 431);
}

TEST(HttpParserTest, HeaderBytesOverTheLimitAre431) {
  HttpParserLimits limits;
  limits.max_header_bytes = 1024;
  const std::string small =
      "GET / HTTP/1.1\r\nHost: x\r\nX-A: " + std::string(500, 'v') + "\r\n\r\n";
  EXPECT_EQ(ParseWhole(small, limits).result, Result::kDone);
  ExpectError("GET / HTTP/1.1\r\nHost: x\r\nX-A: " + std::string(2000, 'v') +
                  "\r\n\r\n",
              431, limits);
  // Over the limit in several fields.
  std::string several = "GET / HTTP/1.1\r\nHost: x\r\n";
  for (int i = 0; i < 4; ++i) {
    several += "X-" + std::to_string(i) + ": " + std::string(400, 'v') + "\r\n";
  }
  ExpectError(several + "\r\n", 431, limits);
  // Before the field section ends.
  ExpectError(several, 431, limits);
  // Default limit (32 KiB), field section not finished.
  ExpectError("GET / HTTP/1.1\r\nX-A: " + std::string(40 * 1024, 'v'), 431);
}

TEST(HttpParserTest, ContentLengthOverTheLimitIs413OnTheHead) {
  HttpParserLimits limits;
  limits.max_body_bytes = 1000;
  EXPECT_EQ(
      ParseWhole("POST / HTTP/1.1\r\nHost: x\r\nContent-Length: 1000\r\n\r\n" +
                     std::string(1000, 'b'),
                 limits)
          .result,
      Result::kDone);
  // No body sent: the head alone is refused.
  ExpectError("POST / HTTP/1.1\r\nHost: x\r\nContent-Length: 1001\r\n\r\n", 413,
              limits);
  ExpectError("POST / HTTP/1.1\r\nHost: x\r\nContent-Length: 1048577\r\n\r\n",
              413);
  EXPECT_EQ(ParseWhole(
                "POST / HTTP/1.1\r\nHost: x\r\nContent-Length: 1048576\r\n\r\n")
                .result,
            Result::kNeedMore);
}

TEST(HttpParserTest, ChunkedBodyOverTheLimitIs413) {
  HttpParserLimits limits;
  limits.max_body_bytes = 1000;
  const std::string head =
      "POST / HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n";
  const std::string chunk = "258\r\n" + std::string(600, 'c') + "\r\n";
  EXPECT_EQ(ParseWhole(head + chunk + "0\r\n\r\n", limits).result,
            Result::kDone);
  ExpectError(head + chunk + chunk + "0\r\n\r\n", 413, limits);
  // One chunk announced larger than the limit, its data not sent.
  ExpectError(head + "3e9\r\n", 413, limits);
  // Fed byte by byte, the error comes at the latest with the body's end.
  const std::string data = head + chunk + chunk + "0\r\n\r\n";
  RequestParser p(limits);
  Result r = Result::kNeedMore;
  for (size_t n = 1; n <= data.size() && r == Result::kNeedMore; ++n) {
    r = p.Parse(std::string_view(data).substr(0, n));
  }
  ASSERT_EQ(r, Result::kError);
  EXPECT_EQ(p.error_status(), 413);
}

// A long chunk extension gets the same answer in one piece and in many.
TEST(HttpParserTest, LongChunkExtensionInEverySplit) {
  const std::string data =
      "POST / HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n"
      "2;ext=" +
      std::string(1100, 'e') + "\r\nok\r\n0\r\n\r\n";
  const Parsed whole = ParseWhole(data);
  EXPECT_EQ(ParseGrowing(data), whole);
}

// Chunk framing counts against the wire limit: a body far below the body
// limit, sent one byte per chunk with long extensions, is a 413 once its
// framing passes MaxChunkedWireBytes; the same body in one chunk is fine.
TEST(HttpParserTest, ChunkFramingOverTheWireLimitIs413) {
  HttpParserLimits limits;
  limits.max_body_bytes = 256;
  ASSERT_EQ(MaxChunkedWireBytes(limits), 2 * 256 + 65536u);
  const std::string head =
      "POST / HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n";
  std::string framed = head;
  for (int i = 0; i < 200; ++i) {
    framed += "1;" + std::string(1000, 'x') + "\r\nA\r\n";
  }
  framed += "0\r\n\r\n";
  ASSERT_GT(framed.size() - head.size(), MaxChunkedWireBytes(limits));
  const Parsed whole = ParseWhole(framed, limits);
  EXPECT_EQ(whole.result, Result::kError);
  EXPECT_EQ(whole.error_status, 413);
  EXPECT_EQ(ParseGrowing(framed, limits), whole);

  const std::string plain =
      head + "c8\r\n" + std::string(200, 'A') + "\r\n0\r\n\r\n";
  const Parsed ok = ParseWhole(plain, limits);
  ASSERT_EQ(ok.result, Result::kDone);
  EXPECT_EQ(ok.body, std::string(200, 'A'));
  // Whatever the parser can need before it answers stays below the
  // server's read cap.
  EXPECT_GE(MaxRequestBytes(limits), limits.max_request_line +
                                         limits.max_header_bytes +
                                         MaxChunkedWireBytes(limits));
}

TEST(HttpParserTest, ChunkSizeOverflowIsAnError) {
  RequestParser p;
  ASSERT_EQ(
      p.Parse("POST / HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n"
              "10000000000000001\r\nx\r\n0\r\n\r\n"),
      Result::kError);
  EXPECT_TRUE(p.error_status() == 400 || p.error_status() == 413)
      << p.error_status();
}

// ------------------------------------------------------------ smuggling

TEST(HttpParserTest, ContentLengthAndTransferEncodingIs400) {
  ExpectError(
      "POST / HTTP/1.1\r\nContent-Length: 3\r\nTransfer-Encoding: chunked\r\n"
      "\r\n3\r\nabc\r\n0\r\n\r\n",
      400);
  ExpectError(
      "POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\nContent-Length: 3\r\n"
      "\r\n3\r\nabc\r\n0\r\n\r\n",
      400);
}

TEST(HttpParserTest, TwoDifferentContentLengthsAre400) {
  ExpectError(
      "POST / HTTP/1.1\r\nContent-Length: 3\r\nContent-Length: 4\r\n\r\nabcd",
      400);
  ExpectError("POST / HTTP/1.1\r\nContent-Length: 3, 4\r\n\r\nabcd", 400);
}

TEST(HttpParserTest, BadContentLengthIs400) {
  for (const char* value :
       {"abc", "-1", "+5", "5a", "0x10", "1 2", "", "99999999999999999999999",
        "18446744073709551616", "1.5"}) {
    ExpectError(std::string("POST / HTTP/1.1\r\nContent-Length: ") + value +
                    "\r\n\r\nabcde",
                400);
  }
}

TEST(HttpParserTest, WhiteSpaceBeforeTheColonIs400) {
  ExpectError("GET / HTTP/1.1\r\nHost : x\r\n\r\n", 400);
  ExpectError("GET / HTTP/1.1\r\nHost\t: x\r\n\r\n", 400);
  ExpectError("POST / HTTP/1.1\r\nContent-Length : 3\r\n\r\nabc", 400);
}

TEST(HttpParserTest, ObsoleteLineFoldingIs400) {
  ExpectError("GET / HTTP/1.1\r\nX-A: one\r\n two\r\n\r\n", 400);
  ExpectError("GET / HTTP/1.1\r\nX-A: one\r\n\ttwo\r\n\r\n", 400);
  // White space before the first field.
  ExpectError("GET / HTTP/1.1\r\n Host: x\r\n\r\n", 400);
}

TEST(HttpParserTest, FieldWithoutColonOrNameIs400) {
  ExpectError("GET / HTTP/1.1\r\nNoColon\r\n\r\n", 400);
  ExpectError("GET / HTTP/1.1\r\n: value\r\n\r\n", 400);
}

TEST(HttpParserTest, UnknownTransferCodingIs501) {
  ExpectError("POST / HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: gzip\r\n\r\n",
              501);
  ExpectError(
      "POST / HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: gzip, chunked\r\n\r\n",
      501);
}

TEST(HttpParserTest, UnsupportedVersionIs505) {
  ExpectError("GET / HTTP/2.0\r\nHost: x\r\n\r\n", 505);
  ExpectError("GET / HTTP/1.2\r\nHost: x\r\n\r\n", 505);
  ExpectError("GET / HTTP/3.0\r\nHost: x\r\n\r\n", 505);
}

TEST(HttpParserTest, GarbageRequestLineIs400) {
  for (const char* data : {
           "HELLO\r\n\r\n",
           "GET\r\n\r\n",
           "GET /\r\n\r\n",
           "GET  / HTTP/1.1\r\n\r\n",
           "GET / HTTP/1.1 extra\r\n\r\n",
           "GET / FTP/1.1\r\n\r\n",
           "GET / HTTP/1\r\n\r\n",
           "GET / HTTP/x.y\r\n\r\n",
           "G\x01T / HTTP/1.1\r\n\r\n",
           "GET / HTTP/1.1x\r\n\r\n",
       }) {
    ExpectError(data, 400);
  }
}

TEST(HttpParserTest, BadChunkSizeIs400) {
  const std::string head =
      "POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n";
  ExpectError(head + "zz\r\nab\r\n0\r\n\r\n", 400);
  ExpectError(head + "\r\nab\r\n0\r\n\r\n", 400);
  ExpectError(head + "-2\r\nab\r\n0\r\n\r\n", 400);
  ExpectError(head + "0x2\r\nab\r\n0\r\n\r\n", 400);
  // Chunk data not followed by CRLF.
  ExpectError(head + "2\r\nabX\r\n0\r\n\r\n", 400);
}

TEST(HttpParserTest, MalformedPercentEscapeIs400) {
  ExpectError("GET /a%zz HTTP/1.1\r\n\r\n", 400);
  ExpectError("GET /a%2 HTTP/1.1\r\n\r\n", 400);
  ExpectError("GET /a% HTTP/1.1\r\n\r\n", 400);
  ExpectError("GET /a?q=%g1 HTTP/1.1\r\n\r\n", 400);
}

TEST(HttpParserTest, BareLfOrCrIs400) {
  ExpectError("GET / HTTP/1.1\nHost: x\n\n", 400);
  ExpectError("GET / HTTP/1.1\r\nHost: x\n\r\n", 400);
  ExpectError("GET / HTTP/1.1\r\nHost: x\r\n\n", 400);
  ExpectError("GET / HTTP/1.1\r\nHost: x\ry: z\r\n\r\n", 400);
  ExpectError("GET / HTTP/1.1\rHost: x\r\n\r\n", 400);
  // In the chunked framing and the trailer section too.
  const std::string chunked =
      "POST / HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n";
  ExpectError(chunked + "2\nok\r\n0\r\n\r\n", 400);
  ExpectError(chunked + "2\r\nok\r\n0\r\nX-T: a\nb\r\n\r\n", 400);
  ExpectError(chunked + "2\r\nok\r\n0\r\nX-T: a\rb\r\n\r\n", 400);
}

// The status of an error does not depend on how the bytes arrive (found by
// fuzz_http_parser: a limit checked on the whole head, a stray byte checked
// as it arrives).
TEST(HttpParserTest, ErrorStatusDoesNotDependOnTheSplit) {
  HttpParserLimits limits;
  limits.max_request_line = 35;
  limits.max_header_count = 2;
  struct Case {
    const char* name;
    std::string data;
  };
  const Case cases[] = {
      {"bare LF in the field over the count limit",
       "GET /a HTTP/1.1\r\nHost: x\r\nX-A: 1\r\nX-B: 2\nX-C: 3\r\n\r\n"},
      {"bare LF in an over-long request line",
       "GET /" + std::string(60, 'a') + "\nX HTTP/1.1\r\nHost: x\r\n\r\n"},
  };
  for (const Case& c : cases) {
    const Parsed whole = ParseWhole(c.data, limits);
    ASSERT_EQ(whole.result, Result::kError) << c.name;
    RequestParser p(limits);
    Result r = Result::kNeedMore;
    for (size_t n = 1; n <= c.data.size() && r == Result::kNeedMore; ++n) {
      r = p.Parse(std::string_view(c.data).substr(0, n));
    }
    ASSERT_EQ(r, Result::kError) << c.name;
    EXPECT_EQ(p.error_status(), whole.error_status)
        << c.name << ": byte by byte '" << p.error_message() << "', whole '"
        << whole.error_message << "'";
  }
}

// ------------------------------------------------------------ linear work

TEST(HttpParserTest, LargeFieldSectionByteByByte) {
  std::string data = "GET /big HTTP/1.1\r\nHost: x\r\n";
  int fields = 0;
  while (data.size() < 31 * 1024) {
    data += "X-F" + std::to_string(fields++) + ": " + std::string(700, 'v') +
            "\r\n";
  }
  data += "\r\n";
  HttpParserLimits limits;
  limits.max_header_bytes = 64 * 1024;
  const Parsed s = ParseByteByByte(data, limits);
  ASSERT_EQ(s.result, Result::kDone);
  EXPECT_EQ(s.consumed, data.size());
  EXPECT_EQ(s.path, "/big");
  EXPECT_EQ(s.headers.size(), static_cast<size_t>(fields) + 1);
  EXPECT_EQ(s.headers.back().second, std::string(700, 'v'));
}

TEST(HttpParserTest, LargeChunkedBodyByteByByte) {
  std::string data =
      "POST /big HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n";
  std::string body;
  for (int i = 0; i < 64; ++i) {
    const std::string chunk(500, static_cast<char>('a' + i % 26));
    char size[32];
    std::snprintf(size, sizeof(size), "%zx", chunk.size());
    data += std::string(size) + "\r\n" + chunk + "\r\n";
    body += chunk;
  }
  data += "0\r\n\r\n";
  const Parsed s = ParseByteByByte(data);
  ASSERT_EQ(s.result, Result::kDone);
  EXPECT_EQ(s.body, body);
}

}  // namespace
}  // namespace rollwear::api

namespace rollwear::api {
namespace {

// "close" in any Connection line wins over "keep-alive" in another.
TEST(HttpParserReviewTest, CloseWinsAcrossConnectionLines) {
  for (const char* data :
       {"GET / HTTP/1.1\r\nHost: x\r\nConnection: close\r\n"
        "Connection: keep-alive\r\n\r\n",
        "GET / HTTP/1.1\r\nHost: x\r\nConnection: keep-alive\r\n"
        "Connection: close\r\n\r\n",
        "GET / HTTP/1.0\r\nConnection: keep-alive, close\r\n\r\n"}) {
    RequestParser p;
    ASSERT_EQ(p.Parse(data), RequestParser::Result::kDone) << data;
    EXPECT_FALSE(p.keep_alive()) << data;
  }
}

// RFC 9112 6.1: chunked framing on HTTP/1.0 is faulty; RFC 9110 10.1.1: an
// HTTP/1.0 client's Expect is ignored.
TEST(HttpParserReviewTest, Http10ChunkedIs400AndExpectIsIgnored) {
  ExpectError(
      "POST / HTTP/1.0\r\nTransfer-Encoding: chunked\r\n\r\n3\r\nabc\r\n0\r\n"
      "\r\n",
      400);
  RequestParser p;
  ASSERT_EQ(p.Parse("POST / HTTP/1.0\r\nExpect: 100-continue\r\n"
                    "Content-Length: 3\r\n\r\n"),
            RequestParser::Result::kNeedMore);
  EXPECT_TRUE(p.headers_done());
  EXPECT_FALSE(p.expects_continue());
  EXPECT_TRUE(p.http10());
}

// After the hex digits of a chunk size only blanks and ";" may follow.
TEST(HttpParserReviewTest, JunkAfterAChunkSizeIs400) {
  const std::string head =
      "POST / HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n";
  for (const char* line : {"5 xyz", "5\tfoo", "5 5", "5x"}) {
    ExpectError(head + line + "\r\nhello\r\n0\r\n\r\n", 400);
  }
  for (const char* line : {"5", "5 ", "5 ;a=b", "5;a", "5\t; q=\"x\""}) {
    RequestParser p;
    const std::string data = head + line + "\r\nhello\r\n0\r\n\r\n";
    ASSERT_EQ(p.Parse(data), RequestParser::Result::kDone) << line;
    EXPECT_EQ(p.request().body, "hello") << line;
  }
}

}  // namespace
}  // namespace rollwear::api

namespace rollwear::api {
namespace {

// The fuzzer's find: a trailer section ending at the limit, or one byte
// below it, gets the same answer in one piece and byte by byte.
TEST(HttpParserReviewTest, TrailerAtTheLimitInEverySplit) {
  HttpParserLimits limits;
  limits.max_header_bytes = 1024;
  for (size_t line = 1015; line <= 1026; ++line) {
    const std::string data =
        "POST /a HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n"
        "0\r\nX:" +
        std::string(line - 2, 'a') + "\r\n\r\n";
    const Parsed whole = ParseWhole(data, limits);
    EXPECT_EQ(ParseGrowing(data, limits), whole)
        << "trailer line of " << line << " bytes";
    // Short trailers pass, long ones are 431.
    if (line + 2 <= 1024) {
      EXPECT_EQ(whole.result, Result::kDone) << line;
    }
    if (line > 1024) {
      EXPECT_EQ(whole.error_status, 431) << line;
    }
  }
}

}  // namespace
}  // namespace rollwear::api
