// The socket-level pieces of the epoll HTTP server (api/http_server.cc):
// the listening socket, peer address text, status reason phrases, the
// error answers the server gives before any handler runs, and the worker
// pool for requests that may block.
//
// Thread-safety: the functions are pure or act on the descriptors they are
// given; WorkerPool::Post may be called from any thread.
#ifndef ROLLWEAR_API_HTTP_WIRE_H_
#define ROLLWEAR_API_HTTP_WIRE_H_

#include <sys/socket.h>

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "api/router.h"
#include "core/base/status.h"

namespace rollwear::api {

// A non-blocking listening TCP socket bound to `address`:`port` (0 =
// ephemeral); *bound_port gets the port. SO_REUSEADDR only (no
// SO_REUSEPORT): a restarted daemon can rebind through TIME_WAIT, but two
// daemons never share a port.
StatusOr<int> ListenOn(const std::string& address, int port, int* bound_port);

// "127.0.0.1", "::1"; empty for other families.
std::string AddressText(const sockaddr_storage& addr);

// "OK", "Created", ... for the status line.
const char* ReasonPhrase(int status);

// The answer to a request the parser refused (400, 413, 414, 431, 501,
// 505), with the API's error body and `message` naming what was wrong.
HttpResponse ProtocolError(int status, const std::string& message);

// A 500 answer with the API's error body.
HttpResponse InternalError(const char* what);

// A fixed pool of threads running queued tasks in order. The destructor
// runs what is queued, then joins.
class WorkerPool {
 public:
  explicit WorkerPool(int threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  void Post(std::function<void()> task);

 private:
  void Run();

  std::mutex mu_;
  std::condition_variable cv_;
  std::deque<std::function<void()>> tasks_;
  bool stop_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_HTTP_WIRE_H_
