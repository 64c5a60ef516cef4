#include "service/jobs/scheduler.h"

#include <algorithm>
#include <ctime>
#include <utility>
#include <vector>

#include "service/jobs/job_log.h"

namespace rollwear::service {

UnixSeconds NextLocalTime(UnixSeconds now, int minute_of_day) {
  const auto t = static_cast<time_t>(now);
  struct tm local;
  localtime_r(&t, &local);
  for (int day = 0; day < 3; ++day) {
    struct tm due = local;
    due.tm_mday += day;
    due.tm_hour = minute_of_day / 60;
    due.tm_min = minute_of_day % 60;
    due.tm_sec = 0;
    due.tm_isdst = -1;
    const time_t candidate = mktime(&due);
    if (candidate != static_cast<time_t>(-1) && candidate > t) {
      return static_cast<UnixSeconds>(candidate);
    }
  }
  return now + int64_t{24} * 3600;  // unreachable in practice
}

Scheduler::Scheduler(storage::MillStore* store, engine::CalibrationRuns* runs,
                     SchedulerOptions options, Finished on_finished)
    : store_(store),
      runs_(runs),
      options_(std::move(options)),
      on_finished_(std::move(on_finished)) {}

Scheduler::~Scheduler() { Stop(); }

UnixSeconds Scheduler::Now() const {
  if (options_.now) return options_.now();
  return std::chrono::duration_cast<std::chrono::seconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

void Scheduler::Start() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (started_) return;
    started_ = true;
    stopping_ = false;
  }
  // Runs a previous process queued but never ran, oldest first.
  std::vector<storage::CalibrationRecord> records =
      store_->ListCalibrations(1000);
  std::sort(records.begin(), records.end(),
            [](const auto& a, const auto& b) { return a.id < b.id; });
  for (const auto& r : records) {
    if (r.status == storage::CalibrationStatus::kQueued) Submit(r.id);
  }
  worker_ = std::thread([this] { WorkerLoop(); });
  if (options_.recalibration_minute >= 0) {
    Tick(Now());  // sets the first due time
    timer_ = std::thread([this] { TimerLoop(); });
  }
}

void Scheduler::Stop() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (!started_) return;
    stopping_ = true;
  }
  work_cv_.notify_all();
  timer_cv_.notify_all();
  if (timer_.joinable()) timer_.join();
  if (worker_.joinable()) worker_.join();
  std::lock_guard<std::mutex> lock(mu_);
  started_ = false;
  idle_cv_.notify_all();
}

void Scheduler::Submit(int64_t id) {
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (std::find(queue_.begin(), queue_.end(), id) != queue_.end()) return;
    queue_.push_back(id);
  }
  work_cv_.notify_one();
}

int64_t Scheduler::Tick(UnixSeconds now) {
  if (options_.recalibration_minute < 0) return 0;
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (next_due_ == 0) {
      next_due_ = NextLocalTime(now, options_.recalibration_minute);
      return 0;
    }
    if (now < next_due_) return 0;
    next_due_ = NextLocalTime(now, options_.recalibration_minute);
  }
  if (store_->Counters().measurements_since_last_calibration <= 0) return 0;
  // The recurrent network, once active, is retrained as such; otherwise the
  // configured law and option.
  StatusOr<storage::ModelVersion> active = store_->ActiveModel();
  const bool ann = active.ok() && active->wear_model.is_ann();
  // A model with adopted terms is recalibrated as its law with option 1, so
  // that the run refits the terms instead of replacing them.
  const bool terms = active.ok() && !ann && !active->wear_model.terms.empty();
  const ModelChoice model =
      ann     ? ModelChoice::Network()
      : terms ? ModelChoice::Law(active->wear_model.law, 1)
              : ModelChoice::Law(options_.law, options_.option);
  StatusOr<int64_t> id = store_->EnqueueCalibration("nightly", model);
  if (!id.ok()) return 0;
  LogCalibrationQueued(*id, "nightly");
  Submit(*id);
  return *id;
}

UnixSeconds Scheduler::next_due() const {
  std::lock_guard<std::mutex> lock(mu_);
  return next_due_;
}

bool Scheduler::WaitIdle(std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mu_);
  return idle_cv_.wait_for(lock, timeout, [this] {
    return (queue_.empty() && !running_job_) || !started_;
  });
}

void Scheduler::WorkerLoop() {
  std::unique_lock<std::mutex> lock(mu_);
  for (;;) {
    work_cv_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
    if (stopping_) break;
    const int64_t id = queue_.front();
    queue_.pop_front();
    running_job_ = true;
    lock.unlock();

    const auto start = std::chrono::steady_clock::now();
    const Status status = runs_->Run(id);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
            .count();
    StatusOr<storage::CalibrationRecord> record = store_->GetCalibration(id);
    if (on_finished_) {
      if (record.ok()) {
        on_finished_(*record, seconds);
      } else {
        storage::CalibrationRecord failed;
        failed.id = id;
        failed.status = storage::CalibrationStatus::kFailed;
        failed.message =
            status.ok() ? record.status().message() : status.message();
        on_finished_(failed, seconds);
      }
    }

    lock.lock();
    running_job_ = false;
    idle_cv_.notify_all();
  }
}

void Scheduler::TimerLoop() {
  std::unique_lock<std::mutex> lock(mu_);
  while (!stopping_) {
    timer_cv_.wait_for(lock, options_.poll_interval,
                       [this] { return stopping_; });
    if (stopping_) break;
    lock.unlock();
    Tick(Now());
    lock.lock();
  }
}

}  // namespace rollwear::service
