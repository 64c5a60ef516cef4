#include "service/jobs/job_log.h"

#include <spdlog/spdlog.h>

namespace rollwear::service {
namespace {

// The value as is when it is a plain word; otherwise in double quotes
// with " and \ escaped and newlines as \n (logfmt).
std::string Quoted(std::string_view text) {
  if (!text.empty() &&
      text.find_first_of(" \t\n\"=\\") == std::string_view::npos) {
    return std::string(text);
  }
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out + "\"";
}

}  // namespace

std::string_view PromotionSource(std::string_view trigger) {
  if (trigger == "nightly") return "nightly";
  if (trigger.rfind("diagnosis", 0) == 0) return "diagnosis";
  return "calibration";
}

void LogCalibrationQueued(int64_t id, std::string_view trigger) {
  spdlog::info("event=calibration_queued id={} trigger={}", id,
               Quoted(trigger));
}

void LogCalibrationFinished(const storage::CalibrationRecord& r,
                            double seconds) {
  if (r.status != storage::CalibrationStatus::kDone) {
    spdlog::warn(
        "event=calibration_finished id={} trigger={} status=failed "
        "seconds={:.1f} message={}",
        r.id, Quoted(r.trigger), seconds, Quoted(r.message));
    return;
  }
  spdlog::info(
      "event=calibration_finished id={} trigger={} model={} option={} "
      "status=done gap_train_um={:.2f} gap_val_um={:.2f} "
      "active_gap_val_um={:.2f} promoted={} version={} seconds={:.1f}",
      r.id, Quoted(r.trigger), r.model, r.option, r.gap_train_um, r.gap_val_um,
      r.active_gap_val_um, r.promoted, r.model_version, seconds);
  if (!r.promoted) return;
  spdlog::info(
      "event=model_promoted version={} source={} trigger={} "
      "calibration_id={} model={} option={} gap_val_um={:.2f} "
      "active_gap_val_um={:.2f}",
      r.model_version, PromotionSource(r.trigger),
      Quoted(r.trigger), r.id, r.model, r.option, r.gap_val_um,
      r.active_gap_val_um);
}

void LogDiagnosisStarted(int64_t id, bool adopt) {
  spdlog::info("event=diagnosis_started id={} adopt={}", id, adopt);
}

void LogDiagnosisFinished(const engine::DiagnosisJob& job, double seconds) {
  std::string adoption;
  if (job.adoption) {
    adoption = " adoption_calibration_id=" + std::to_string(job.adoption->id) +
               " promoted=" + (job.adoption->promoted ? "true" : "false");
  }
  if (job.status == "done") {
    spdlog::info(
        "event=diagnosis_finished id={} adopt={} status=done verdict={} "
        "seconds={:.1f}{}{}",
        job.id, job.adopt, job.verdict, seconds, adoption,
        job.message.empty() ? "" : " message=" + Quoted(job.message));
    return;
  }
  spdlog::warn(
      "event=diagnosis_finished id={} adopt={} status={} seconds={:.1f} "
      "message={}",
      job.id, job.adopt, job.status, seconds, Quoted(job.message));
}

}  // namespace rollwear::service
