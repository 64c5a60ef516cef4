// The daemon's dashboard (GET /) as one self-contained HTML page for the
// mill pulpit: every mounted roll position with its predicted wear, 95 %
// interval, coils and rolled length; the wear growth along the open
// campaign; measured against predicted wear of the last campaigns per stand
// (parity plots with the 1:1 line); the last calibrations with their
// training/validation gaps; the latest diagnosis finding. Charts are inline
// SVG from core/report/svg_plot.h; no script, font or style is fetched from
// anywhere, and a small inline script re-fetches the page every
// `refresh_seconds` (a <noscript> meta refresh does the same without
// JavaScript). Laid out for 1366x768 screens.
//
// Every roll position is a table row carrying machine-readable markers:
//   data-stand="6" data-position="top" data-roll-id="..." data-coils="123"
//   data-length-m="45678.900" data-wear-um="123.456" data-lo-um="..."
//   data-hi-um="..." data-limit-um="..." data-remaining-m="..."
//   data-remaining-lo-m="..." data-remaining-hi-m="..."
//   data-remaining-coils="..."
// (numbers with 3 decimals; the limit and remaining-life markers are ""
// when GET /v1/wear has null, an unbounded interval end "inf"); the visible
// wear is printed with 1 decimal, the remaining length in km with 1. The
// growth chart draws, for each roll with a remaining life, a straight
// forecast line from its current wear to its limit ("F6 top to limit": the
// campaign's mix so far, as GET /v1/wear's remaining_length_m).
//
// The profile section (api/dashboard_profile.cc) draws each mounted roll's
// predicted wear across the barrel with its 95 % interval (GET /v1/wear/
// {stand}/{position}/profile's numbers), and the measured against predicted
// profiles of the last ended campaigns with grinder profiles. Each mounted
// roll's panel carries
//   class="roll-profile" data-stand="6" data-position="top"
//   data-shape="calibrated" data-x-mm="x0 x1 ..." data-wear-um="..."
//   data-lo-um="..." data-hi-um="..."
// (space-separated, 9 significant digits); a roll without a calibrated
// profile shape ("uncalibrated") gets data-shape="uncalibrated", no numbers
// and no curve, and the page says it has no profile model yet. A measured
// profile's panel carries class="measured-profile", data-campaign-id,
// data-stand, data-position, data-x-mm, data-measured-um and
// data-predicted-um (empty, and no predicted line, when the model has no
// profile shape).
//
// Pure: takes plain values and returns a string (no clock, no I/O).
// Thread-safety: DashboardHtml is a pure function.
#ifndef ROLLWEAR_API_DASHBOARD_PAGE_H_
#define ROLLWEAR_API_DASHBOARD_PAGE_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace rollwear {

struct DashboardRoll {
  int stand = 0;
  std::string position;  // "top" / "bottom"
  std::string roll_id;
  std::string roll_type;
  int coils = 0;
  double rolled_length_m = 0;
  double predicted_wear_um = 0;
  double interval_lo_um = 0;
  double interval_hi_um = 0;
  // Wear growth along the open campaign: rolled length so far and the
  // predicted wear after each coil (may be empty).
  std::vector<double> track_length_m;
  std::vector<double> track_wear_um;
  // The position's wear limit and the remaining life until it (GET
  // /v1/wear's fields; empty when null).
  std::optional<double> wear_limit_um;
  std::optional<double> remaining_length_m;
  std::optional<double> remaining_coils;
  std::optional<double> remaining_lo_m;
  std::optional<double> remaining_hi_m;  // empty also when unbounded
  // The predicted profile across the barrel (GET .../profile): its shape
  // state ("calibrated", "uncalibrated"; "" when the daemon has none for
  // this roll) and per slice x, wear and the interval.
  std::string profile_shape;
  std::vector<double> profile_x_mm;
  std::vector<double> profile_wear_um;
  std::vector<double> profile_lo_um;
  std::vector<double> profile_hi_um;
};

// A grinder profile of a recent ended campaign with the active model's
// prediction at its points (MillStore::RecentProfiles).
struct DashboardMeasuredProfile {
  int stand = 0;
  std::string position;  // "top" / "bottom"
  std::string campaign_id;
  std::string roll_id;
  bool calibrated = false;  // false: the prediction is not drawn
  std::vector<double> x_mm;
  std::vector<double> measured_um;
  std::vector<double> predicted_um;
};

// One measured roll of a recent ended campaign.
struct DashboardParityPoint {
  int stand = 0;
  std::string position;  // "top" / "bottom"
  std::string campaign_id;
  double measured_um = 0;
  // Under the active model: the predicted wear plus its measurement terms
  // (what the grinder is expected to read; see parity_reading_terms).
  double predicted_um = 0;
  // The stored suspect flag ("<kind>: <reason>", "" when plausible): such a
  // point is drawn apart ("suspect") and listed with its reason.
  std::string suspect;
};

struct DashboardCalibration {
  int64_t id = 0;
  std::string status;  // queued, running, done, failed
  std::string trigger;
  std::string model;  // law
  int option = 1;
  std::string finished;  // "2024-05-01 03:00 UTC" or ""
  double gap_train_um = 0;
  double gap_val_um = 0;
  double active_gap_val_um = 0;
  bool promoted = false;
  int64_t model_version = 0;
  std::string message;
};

struct DashboardFinding {
  int64_t diagnosis_id = 0;
  std::string verdict;  // missing_physics_found / no_significant_mismatch
  // The strongest finding (empty covariate when there is none).
  std::string covariate;
  std::string mechanism;
  std::string explanation;
  double p_value = 0;
  double gap_val_before_um = 0;
  double gap_val_after_um = 0;
  double baseline_gap_val_um = 0;
};

struct DashboardData {
  std::string title = "rollwear";
  std::string generated_at;  // "2024-05-01 12:34:56 UTC"
  int64_t model_version = 0;
  std::string model_label;           // "wang, option 1" ("prior" for version 0)
  double model_gap_val_um = 0;       // NaN or 0 when unknown
  std::string campaign_id;           // the open campaign ("" when none)
  std::vector<DashboardRoll> rolls;  // by stand, top first
  int parity_campaigns = 0;          // campaigns behind `parity`
  std::vector<DashboardParityPoint> parity;
  // The active model has measurement terms: the parity plots' y axis is the
  // expected grinder reading, not the wear alone.
  bool parity_reading_terms = false;
  std::vector<DashboardCalibration> calibrations;  // newest first
  // Grinder profiles of the last ended campaigns that have one, newest
  // campaign first.
  std::vector<DashboardMeasuredProfile> measured_profiles;
  std::optional<DashboardFinding> diagnosis;
  int refresh_seconds = 15;
};

std::string DashboardHtml(const DashboardData& data);

// The profile section of DashboardHtml (api/dashboard_profile.cc).
std::string DashboardProfileSection(const DashboardData& data);

}  // namespace rollwear

#endif  // ROLLWEAR_API_DASHBOARD_PAGE_H_
