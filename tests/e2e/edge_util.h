// Helpers of the edge tests (nginx_test.cc, metrics_conventions_test.cc):
// whether an edge tool (nginx, promtool, openssl) is installed, skipping
// when it is not unless ROLLWEAR_REQUIRE_EDGE=1 (the CI phase "edge"), a
// free loopback port, and a real nginx started in the foreground from a
// config derived from deploy/nginx/rollwear.conf, killed with its workers
// when the object goes (also when a test fails).
//
// Thread-safety: test helpers; use from one thread.
#ifndef ROLLWEAR_TESTS_E2E_EDGE_UTIL_H_
#define ROLLWEAR_TESTS_E2E_EDGE_UTIL_H_

#include <memory>
#include <string>

#include "tests/e2e/e2e_util.h"

namespace rollwear::e2e {

// True when `path` is an executable file. Otherwise "" when the test
// should skip, or the failure message when ROLLWEAR_REQUIRE_EDGE=1.
bool EdgeToolPresent(const std::string& path, std::string* fail_message);

// A loopback TCP port that was free a moment ago.
int FreeLoopbackPort();

// deploy/nginx/rollwear.conf with the daemon's port, the HTTPS server on
// 127.0.0.1:`port` and the redirect server on 127.0.0.1:`redirect_port`.
// With `cert` and `key` the TLS lines stay (paths replaced); without, the
// server speaks plain HTTP (ssl lines dropped). "" with *error when the
// shipped file no longer has a line the derivation replaces.
std::string DeriveEdgeConfig(const std::string& shipped, int daemon_port,
                             int port, int redirect_port,
                             const std::string& cert, const std::string& key,
                             std::string* error);

// nginx -p `dir` with `site` (the derived rollwear.conf) in its http {}
// and every path (pid, logs, temp files) inside `dir`.
class EdgeNginx {
 public:
  EdgeNginx(const std::string& dir, const std::string& site);
  // SIGTERM (fast shutdown); after 10 s SIGKILL to the master and its
  // workers.
  ~EdgeNginx();
  EdgeNginx(const EdgeNginx&) = delete;
  EdgeNginx& operator=(const EdgeNginx&) = delete;

  // `nginx -t`: 0 when the configuration is valid (output in *output).
  int Test(std::string* output);
  // Starts in the foreground and waits until `port` answers; false with
  // the error log on failure.
  bool Start(int port, std::string* error);
  std::string ErrorLog() const;

 private:
  std::string dir_, conf_;
  std::unique_ptr<Subprocess> process_;
};

}  // namespace rollwear::e2e

#endif  // ROLLWEAR_TESTS_E2E_EDGE_UTIL_H_
