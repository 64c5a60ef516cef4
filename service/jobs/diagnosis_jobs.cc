#include "service/jobs/diagnosis_jobs.h"

#include <chrono>
#include <exception>
#include <string>
#include <utility>

#include "api/diagnosis_json.h"
#include "core/diagnosis/diagnosis.h"
#include "service/jobs/job_log.h"

namespace rollwear::service {
namespace {

constexpr size_t kKeep = 50;  // reports kept in memory

}  // namespace

DiagnosisJobs::DiagnosisJobs(storage::MillStore* store,
                             CalibrationDone on_calibration)
    : store_(store),
      on_calibration_(std::move(on_calibration)),
      worker_([this] { Work(); }) {}

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
  api::DiagnosisJob job;
  job.id = id;
  job.status = "queued";
  job.adopt = adopt;
  jobs_[id] = std::move(job);
  queue_.push_back(id);
  while (jobs_.size() > kKeep) jobs_.erase(jobs_.begin());
  cv_.notify_one();
  return id;
}

std::optional<api::DiagnosisJob> DiagnosisJobs::Get(int64_t id) const {
  std::lock_guard<std::mutex> lock(mu_);
  auto it = jobs_.find(id);
  if (it == jobs_.end()) return std::nullopt;
  return it->second;
}

void DiagnosisJobs::Work() {
  for (;;) {
    int64_t id = 0;
    bool adopt = false;
    {
      std::unique_lock<std::mutex> lock(mu_);
      cv_.wait(lock, [this] { return stop_ || !queue_.empty(); });
      if (stop_) return;
      id = queue_.front();
      queue_.pop_front();
      auto it = jobs_.find(id);
      if (it == jobs_.end()) continue;  // evicted before it ran
      it->second.status = "running";
      adopt = it->second.adopt;
    }
    LogDiagnosisStarted(id, adopt);
    const auto start = std::chrono::steady_clock::now();
    api::DiagnosisJob result = Run(id, adopt);
    LogDiagnosisFinished(
        result, std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                              start)
                    .count());
    std::lock_guard<std::mutex> lock(mu_);
    auto it = jobs_.find(id);
    if (it != jobs_.end()) it->second = std::move(result);
  }
}

api::DiagnosisJob DiagnosisJobs::Run(int64_t id, bool adopt) {
  api::DiagnosisJob result;
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
    result.status = "done";
    result.verdict = report->verdict;
    result.report = api::DiagnosisJsonText(*report, -1, &data->quality);
    if (adopt && !report->findings.empty()) {
      // Scored on the validation campaigns of the data and split the
      // diagnosis fitted on.
      const auto start = std::chrono::steady_clock::now();
      StatusOr<storage::CalibrationRecord> run = store_->ProposeModel(
          "diagnosis " + std::to_string(id),
          WearLawName(report->adopted_model.law), 1, report->adopted_model,
          data->fit, options.split_seed);
      const double seconds = std::chrono::duration<double>(
                                 std::chrono::steady_clock::now() - start)
                                 .count();
      if (on_calibration_) {
        storage::CalibrationRecord counted;
        if (run.ok()) {
          counted = *run;
        } else {
          counted.trigger = "diagnosis " + std::to_string(id);
          counted.status = storage::CalibrationStatus::kFailed;
          counted.message = run.status().message();
        }
        on_calibration_(counted, seconds);
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

}  // namespace rollwear::service
