// service/cpu_latency: the CPU latency QoS hold, on a regular file (which
// records every value written, 4 bytes each) and, where this process may
// write it, on the kernel's /dev/cpu_dma_latency through the real daemon.
#include "service/cpu_latency.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "tests/e2e/e2e_util.h"

namespace rollwear::service {
namespace {

using std::chrono::milliseconds;

// The s32 values written to `path`, in order.
std::vector<int32_t> Written(const std::string& path) {
  const std::string bytes = e2e::ReadFile(path);
  std::vector<int32_t> values(bytes.size() / sizeof(int32_t));
  if (!values.empty()) {
    std::memcpy(values.data(), bytes.data(), values.size() * sizeof(int32_t));
  }
  return values;
}

// An empty regular file standing in for the device, in `dir`.
std::string FakeDevice(const e2e::TempDir& dir) {
  const std::string path = dir / "qos";
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f != nullptr) std::fclose(f);
  return path;
}

// Polls `done` for up to `limit`.
template <typename F>
bool WaitFor(F done, milliseconds limit) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (!done()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(milliseconds(2));
  }
  return true;
}

constexpr int64_t kHourNs = 3600LL * 1000 * 1000 * 1000;

// The hold's decisions at chosen times: a one-hour release delay keeps the
// background thread out of the way, so nothing depends on the test's pace.
TEST(CpuLatencyHoldTest, HoldsWhileTouchedAndReleasesWhenIdle) {
  e2e::TempDir dir;
  const std::string device = FakeDevice(dir);
  auto hold = CpuLatencyHold::Open(0, std::chrono::hours(1), device);
  ASSERT_TRUE(hold.ok()) << hold.status().ToString();
  CpuLatencyHold& h = **hold;
  EXPECT_FALSE(h.engaged());
  EXPECT_TRUE(Written(device).empty());  // opening asks for nothing
  EXPECT_FALSE(h.ReleaseIfIdle(h.last_touch_ns() + 2 * kHourNs));

  // A stream of requests: one write, held through.
  for (int i = 0; i < 100; ++i) {
    h.Touch();
    EXPECT_TRUE(h.engaged());
  }
  EXPECT_EQ(Written(device), std::vector<int32_t>({0}));
  EXPECT_EQ(h.engagements(), 1);

  // Still held just before the delay has passed since the last request,
  // released (PM_QOS_DEFAULT_VALUE, -1) once it has, and only once.
  const int64_t last = h.last_touch_ns();
  EXPECT_FALSE(h.ReleaseIfIdle(last + kHourNs - 1));
  EXPECT_TRUE(h.engaged());
  EXPECT_TRUE(h.ReleaseIfIdle(last + kHourNs));
  EXPECT_FALSE(h.engaged());
  EXPECT_FALSE(h.ReleaseIfIdle(last + 2 * kHourNs));
  EXPECT_EQ(Written(device), std::vector<int32_t>({0, -1}));
  EXPECT_EQ(h.releases(), 1);

  // The next request holds it again.
  h.Touch();
  EXPECT_TRUE(h.engaged());
  EXPECT_EQ(Written(device), std::vector<int32_t>({0, -1, 0}));
  EXPECT_EQ(h.engagements(), 2);
}

// The background thread releases by itself (no upper bound on when: the
// machine may be slow, only that it happens).
TEST(CpuLatencyHoldTest, BackgroundThreadReleasesAfterTheDelay) {
  e2e::TempDir dir;
  const std::string device = FakeDevice(dir);
  auto hold = CpuLatencyHold::Open(3, milliseconds(20), device);
  ASSERT_TRUE(hold.ok()) << hold.status().ToString();
  const auto touched = std::chrono::steady_clock::now();
  (*hold)->Touch();
  ASSERT_TRUE(
      WaitFor([&] { return (*hold)->releases() == 1; }, milliseconds(30000)));
  EXPECT_GE(std::chrono::steady_clock::now() - touched, milliseconds(20));
  EXPECT_FALSE((*hold)->engaged());
  EXPECT_EQ(Written(device), std::vector<int32_t>({3, -1}));
}

TEST(CpuLatencyHoldTest, ConcurrentTouchesWriteTheLimitOnce) {
  e2e::TempDir dir;
  const std::string device = FakeDevice(dir);
  auto hold = CpuLatencyHold::Open(25, milliseconds(60000), device);
  ASSERT_TRUE(hold.ok()) << hold.status().ToString();
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t) {
    threads.emplace_back([&] {
      for (int i = 0; i < 1000; ++i) (*hold)->Touch();
    });
  }
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(Written(device), std::vector<int32_t>({25}));
  EXPECT_EQ((*hold)->engagements(), 1);
}

TEST(CpuLatencyHoldTest, RefusesBadLimitsAndUnopenableDevices) {
  e2e::TempDir dir;
  auto bad = CpuLatencyHold::Open(-1, milliseconds(10), dir / "x");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().code(), StatusCode::kInvalidArgument);
  auto missing = CpuLatencyHold::Open(0, milliseconds(10), dir / "no/such");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.status().code(), StatusCode::kIoError);
  EXPECT_NE(missing.status().message().find(dir / "no/such"),
            std::string::npos);
  EXPECT_NE(missing.status().message().find("No such file"), std::string::npos)
      << missing.status().message();
  auto directory = CpuLatencyHold::Open(0, milliseconds(10), dir.path());
  ASSERT_FALSE(directory.ok());
  EXPECT_NE(directory.status().message().find("cannot open for writing"),
            std::string::npos);
}

// The kernel's aggregated CPU latency limit (a read of the device returns
// it as an s32); -1 when the device cannot be read.
int64_t KernelLimit() {
  const int fd = open(kCpuLatencyDevice, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return -1;
  int32_t value = 0;
  const ssize_t n = read(fd, &value, sizeof(value));
  close(fd);
  return n == sizeof(value) ? value : -1;
}

// The daemon with cpu_wakeup_latency_us set holds the limit once a request
// came in, and the kernel drops it when the daemon exits.
TEST(CpuLatencyHoldTest, DaemonHoldsTheKernelLimitWhileServing) {
  if (access(kCpuLatencyDevice, R_OK | W_OK) != 0) {
    GTEST_SKIP() << kCpuLatencyDevice << " is not readable and writable here";
  }
  constexpr int kLimitUs = 7;  // unusual: another holder would rarely ask
  const int64_t before = KernelLimit();
  if (before <= kLimitUs) {
    GTEST_SKIP() << "another holder already asks for " << before << " us";
  }
  e2e::TempDir dir;
  e2e::Daemon daemon(
      dir / "w.db", dir / "serve.log", 0, {},
      {"ROLLWEAR_CPU_WAKEUP_LATENCY_US=" + std::to_string(kLimitUs)});
  std::string error;
  ASSERT_TRUE(daemon.Start(&error)) << error;
  nlohmann::json body;
  ASSERT_EQ(e2e::HttpGet(daemon.url(), "/v1/wear", &body), 200);
  // The effective limit is the minimum over all holders: at most ours.
  EXPECT_LE(KernelLimit(), kLimitUs);
  EXPECT_GE(KernelLimit(), 0);
  EXPECT_EQ(daemon.Terminate(), 0);
  EXPECT_GT(KernelLimit(), kLimitUs);  // ours is gone
  EXPECT_NE(e2e::ReadFile(dir / "serve.log")
                .find("cpu wake-up latency limit 7 us held"),
            std::string::npos);
}

// A limit that cannot be held stops the start (exit 1) before the database
// is opened, and says why. Run as a user who may not write the device: this
// one, or nobody when this is root (a copy of the binary where nobody may
// run it).
TEST(CpuLatencyHoldTest, DaemonStopsWithNothingDoneWhenTheLimitCannotBeHeld) {
  e2e::TempDir dir;
  std::vector<std::string> argv;
  if (geteuid() == 0) {
    if (access("/usr/bin/setpriv", X_OK) != 0) {
      GTEST_SKIP() << "root, and no setpriv to drop to nobody";
    }
    ASSERT_EQ(chmod(dir.path().c_str(), 0755), 0);
    std::filesystem::copy_file(ROLLWEAR_BINARY, dir / "rollwear");
    ASSERT_EQ(chmod((dir / "rollwear").c_str(), 0755), 0);
    argv = {"/usr/bin/setpriv", "--reuid=65534", "--regid=65534",
            "--clear-groups", dir / "rollwear"};
  } else {
    if (access(kCpuLatencyDevice, W_OK) == 0) {
      GTEST_SKIP() << "this user may write " << kCpuLatencyDevice;
    }
    argv = {ROLLWEAR_BINARY};
  }
  for (const char* a : {"serve", "--db"}) argv.push_back(a);
  argv.push_back(dir / "w.db");
  e2e::Subprocess serve(argv, dir / "serve.log",
                        {"ROLLWEAR_CPU_WAKEUP_LATENCY_US=0"});
  EXPECT_EQ(serve.Wait(60), 1);
  const std::string log = e2e::ReadFile(dir / "serve.log");
  EXPECT_NE(log.find("rollwear serve: cpu_wakeup_latency_us=0: "
                     "/dev/cpu_dma_latency: cannot open for writing: "),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("docs/operations.md#cpu-wake-up-latency"),
            std::string::npos);
  EXPECT_EQ(access((dir / "w.db").c_str(), F_OK), -1);
}

TEST(CpuLatencyHoldTest, BadLimitIsAConfigurationError) {
  e2e::TempDir dir;
  e2e::Subprocess serve({ROLLWEAR_BINARY, "serve", "--db", dir / "w.db"},
                        dir / "serve.log",
                        {"ROLLWEAR_CPU_WAKEUP_LATENCY_US=fast"});
  EXPECT_EQ(serve.Wait(60), 2);
  EXPECT_NE(e2e::ReadFile(dir / "serve.log")
                .find("ROLLWEAR_CPU_WAKEUP_LATENCY_US: cpu_wakeup_latency_us: "
                      "must be an integer in [0, 1000000] or off, got 'fast'"),
            std::string::npos)
      << e2e::ReadFile(dir / "serve.log");
  EXPECT_EQ(access((dir / "w.db").c_str(), F_OK), -1);
}

}  // namespace
}  // namespace rollwear::service
