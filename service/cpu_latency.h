// CpuLatencyHold: keeps the CPUs out of slow idle states while the daemon is
// serving requests, through Linux's CPU latency QoS (the user-mode interface
// /dev/cpu_dma_latency of Documentation/power/pm_qos_interface.rst).
//
// Why: a request that arrives while a CPU is idle waits for that CPU to wake
// up. On bare metal a deep C-state costs tens to hundreds of microseconds;
// in a virtual machine an idle vCPU halts, and waking it is a VM exit that
// the host may schedule milliseconds later. At a paced 5,000 wear reads/s on
// the 2 vCPUs of the benchmark machine, those wake-ups put 1-20 % of the
// answers over 1 ms; with a 0 us limit held, the p99 fell to 0.1-0.3 ms
// (docs/performance.md). The price: while the request is held, idle CPUs
// poll instead of sleeping (power; in a VM, the host sees busy vCPUs).
//
// So the request is held only while there is traffic: the first Touch()
// after a quiet spell writes the limit, and a background thread, checking
// every release_after / 4 (at most every second), writes
// PM_QOS_DEFAULT_VALUE (-1, "no constraint from me") once no Touch() came
// for `release_after`. Closing the device (the destructor, or the process
// dying) removes the request.
//
// The kernel takes the limit as a 4-byte native-endian s32 written to the
// open device; the effective limit is the minimum over every holder, and a
// read returns it.
//
// Thread-safety: Touch(), ReleaseIfIdle() and the accessors may be called
// from any thread; the first Touch() after a release takes a mutex and
// makes one write(2). Construction and destruction are single-threaded, and
// no Touch() may race with or follow destruction (it would write to a
// closed descriptor): whoever calls Touch() must be gone first.
#ifndef ROLLWEAR_SERVICE_CPU_LATENCY_H_
#define ROLLWEAR_SERVICE_CPU_LATENCY_H_

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "core/base/status.h"

namespace rollwear::service {

inline constexpr const char* kCpuLatencyDevice = "/dev/cpu_dma_latency";

class CpuLatencyHold {
 public:
  // Opens `device` for writing (the request is registered, unconstrained,
  // until the first Touch()). `limit_us` in [0, 1e6]. Errors name the
  // device and the reason (no such file, permission denied: the device is
  // root's, mode 0600, by default).
  static StatusOr<std::unique_ptr<CpuLatencyHold>> Open(
      int limit_us, std::chrono::milliseconds release_after,
      const std::string& device = kCpuLatencyDevice);

  ~CpuLatencyHold();
  CpuLatencyHold(const CpuLatencyHold&) = delete;
  CpuLatencyHold& operator=(const CpuLatencyHold&) = delete;

  // Traffic arrived: hold the limit (writes it if released).
  void Touch();
  // Releases the limit when no Touch() came within `release_after` before
  // `now_ns` (steady_clock nanoseconds); true when it released. The
  // background thread calls it with the current time; tests may call it
  // with any time.
  bool ReleaseIfIdle(int64_t now_ns);
  // steady_clock nanoseconds of the last Touch().
  int64_t last_touch_ns() const { return last_touch_ns_.load(); }
  // Whether the limit is currently held.
  bool engaged() const { return engaged_.load(std::memory_order_acquire); }
  // Times the limit was written (engagements) and released.
  int64_t engagements() const { return engagements_.load(); }
  int64_t releases() const { return releases_.load(); }
  int limit_us() const { return limit_us_; }

 private:
  CpuLatencyHold(int fd, int limit_us, std::chrono::milliseconds release_after);
  void ReleaseLoop();
  bool ReleaseIfIdleLocked(int64_t now_ns);  // mu_ held
  bool WriteValue(int32_t value);

  const int fd_;
  const int limit_us_;
  const std::chrono::milliseconds release_after_;
  // steady_clock nanoseconds of the last Touch().
  std::atomic<int64_t> last_touch_ns_{0};
  std::atomic<bool> engaged_{false};
  std::atomic<int64_t> engagements_{0};
  std::atomic<int64_t> releases_{0};

  std::atomic<bool> write_failed_{false};  // a failed write was logged

  std::mutex mu_;  // serialises the writes and guards stop_
  std::condition_variable cv_;
  bool stop_ = false;
  std::thread releaser_;
};

}  // namespace rollwear::service

#endif  // ROLLWEAR_SERVICE_CPU_LATENCY_H_
