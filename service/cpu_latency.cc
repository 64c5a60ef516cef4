#include "service/cpu_latency.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

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
    if (err == EACCES || err == EPERM) {
      hint =
          " (the device is root's, mode 0600: run as root or grant write "
          "access, see docs/operations.md#cpu-wake-up-latency)";
    }
    return Status::IoError(
        device + ": cannot open for writing: " + std::strerror(err) + hint);
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

// Touch() and the release check use sequentially consistent operations on
// last_touch_ns_ and engaged_: either Touch() sees engaged_ == false (and
// then writes the limit under mu_, after the releaser is done), or its
// store of last_touch_ns_ precedes the releaser's read of it, so the
// releaser keeps the limit. A request arriving as the limit is released
// therefore never finds it released for good.
void CpuLatencyHold::Touch() {
  last_touch_ns_.store(NowNs());
  if (engaged_.load()) return;
  std::lock_guard<std::mutex> lock(mu_);
  if (engaged_.load()) return;
  if (WriteValue(limit_us_)) {
    engaged_.store(true);
    engagements_.fetch_add(1);
  }
}

void CpuLatencyHold::ReleaseLoop() {
  const auto poll = std::clamp(release_after_ / 4, std::chrono::milliseconds(5),
                               std::chrono::milliseconds(1000));
  const int64_t release_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(release_after_)
          .count();
  std::unique_lock<std::mutex> lock(mu_);
  while (!stop_) {
    cv_.wait_for(lock, poll);
    if (stop_ || !engaged_.load()) continue;
    engaged_.store(false);
    if (NowNs() - last_touch_ns_.load() < release_ns) {
      engaged_.store(true);  // still busy: nothing was written
      continue;
    }
    if (WriteValue(kNoConstraint)) {
      releases_.fetch_add(1);
    } else {
      engaged_.store(true);  // keep trying on the next round
    }
  }
}

}  // namespace rollwear::service
