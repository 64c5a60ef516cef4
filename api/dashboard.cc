// GET /: gathers what the pulpit's dashboard shows from the store (wear of
// the mounted rolls and their profiles across the barrel, the open
// campaign's wear history, the last measured campaigns and grinder profiles
// under the active model, the last calibrations) and from the
// router's diagnosis jobs (the latest finished diagnosis), and renders it
// with api/dashboard_page.h. Part of Router (api/router.h).
#include <cmath>
#include <ctime>
#include <exception>
#include <string>

#include <nlohmann/json.hpp>

#include "api/dashboard_page.h"
#include "api/router.h"
#include "core/model/model_eval.h"

namespace rollwear::api {
namespace {

// Ended, measured campaigns behind the parity plots.
constexpr int kParityCampaigns = 20;
// Ended campaigns with grinder profiles drawn (measured vs predicted).
constexpr int kProfileCampaigns = 2;
// Calibration runs listed.
constexpr int kCalibrationRows = 5;
// Diagnosis jobs looked back through for the latest finished one
// (engine::DiagnosisJobs keeps the last 50).
constexpr int kDiagnosisLookback = 50;

std::string UtcTime(int64_t unix_seconds, bool with_seconds) {
  if (unix_seconds <= 0) return "";
  const std::time_t t = static_cast<std::time_t>(unix_seconds);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[40];
  std::strftime(buf, sizeof(buf),
                with_seconds ? "%Y-%m-%d %H:%M:%S UTC" : "%Y-%m-%d %H:%M UTC",
                &tm);
  return buf;
}

double NumberOr(const nlohmann::json& j, const char* key, double fallback) {
  auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<double>() : fallback;
}

std::string TextOr(const nlohmann::json& j, const char* key) {
  auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : "";
}

// The strongest finding of a diagnosis report (JSON of diagnosis_json.h).
std::optional<DashboardFinding> FindingOf(int64_t id,
                                          const std::string& report) {
  try {
    const nlohmann::json j = nlohmann::json::parse(report);
    DashboardFinding f;
    f.diagnosis_id = id;
    f.verdict = TextOr(j, "verdict");
    if (j.contains("baseline") && j["baseline"].is_object()) {
      f.baseline_gap_val_um = NumberOr(j["baseline"], "gap_val_um", NAN);
    }
    if (j.contains("findings") && j["findings"].is_array() &&
        !j["findings"].empty()) {
      const nlohmann::json& top = j["findings"][0];
      f.covariate = TextOr(top, "covariate");
      f.mechanism = TextOr(top, "mechanism");
      f.explanation = TextOr(top, "explanation");
      f.p_value = NumberOr(top, "p_value", NAN);
      f.gap_val_before_um = NumberOr(top, "gap_val_before_um", NAN);
      f.gap_val_after_um = NumberOr(top, "gap_val_after_um", NAN);
    }
    return f;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// The dashboard's row of one mounted roll: its wear (PositionWearOf) and
// its profile as GET .../profile serves it (none when that errs), both
// read from the same moment `mounted`.
DashboardRoll RollRow(const storage::MountedState& mounted, int slot) {
  const engine::PositionWear p = engine::PositionWearOf(mounted, slot);
  DashboardRoll r;
  r.stand = p.stand;
  r.position = PositionName(p.position);
  r.roll_id = p.roll_id;
  r.roll_type = p.roll_type;
  r.coils = p.coils;
  r.rolled_length_m = p.rolled_length_m;
  r.predicted_wear_um = p.predicted_wear_um;
  r.interval_lo_um = p.interval_lo_um;
  r.interval_hi_um = p.interval_hi_um;
  r.wear_limit_um = p.wear_limit_um;
  if (p.remaining) {
    r.remaining_length_m = p.remaining->length_m;
    r.remaining_coils = p.remaining->coils;
    r.remaining_lo_m = p.remaining->length_lo_m;
    r.remaining_hi_m = p.remaining->length_hi_m;
  }
  StatusOr<engine::ProfileWear> profile = engine::ProfileWearOf(mounted, slot);
  if (profile.ok()) {
    r.profile_shape = profile->shape ? "calibrated" : "uncalibrated";
    r.profile_x_mm = std::move(profile->profile.x_mm);
    r.profile_wear_um = std::move(profile->profile.wear_um);
    r.profile_lo_um = std::move(profile->profile.lo_um);
    r.profile_hi_um = std::move(profile->profile.hi_um);
  }
  return r;
}

// The wear history's parts of the page: the open campaign's track of each
// mounted roll (`d->rolls`, of campaign `d->campaign_id`) and the parity
// points of the ended campaigns.
void AddWearHistory(const std::vector<storage::CampaignWearHistory>& history,
                    DashboardData* d) {
  for (const storage::CampaignWearHistory& c : history) {
    if (c.open) {
      if (c.campaign_id != d->campaign_id) continue;
      for (const storage::RollWearHistory& h : c.rolls) {
        for (DashboardRoll& r : d->rolls) {
          if (r.stand == h.stand && r.position == PositionName(h.position)) {
            r.track_length_m = h.rolled_length_m;
            r.track_wear_um = h.predicted_wear_um;
          }
        }
      }
      continue;
    }
    ++d->parity_campaigns;
    for (const storage::RollWearHistory& h : c.rolls) {
      if (!h.measured_um) continue;
      d->parity.push_back(DashboardParityPoint{
          h.stand, PositionName(h.position), c.campaign_id, *h.measured_um,
          h.expected_reading_um, h.measured_suspect});
    }
  }
}

DashboardCalibration CalibrationRow(const storage::CalibrationRecord& c) {
  DashboardCalibration row;
  row.id = c.id;
  row.status = storage::CalibrationStatusName(c.status);
  row.trigger = c.trigger;
  row.model = c.model;
  row.option = c.option;
  row.finished = UtcTime(c.finished_at, false);
  row.gap_train_um = c.gap_train_um;
  row.gap_val_um = c.gap_val_um;
  row.active_gap_val_um = c.active_gap_val_um;
  row.promoted = c.promoted;
  row.model_version = c.model_version;
  row.message = c.message;
  return row;
}

}  // namespace

HttpResponse Router::GetDashboard() {
  DashboardData d;
  d.generated_at = UtcTime(static_cast<int64_t>(std::time(nullptr)), true);

  // The mounted rolls, their wear and profiles of one moment.
  const storage::MountedState mounted = mounted_.Mounted();
  d.model_version = mounted.model->version;
  for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
    if ((*mounted.rolls)[slot]) d.rolls.push_back(RollRow(mounted, slot));
  }
  if (!d.rolls.empty()) d.campaign_id = mounted.campaign_id;
  // The served model of that moment (the version as stored with each
  // roll's factor re-estimated from its readings: the same law, option,
  // gap and terms).
  const storage::ModelVersion& model = *mounted.model;
  d.model_label = model.version == 0 ? "prior (uncalibrated) " + model.model
                                     : model.model + ", option " +
                                           std::to_string(model.option);
  if (model.version > 0) d.model_gap_val_um = model.gap_val_um;
  d.parity_reading_terms = HasMeasurementTerms(model.wear_model);

  StatusOr<std::vector<storage::MeasuredProfile>> profiles =
      store_->RecentProfiles(kProfileCampaigns);
  if (profiles.ok()) {
    for (storage::MeasuredProfile& m : *profiles) {
      d.measured_profiles.push_back(DashboardMeasuredProfile{
          m.stand, PositionName(m.position), m.campaign_id, m.roll_id,
          m.calibrated, std::move(m.x_mm), std::move(m.measured_um),
          std::move(m.predicted_um)});
    }
  }
  StatusOr<std::vector<storage::CampaignWearHistory>> history =
      store_->RecentWear(kParityCampaigns);
  if (history.ok()) AddWearHistory(*history, &d);
  for (const storage::CalibrationRecord& c :
       store_->ListCalibrations(kCalibrationRows)) {
    d.calibrations.push_back(CalibrationRow(c));
  }

  // Only queued diagnoses set last_diagnosis_id_ (so diagnoses is set).
  const int64_t last = last_diagnosis_id_.load(std::memory_order_relaxed);
  for (int64_t id = last; id > 0 && id > last - kDiagnosisLookback; --id) {
    std::optional<engine::DiagnosisJob> job = options_.diagnoses->Get(id);
    if (!job || job->status != "done") continue;
    d.diagnosis = FindingOf(id, job->report);
    if (d.diagnosis) break;
  }

  HttpResponse r;
  r.status = 200;
  r.content_type = "text/html; charset=utf-8";
  r.body = DashboardHtml(d);
  r.headers.emplace_back("Cache-Control", "no-store");
  return r;
}

}  // namespace rollwear::api
