#include "api/diagnosis_jobs.h"

#include <nlohmann/json.hpp>

#include "api/diagnosis_json.h"
#include "core/diagnosis/diagnosis.h"

namespace rollwear::api {
namespace {

constexpr size_t kKeep = 50;  // reports kept in memory

}  // namespace

std::string EncodeDiagnosisJob(const DiagnosisJob& job) {
  nlohmann::json j = nlohmann::json::object();
  if (job.status == "done") {
    j = nlohmann::json::parse(job.report, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded()) j = nlohmann::json::object();
  }
  j["id"] = job.id;
  j["status"] = job.status;
  if (!job.message.empty()) j["message"] = job.message;
  if (job.adoption.has_value()) {
    const storage::CalibrationRecord& r = *job.adoption;
    j["adoption"] = {
        {"calibration_id", r.id},
        {"promoted", r.promoted},
        {"gap_val_um", r.gap_val_um},
        {"active_gap_val_um", r.active_gap_val_um},
        {"model_version", r.model_version == 0 ? nlohmann::json(nullptr)
                                               : nlohmann::json(r.model_version)},
        {"message", r.message}};
  }
  return j.dump();
}

DiagnosisJobs::DiagnosisJobs(storage::MillStore* store)
    : store_(store), worker_([this] { Work(); }) {}

DiagnosisJobs::~DiagnosisJobs() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
  }
  cv_.notify_all();
  worker_.join();
}

int64_t DiagnosisJobs::Enqueue(bool adopt) {
  std::lock_guard<std::mutex> lock(mu_);
  const int64_t id = next_id_++;
  DiagnosisJob job;
  job.id = id;
  job.status = "queued";
  job.adopt = adopt;
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
    DiagnosisJob result;
    result.id = id;
    result.status = "failed";
    result.adopt = adopt;
    StatusOr<Dataset> data = store_->ExportDataset();
    if (!data.ok()) {
      result.message = data.status().message();
    } else try {
      const DiagnosisOptions options;
      StatusOr<DiagnosisReport> report = Diagnose(*data, options);
      if (report.ok()) {
        result.status = "done";
        result.report = DiagnosisJsonText(*report);
        if (adopt && !report->findings.empty()) {
          // Scored on the validation campaigns of the data and split the
          // diagnosis fitted on.
          StatusOr<storage::CalibrationRecord> run = store_->ProposeModel(
              "diagnosis " + std::to_string(id), WearLawName(report->adopted_model.law),
              1, report->adopted_model, *data, options.split_seed);
          if (run.ok()) {
            result.adoption = std::move(run).value();
          } else {
            result.message = "adoption could not be recorded: " + run.status().message();
          }
        }
      } else {
        result.message = report.status().message();
      }
    } catch (const std::exception& e) {
      result.status = "failed";
      result.message = std::string("diagnosis threw: ") + e.what();
    }
    std::lock_guard<std::mutex> lock(mu_);
    auto it = jobs_.find(id);
    if (it != jobs_.end()) it->second = std::move(result);
  }
}

}  // namespace rollwear::api
