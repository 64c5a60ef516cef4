// The client side of HTTP/1.1 framing (RFC 9112) for rollwear's own epoll
// clients (api/async_http_client.h, bench/load_client.h): an answer's head
// (status, Content-Length, chunked, Connection: close), a chunked body, and
// reading what a non-blocking socket holds.
//
// Thread-safety: pure functions (ReadAvailable acts on the socket given).
#ifndef ROLLWEAR_API_HTTP_ANSWER_H_
#define ROLLWEAR_API_HTTP_ANSWER_H_

#include <cstddef>
#include <string>
#include <string_view>

namespace rollwear::api {

// The head of an HTTP/1.1 answer at the start of a connection's input.
struct AnswerHead {
  int status = 0;
  size_t body_length = 0;  // Content-Length (0 when absent)
  size_t head_length = 0;  // up to and including the blank line
  bool close = false;      // "Connection: close"
  bool chunked = false;    // "Transfer-Encoding: chunked"
};
// Parses the head at the start of `in`; false while it is incomplete. Sets
// *bad when it cannot be an HTTP/1.x answer.
bool ParseAnswerHead(std::string_view in, AnswerHead* head, bool* bad);

// A chunked body starting at `in[start]`: 1 with the body in *body and the
// offset just past its end (trailers included) in *end; 0 while incomplete;
// -1 when the chunk framing is broken.
int ChunkedBody(std::string_view in, size_t start, std::string* body,
                size_t* end);

// Appends what the non-blocking socket `fd` holds to *in until a read would
// block; *closed when the peer has ended the stream (an answer and the FIN
// may come together: the answer is read first). 0, or the errno of a
// failed read (what was read before it is kept).
int ReadAvailable(int fd, std::string* in, bool* closed);

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_HTTP_ANSWER_H_
