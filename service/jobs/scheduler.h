// Scheduler: the daemon's calibration work (the diagnoses run beside it,
// in engine/diagnosis_jobs.h).
//   - a job worker thread that runs queued calibration runs
//     (engine::CalibrationRuns::Run) one at a time, in submission order;
//   - a nightly trigger that, at the configured local time of day, queues a
//     calibration only when measurements arrived since the last run
//     (StoreCounters::measurements_since_last_calibration > 0).
// The clock is injectable and Tick() evaluates the trigger at a given time,
// so tests need neither real nights nor sleeps.
//
// Thread-safety: Submit(), Tick() and the accessors are thread-safe;
// Start()/Stop() are called from one controlling thread. Stop() waits for a
// running calibration to finish (a run cannot be interrupted) and abandons
// the queued ones, which stay queued in the store and are picked up by
// Start() of the next process.
#ifndef ROLLWEAR_SERVICE_JOBS_SCHEDULER_H_
#define ROLLWEAR_SERVICE_JOBS_SCHEDULER_H_

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>

#include "core/dataset/dataset.h"
#include "core/model/wear_law.h"
#include "engine/calibration_runs.h"
#include "storage/mill_store.h"

namespace rollwear::service {

struct SchedulerOptions {
  // Minutes after local midnight of the nightly trigger; -1 = no trigger.
  int recalibration_minute = 2 * 60;
  // Law and K option of nightly runs.
  WearLaw law = WearLaw::kWang;
  int option = 1;
  // Current time; default the system clock.
  std::function<UnixSeconds()> now;
  // How often the timer thread evaluates the trigger.
  std::chrono::milliseconds poll_interval{1000};
};

// The first time strictly after `now` at which the local wall clock
// (the process's TZ) shows `minute_of_day`; DST gaps resolve as mktime does.
UnixSeconds NextLocalTime(UnixSeconds now, int minute_of_day);

class Scheduler {
 public:
  // Called on the worker thread after every run with the final record and
  // the wall time the run took.
  using Finished =
      std::function<void(const storage::CalibrationRecord&, double seconds)>;

  // `store` and `runs` (the engine's, on that store) must outlive the
  // scheduler.
  Scheduler(storage::MillStore* store, engine::CalibrationRuns* runs,
            SchedulerOptions options, Finished on_finished = nullptr);
  ~Scheduler();

  Scheduler(const Scheduler&) = delete;
  Scheduler& operator=(const Scheduler&) = delete;

  // Starts the worker and timer threads and re-submits the runs a previous
  // process left queued.
  void Start();
  void Stop();

  // Hands a queued run (from MillStore::EnqueueCalibration) to the worker.
  void Submit(int64_t id);

  // Evaluates the nightly trigger at `now`: when the due time has come,
  // queues and submits a "nightly" run if measurements arrived since the
  // last run, and moves the due time to the next day. Returns the queued id,
  // or 0. The first call only sets the due time.
  int64_t Tick(UnixSeconds now);

  // Next due time of the nightly trigger (0 before the first Tick).
  UnixSeconds next_due() const;
  // Blocks until no run is queued or running, or `timeout` passes; true
  // when idle.
  bool WaitIdle(std::chrono::milliseconds timeout);

 private:
  void WorkerLoop();
  void TimerLoop();
  UnixSeconds Now() const;

  storage::MillStore* store_;
  engine::CalibrationRuns* runs_;
  SchedulerOptions options_;
  Finished on_finished_;

  mutable std::mutex mu_;
  std::condition_variable work_cv_;   // worker: new job or stop
  std::condition_variable idle_cv_;   // WaitIdle: job finished
  std::condition_variable timer_cv_;  // timer: stop
  std::deque<int64_t> queue_;
  bool running_job_ = false;
  bool stopping_ = false;
  bool started_ = false;
  UnixSeconds next_due_ = 0;

  std::thread worker_;
  std::thread timer_;
};

}  // namespace rollwear::service

#endif  // ROLLWEAR_SERVICE_JOBS_SCHEDULER_H_
