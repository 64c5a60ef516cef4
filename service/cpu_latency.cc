#include "service/cpu_latency.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <spdlog/spdlog.h>

namespace rollwear::service {
namespace {

// PM_QOS_DEFAULT_VALUE of include/linux/pm_qos.h: the request asks for the
// constraint's default, i.e. no limit.
constexpr int32_t kNoConstraint = -1;

int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

StatusOr<std::unique_ptr<CpuLatencyHold>> CpuLatencyHold::Open(
    int limit_us, std::chrono::milliseconds release_after,
    const std::string& device) {
  if (limit_us < 0 || limit_us > 1000000) {
    return Status::InvalidArgument(
        "cpu latency limit must be in [0, 1000000] us, got " +
        std::to_string(limit_us));
  }
  if (release_after.count() <= 0) {
    return Status::InvalidArgument("cpu latency release delay must be > 0");
  }
  const int fd = open(device.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    std::string hint;
    if (err == EACCES) {
      hint =
          "the device is root's, mode 0600: run as root or grant write "
          "access";
    } else if (err == ENOENT) {
      hint =
          "no such device in this /dev: a private /dev (systemd's "
          "PrivateDevices=yes) or a container";
    } else if (err == EPERM) {
      hint =
          "refused by the device policy (systemd's DevicePolicy= / "
          "DeviceAllow=)";
    }
    return Status::IoError(device +
                           ": cannot open for writing: " + std::strerror(err) +
                           (hint.empty() ? "" : " (" + hint + ")") +
                           "; see docs/operations.md#cpu-wake-up-latency");
  }
  return std::unique_ptr<CpuLatencyHold>(
      new CpuLatencyHold(fd, limit_us, release_after));
}

CpuLatencyHold::CpuLatencyHold(int fd, int limit_us,
                               std::chrono::milliseconds release_after)
    : fd_(fd), limit_us_(limit_us), release_after_(release_after) {
  releaser_ = std::thread([this] { ReleaseLoop(); });
}

CpuLatencyHold::~CpuLatencyHold() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
  }
  cv_.notify_all();
  releaser_.join();
  close(fd_);  // removes the request
}

bool CpuLatencyHold::WriteValue(int32_t value) {
  ssize_t n;
  do {
    n = write(fd_, &value, sizeof(value));
  } while (n < 0 && errno == EINTR);
  return n == static_cast<ssize_t>(sizeof(value));
}

// Touch() and ReleaseIfIdle() use sequentially consistent operations on
// last_touch_ns_ and engaged_. A release first sees the last touch old
// enough, then stores engaged_ = false and reads last_touch_ns_ again:
// either Touch() sees engaged_ == false (and then writes the limit under
// mu_, after the release is done), or its store of last_touch_ns_ precedes
// that second read, so the limit is kept. Caveat: a Touch() preempted
// between reading the clock and storing it for longer than release_after
// may find the limit released just after it returns; the next Touch()
// takes it again.
void CpuLatencyHold::Touch() {
  last_touch_ns_.store(NowNs());
  if (engaged_.load()) return;
  std::lock_guard<std::mutex> lock(mu_);
  if (engaged_.load()) return;
  if (WriteValue(limit_us_)) {
    engaged_.store(true);
    engagements_.fetch_add(1);
  } else if (!write_failed_.exchange(true)) {
    // Once: the next Touch() tries again, and a log line per request
    // would flood the log.
    spdlog::warn("cpu wake-up latency limit: write failed: {}",
                 std::strerror(errno));
  }
}

bool CpuLatencyHold::ReleaseIfIdle(int64_t now_ns) {
  std::lock_guard<std::mutex> lock(mu_);
  return ReleaseIfIdleLocked(now_ns);
}

bool CpuLatencyHold::ReleaseIfIdleLocked(int64_t now_ns) {
  const int64_t release_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(release_after_)
          .count();
  // Busy (the common case): nothing changes, engaged_ never flickers.
  if (!engaged_.load() || now_ns - last_touch_ns_.load() < release_ns) {
    return false;
  }
  engaged_.store(false);
  if (now_ns - last_touch_ns_.load() < release_ns) {
    engaged_.store(true);  // a request came in meanwhile: nothing written
    return false;
  }
  if (!WriteValue(kNoConstraint)) {
    engaged_.store(true);  // keep trying on the next round
    return false;
  }
  releases_.fetch_add(1);
  return true;
}

void CpuLatencyHold::ReleaseLoop() {
  const auto poll = std::clamp(release_after_ / 4, std::chrono::milliseconds(5),
                               std::chrono::milliseconds(1000));
  std::unique_lock<std::mutex> lock(mu_);
  while (!stop_) {
    cv_.wait_for(lock, poll);
    if (!stop_) ReleaseIfIdleLocked(NowNs());
  }
}

}  // namespace rollwear::service
