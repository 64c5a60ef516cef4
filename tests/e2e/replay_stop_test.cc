// End-to-end tests of `rollwear replay` stopping at once, with a non-zero
// exit and a message that says which, when no retry can help: nothing
// listens at the URL (connection refused), or the daemon answers 401
// because the token is missing. Retrying stays for a daemon that was
// answering (crash_test.cc). The bound of 10 s is generous: before, each
// request was retried for 60 s.
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>

#include <gtest/gtest.h>

#include "tests/e2e/e2e_util.h"

namespace rollwear::e2e {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// A loopback port bound but not listening: a connection to it is refused,
// and no other process can take the port while this object lives.
class RefusingPort {
 public:
  RefusingPort() {
    fd_ = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof(addr);
    if (fd_ >= 0 &&
        bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) == 0 &&
        getsockname(fd_, reinterpret_cast<sockaddr*>(&addr), &len) == 0) {
      port_ = ntohs(addr.sin_port);
    }
  }
  ~RefusingPort() {
    if (fd_ >= 0) close(fd_);
  }
  int port() const { return port_; }

 private:
  int fd_ = -1;
  int port_ = 0;
};

TEST(ReplayStopTest, StopsAtOnceOnARefusedConnection) {
  TempDir dir;
  std::string error;
  ASSERT_TRUE(Simulate(dir / "data", 2, 3, &error)) << error;
  RefusingPort refusing;
  ASSERT_GT(refusing.port(), 0);
  const std::string url = "http://127.0.0.1:" + std::to_string(refusing.port());
  std::string out, err;
  const auto start = Clock::now();
  const int code =
      RunRollwear({"replay", "--data", dir / "data", "--url", url, "--quiet"},
                  &out, &err, 60);
  const double seconds = SecondsSince(start);
  EXPECT_EQ(code, 1) << out << err;
  EXPECT_LT(seconds, 10.0) << out << err;
  EXPECT_NE(
      err.find("connection refused at " + url + ": is the daemon running?"),
      std::string::npos)
      << err;
  // Nothing was sent, and the summary says so.
  EXPECT_NE(out.find("replay: 0 coils"), std::string::npos) << out;
}

TEST(ReplayStopTest, StopsAtOnceOnA401AndStoresNothing) {
  TempDir dir;
  std::string error;
  ASSERT_TRUE(Simulate(dir / "data", 2, 3, &error)) << error;
  Daemon daemon(dir / "rollwear.db", dir / "serve.log", 0, {},
                {"ROLLWEAR_TOKEN=s3cret"});
  ASSERT_TRUE(daemon.Start(&error)) << error;
  std::string out, err;
  const auto start = Clock::now();
  // No --token and no ROLLWEAR_TOKEN in the replay's environment.
  const int code = RunRollwear(
      {"replay", "--data", dir / "data", "--url", daemon.url(), "--quiet"},
      &out, &err, 60);
  const double seconds = SecondsSince(start);
  EXPECT_EQ(code, 1) << out << err;
  EXPECT_LT(seconds, 10.0) << out << err;
  EXPECT_NE(err.find("401 unauthorized: set --token or ROLLWEAR_TOKEN"),
            std::string::npos)
      << err;
  const auto metrics = ScrapeMetrics(daemon.url());
  EXPECT_EQ(metrics.at("rollwear_coils_stored"), 0);
  EXPECT_EQ(metrics.at("rollwear_campaigns_stored"), 0);
}

}  // namespace
}  // namespace rollwear::e2e
