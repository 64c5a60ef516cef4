#include "engine/diagnosis_jobs.h"

#include <chrono>
#include <exception>
#include <string>
#include <utility>

#include "core/report/diagnosis_report.h"

namespace rollwear::engine {
namespace {

constexpr size_t kKeep = 50;  // reports kept in memory

UnixSeconds Now() {
  return std::chrono::duration_cast<std::chrono::seconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// What is stored of a finished job.
storage::StoredDiagnosis ToStored(const DiagnosisJob& job) {
  storage::StoredDiagnosis d;
  d.id = job.id;
  d.status = job.status;
  d.adopt = job.adopt;
  d.queued_at = job.queued_at;
  d.started_at = job.started_at;
  d.finished_at = job.finished_at;
  d.verdict = job.verdict;
  d.message = job.message;
  d.calibration_id = job.adoption ? job.adoption->id : 0;
  d.report_json = job.report;
  d.report_html = job.html;
  return d;
}

}  // namespace

DiagnosisJobs::DiagnosisJobs(storage::MillStore* store, CalibrationRuns* runs,
                             DiagnosisJobHooks hooks)
    : store_(store), runs_(runs), hooks_(std::move(hooks)) {
  // Ids go on after those stored by an earlier run of the daemon.
  StatusOr<int64_t> last = store_->LastDiagnosisId();
  if (last.ok()) next_id_ = *last + 1;
  worker_ = std::thread([this] { Work(); });
}

DiagnosisJobs::~DiagnosisJobs() { Stop(); }

void DiagnosisJobs::Stop() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
  }
  cv_.notify_all();
  if (worker_.joinable()) worker_.join();
}

int64_t DiagnosisJobs::Enqueue(bool adopt) {
  std::lock_guard<std::mutex> lock(mu_);
  const int64_t id = next_id_++;
  DiagnosisJob job;
  job.id = id;
  job.status = "queued";
  job.adopt = adopt;
  job.queued_at = Now();
  jobs_[id] = std::move(job);
  queue_.push_back(id);
  while (jobs_.size() > kKeep) jobs_.erase(jobs_.begin());
  cv_.notify_one();
  return id;
}

std::optional<DiagnosisJob> DiagnosisJobs::Get(int64_t id) const {
  std::lock_guard<std::mutex> lock(mu_);
  auto it = jobs_.find(id);
  if (it == jobs_.end()) return std::nullopt;
  return it->second;
}

void DiagnosisJobs::Work() {
  for (;;) {
    int64_t id = 0;
    bool adopt = false;
    UnixSeconds queued_at = 0, started_at = 0;
    {
      std::unique_lock<std::mutex> lock(mu_);
      cv_.wait(lock, [this] { return stop_ || !queue_.empty(); });
      if (stop_) return;
      id = queue_.front();
      queue_.pop_front();
      auto it = jobs_.find(id);
      if (it == jobs_.end()) continue;  // evicted before it ran
      it->second.status = "running";
      it->second.started_at = Now();
      adopt = it->second.adopt;
      queued_at = it->second.queued_at;
      started_at = it->second.started_at;
    }
    if (hooks_.on_started) hooks_.on_started(id, adopt);
    const auto start = std::chrono::steady_clock::now();
    DiagnosisJob result = Run(id, adopt);
    result.queued_at = queued_at;
    result.started_at = started_at;
    result.finished_at = Now();
    // Stored before it is shown finished, so a finished diagnosis is never
    // lost by a restart.
    Status saved = store_->SaveDiagnosis(ToStored(result));
    if (!saved.ok()) {
      result.message += (result.message.empty() ? "" : "; ") +
                        std::string("not stored: ") + saved.message();
    }
    if (hooks_.on_finished) {
      hooks_.on_finished(result, std::chrono::duration<double>(
                                     std::chrono::steady_clock::now() - start)
                                     .count());
    }
    std::lock_guard<std::mutex> lock(mu_);
    auto it = jobs_.find(id);
    if (it != jobs_.end()) it->second = std::move(result);
  }
}

DiagnosisJob DiagnosisJobs::Run(int64_t id, bool adopt) {
  DiagnosisJob result;
  result.id = id;
  result.status = "failed";
  result.adopt = adopt;
  // Suspect measurements are not diagnosed (storage/store_quality.h); the
  // report says which ("data_quality").
  StatusOr<storage::FittingData> data = store_->ReadFittingData();
  if (!data.ok()) {
    result.message = data.status().message();
    return result;
  }
  try {
    const DiagnosisOptions options;
    StatusOr<DiagnosisReport> report = Diagnose(data->fit, options);
    if (!report.ok()) {
      result.message = report.status().message();
      return result;
    }
    if (!hooks_.report_json) {
      result.message = "no report writer was given to the diagnosis jobs";
      return result;
    }
    result.status = "done";
    result.verdict = report->verdict;
    result.report = hooks_.report_json(*report, data->quality);
    result.html = DiagnosisHtml(*report);
    if (adopt && !report->findings.empty()) {
      // Scored on the validation campaigns of the data and split the
      // diagnosis fitted on.
      const auto start = std::chrono::steady_clock::now();
      StatusOr<storage::CalibrationRecord> run =
          runs_->Propose("diagnosis " + std::to_string(id),
                         WearLawName(report->adopted_model.law), 1,
                         report->adopted_model, data->fit, options.split_seed);
      const double seconds = std::chrono::duration<double>(
                                 std::chrono::steady_clock::now() - start)
                                 .count();
      if (hooks_.on_calibration) {
        storage::CalibrationRecord counted;
        if (run.ok()) {
          counted = *run;
        } else {
          counted.trigger = "diagnosis " + std::to_string(id);
          counted.status = storage::CalibrationStatus::kFailed;
          counted.message = run.status().message();
        }
        hooks_.on_calibration(counted, seconds);
      }
      if (run.ok()) {
        result.adoption = std::move(run).value();
      } else {
        result.message =
            "adoption could not be recorded: " + run.status().message();
      }
    }
  } catch (const std::exception& e) {
    result.status = "failed";
    result.message = std::string("diagnosis threw: ") + e.what();
  }
  return result;
}

}  // namespace rollwear::engine
