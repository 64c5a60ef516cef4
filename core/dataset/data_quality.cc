#include "core/dataset/data_quality.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace rollwear {
namespace {

// The thresholds, from physical bounds and the data's own spread (never
// tuned to a known answer):
//
// Expected wear. Every wear law of data-format.md is, to first order,
// proportional to Wang's load sum(force / width * length) of the roll
// position's passes. The data's own wear rate q = median(wear / load) over
// the positive readings gives a rough expected wear e = q * load.
//
// Spread. s = 1.4826 * MAD of log(wear / load) over the positive readings
// is the data's relative spread of wear rates (forces, grades, roll types,
// roll-to-roll scatter; Hampel 1974, JASA 69:383: the MAD's consistency
// factor for a normal law). A reading with expected wear e then scatters
// with sd(e) = sqrt(sigma0^2 + (s * e)^2).
//
// Gauge noise sigma0: the robust sd of (wear - e) among the least-worn
// quarter of the rolls (at least kMinNoiseSample of them), where the
// relative scatter matters least. It folds in what is left of the
// roll-to-roll scatter there, so it bounds the gauge's noise from above
// and the rules below flag less, never more. (Taking the relative part
// s * median(e) out instead over-corrects: s also holds the spread
// between stands and grades, and sigma0 collapsed to the grinder's
// resolution on simulated mills with 8 µm noise.) Below kMinNoiseSample
// readings sigma0 = kFallbackNoiseSdUm, which makes the limit below the
// former fixed floor of -50 µm. sigma0 >= kMinNoiseSdUm (the grinder's
// resolution).
//
// negative_wear: wear < -kNoiseSigmas * sigma0 (true wear is >= 0, so such
// a reading is more than 4 noise sd's from any physical value), or wear <
// 0 and more than kNoiseSigmas * sd(e) below its expected wear e. A normal
// error that large has probability 3e-5, i.e. 0.05 false flags among 1,500
// readings.
//
// excess_wear: log(wear / e) above kExcessSigmas robust sd's of log(wear /
// load) (1.4826 * MAD) and wear - e above kNoiseSigmas * sigma0. Six robust
// sd's is far outside any normal scatter (p ~ 1e-9) yet leaves the whole
// natural spread of wear rates (forces, grades, roll types) inside. A
// reading of more than kNoiseSigmas * sigma0 on a roll position without a
// pass is excess wear too (its campaign produced none).
//
// unit_mm: the median reading of the rolls that rolled anything is
// positive and below kMmMedianUm while their median rolled length is at
// least kMmMinLengthM.
// Hot-strip work rolls lose wear of the order of µm per km of strip (the
// study's rolls hundreds of µm in campaigns of tens of km), so a roll that
// rolled >= 10 km has lost >= ~10 µm: a median three orders of magnitude
// smaller is the factor between µm and mm.
//
// low_wear: the mirror of excess_wear, for a reading near zero where its
// campaign predicts far more (a gauge that read nothing, a reading taken
// on the wrong roll): max(wear, sigma0) below e / exp(kExcessSigmas * s)
// and wear more than kNoiseSigmas * sigma0 below e. Only when the spread s
// is known.
//
// profile_not_wear: a whole profile whose median |value| exceeds
// kProfileNotWearUm. A work roll of a hot strip mill loses at most about a
// millimetre of radius in a campaign (the study's rolls: hundreds of µm);
// 5 mm is five times that, while a profile file holding roll diameters
// (~750 mm = 750,000 µm) or positions read from a datum lies orders of
// magnitude beyond. Its points are set aside, never the dataset.
//
// centre_vs_profile: the profile's centre, the median of its points within
// kProfileCentreHalfWidthMm of x = 0 (at least 2), differs from the centre
// reading of the same roll by more than kNoiseSigmas * sqrt(2) * sigma0 +
// kProfileCentreRelative of the larger of the two: two readings of one
// surface by one grinder differ by the gauge's noise of each, plus the
// crown a slice of +-100 mm holds (25 % is a generous bound of a work
// roll's wear gradient there).
constexpr double kProfileNotWearUm = 5000.0;
constexpr double kProfileCentreHalfWidthMm = 100.0;
constexpr double kProfileCentreRelative = 0.25;
constexpr int kMinNoiseSample = 8;
constexpr double kFallbackNoiseSdUm = 12.5;  // 4 * 12.5 = the old -50 µm
constexpr double kMinNoiseSdUm = 1.0;
constexpr double kNoiseSigmas = kSuspectNoiseSigmas;
constexpr double kExcessSigmas = 6.0;
constexpr double kMadToSd = 1.4826;
constexpr double kMmMedianUm = 1.0;
constexpr double kMmMinLengthM = 10'000.0;

double Median(std::vector<double> v) {
  if (v.empty()) return NAN;
  const size_t n = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + n, v.end());
  const double hi = v[n];
  if (v.size() % 2 == 1) return hi;
  return 0.5 * (hi + *std::max_element(v.begin(), v.begin() + n));
}

double RobustSd(const std::vector<double>& v) {
  const double med = Median(v);
  std::vector<double> dev;
  dev.reserve(v.size());
  for (double x : v) dev.push_back(std::fabs(x - med));
  return kMadToSd * Median(std::move(dev));
}

std::string Fmt(const char* format, double a, double b = 0, double c = 0) {
  char buf[256];
  std::snprintf(buf, sizeof(buf), format, a, b, c);
  return buf;
}

// Each measurement's exposure: its wear, and Wang's load and the rolled
// length of its roll position's passes in its campaign.
std::vector<ReadingExposure> ExposuresOf(const Dataset& data,
                                         const DatasetIndex& index) {
  std::vector<ReadingExposure> out;
  out.reserve(data.measurements.size());
  for (const Measurement& m : data.measurements) {
    ReadingExposure r;
    r.wear_um = m.wear_center_um;
    for (int p : index.PassesOf(m.campaign, m.stand)) {
      const Pass& pass = data.passes[p];
      r.load += PassLoad(pass);
      r.length_m += pass.length_m;
    }
    out.push_back(r);
  }
  return out;
}

std::string WhereOf(const Dataset& data, int campaign, int stand,
                    Position position) {
  return RollPositionName(stand, position) + " of campaign '" +
         data.campaigns[campaign].id + "'";
}

// Returns false when there are too few readings to estimate sigma0 (the
// fallback is used) and with it the spread: only the absolute negative
// bound and the excess bound apply then.
bool EstimateBounds(const std::vector<ReadingExposure>& readings,
                    DataQuality* q) {
  std::vector<double> log_ratio;
  std::vector<double> rate;
  for (const ReadingExposure& r : readings) {
    if (r.wear_um > 0 && r.load > 0) {
      rate.push_back(r.wear_um / r.load);
      log_ratio.push_back(std::log(r.wear_um / r.load));
    }
  }
  q->wear_rate_um_per_unit = rate.empty() ? 0 : Median(rate);
  q->log_ratio_scale = log_ratio.size() < 2 ? 0 : RobustSd(log_ratio);
  q->excess_factor = std::exp(kExcessSigmas * q->log_ratio_scale);
  // sigma0 from the least-worn quarter of the loaded rolls.
  std::vector<size_t> loaded;
  for (size_t i = 0; i < readings.size(); ++i) {
    if (readings[i].load > 0) loaded.push_back(i);
  }
  // Ordered by load, then wear: a total order (the two rolls of a stand
  // share their load), so sigma0 does not depend on the readings' order.
  std::sort(loaded.begin(), loaded.end(), [&](size_t a, size_t b) {
    const ReadingExposure& x = readings[a];
    const ReadingExposure& y = readings[b];
    return x.load != y.load ? x.load < y.load : x.wear_um < y.wear_um;
  });
  const size_t n = std::max<size_t>(loaded.size() / 4, kMinNoiseSample);
  if (loaded.size() < kMinNoiseSample || q->wear_rate_um_per_unit <= 0) {
    q->noise_sd_um = kFallbackNoiseSdUm;
    return false;
  }
  std::vector<double> residual;
  for (size_t k = 0; k < n; ++k) {
    const ReadingExposure& r = readings[loaded[k]];
    residual.push_back(r.wear_um - q->wear_rate_um_per_unit * r.load);
  }
  q->noise_sd_um = std::max(kMinNoiseSdUm, RobustSd(residual));
  return true;
}

// unit_mm: the reason every reading is flagged when the readings look like
// mm, else "".
std::string MillimetreReason(const std::vector<ReadingExposure>& readings) {
  std::vector<double> wear, length;
  for (const ReadingExposure& r : readings) {
    if (r.length_m <= 0) continue;
    wear.push_back(r.wear_um);
    length.push_back(r.length_m);
  }
  if (wear.empty()) return "";
  const double median_wear = Median(wear), median_length = Median(length);
  // Values in mm are positive: a negative median is not mm (the daemon
  // judges a single reading this way: core/dataset/data_quality.h).
  if (!(median_wear > 0 && median_wear < kMmMedianUm &&
        median_length >= kMmMinLengthM)) {
    return "";
  }
  return Fmt(
      "the file's values look like mm, not µm: median wear %.3g µm while "
      "the rolls rolled a median %.1f km (expected >= ~10 µm); write wear "
      "in µm",
      median_wear, median_length / 1000);
}

// Judges readings [from, end) among all of `readings`: the bounds' figures
// into *q, each reason into q->suspect[i] ("" = plausible; q->suspect is
// sized by the caller) and its kind into (*kinds)[i].
void JudgeReadings(const std::vector<ReadingExposure>& readings, size_t from,
                   DataQuality* q, std::vector<DataQualityKind>* kinds) {
  const bool spread_known = EstimateBounds(readings, q);
  const std::string mm = MillimetreReason(readings);
  kinds->resize(readings.size(), DataQualityKind::kNegativeWear);
  for (size_t i = from; i < readings.size(); ++i) {
    if (!mm.empty()) {
      q->suspect[i] = mm;
      (*kinds)[i] = DataQualityKind::kUnitMm;
      continue;
    }
    ReadingBounds bounds;
    bounds.expected_um = q->wear_rate_um_per_unit * readings[i].load;
    bounds.noise_sd_um = q->noise_sd_um;
    bounds.excess_factor = q->excess_factor;
    bounds.relative_sd = spread_known ? q->log_ratio_scale : INFINITY;
    q->suspect[i] = SuspectReading(readings[i].wear_um, bounds, &(*kinds)[i]);
  }
}

void FlagUnpassedPositions(const Dataset& data, const DatasetIndex& index,
                           DataQuality* q) {
  std::vector<bool> has_coils(data.campaigns.size(), false);
  for (const Pass& p : data.passes) has_coils[p.campaign] = true;
  for (size_t i = 0; i < data.mounts.size(); ++i) {
    const Mount& m = data.mounts[i];
    if (!has_coils[m.campaign] || !index.PassesOf(m.campaign, m.stand).empty()) {
      continue;
    }
    DataQualityIssue issue;
    issue.kind = DataQualityKind::kNoPasses;
    issue.mount = static_cast<int>(i);
    issue.where = WhereOf(data, m.campaign, m.stand, m.position);
    issue.reason = "roll position " + RollPositionName(m.stand, m.position) +
                   " received no pass in a campaign with coils (is its "
                   "stand named as in coils.csv?)";
    q->issues.push_back(std::move(issue));
  }
}

// The profiles' checks (profile_not_wear, centre_vs_profile: top).
void FlagProfiles(const Dataset& data, const DatasetIndex& index,
                  DataQuality* q) {
  std::map<std::pair<int, int>, std::vector<int>> profiles;  // (c, slot)
  for (size_t i = 0; i < data.profile_points.size(); ++i) {
    const ProfilePoint& p = data.profile_points[i];
    profiles[{p.campaign, RollPositionSlot(p.stand, p.position)}].push_back(
        static_cast<int>(i));
  }
  for (const auto& [key, points] : profiles) {
    const ProfilePoint& first = data.profile_points[points.front()];
    std::vector<double> abs_wear, centre;
    for (int i : points) {
      const ProfilePoint& p = data.profile_points[i];
      abs_wear.push_back(std::fabs(p.wear_um));
      if (std::fabs(p.x_mm) <= kProfileCentreHalfWidthMm) centre.push_back(p.wear_um);
    }
    DataQualityIssue issue;
    issue.where = WhereOf(data, first.campaign, first.stand, first.position);
    const double median_abs = Median(abs_wear);
    if (median_abs > kProfileNotWearUm) {
      issue.kind = DataQualityKind::kProfileNotWear;
      issue.profile_point = points.front();
      issue.reason = Fmt(
          "the profile's %.0f points have a median |value| of %.0f µm, beyond "
          "any campaign's wear (%.0f µm): diameters or positions, not wear; "
          "its points are set aside",
          static_cast<double>(points.size()), median_abs, kProfileNotWearUm);
      for (int i : points) q->suspect_point[i] = true;
      q->issues.push_back(std::move(issue));
      continue;
    }
    const int me = index.MeasurementOf(key.first, key.second);
    if (me < 0 || centre.size() < 2 || !q->suspect[me].empty()) continue;
    const double w = data.measurements[me].wear_center_um, c = Median(centre);
    const double limit = kNoiseSigmas * std::sqrt(2.0) * q->noise_sd_um +
                         kProfileCentreRelative * std::max(std::fabs(w), std::fabs(c));
    if (!(std::fabs(w - c) > limit)) continue;
    issue.kind = DataQualityKind::kCentreVsProfile;
    issue.measurement = me;
    issue.value_um = w;
    issue.reason = Fmt(
        "centre reading %.1f µm, its own profile reads %.1f µm at the centre "
        "(limit %.1f µm apart)",
        w, c, limit);
    q->suspect[me] = issue.reason;
    q->issues.push_back(std::move(issue));
  }
}

}  // namespace

const char* DataQualityKindName(DataQualityKind kind) {
  switch (kind) {
    case DataQualityKind::kNegativeWear: return "negative_wear";
    case DataQualityKind::kExcessWear: return "excess_wear";
    case DataQualityKind::kUnitMm: return "unit_mm";
    case DataQualityKind::kNoPasses: return "no_passes";
    case DataQualityKind::kLowWear: return "low_wear";
    case DataQualityKind::kProfileNotWear: return "profile_not_wear";
    case DataQualityKind::kCentreVsProfile: return "centre_vs_profile";
  }
  return "unknown";
}

std::string DataQualityIssue::Location() const {
  return line > 0 ? file + ":" + std::to_string(line) : file;
}

std::string SuspectReading(double wear_um, const ReadingBounds& b,
                           DataQualityKind* kind) {
  const double noise_limit = kNoiseSigmas * b.noise_sd_um;
  const double sd = std::hypot(b.noise_sd_um, b.relative_sd * b.expected_um);
  if (wear_um < -noise_limit) {
    *kind = DataQualityKind::kNegativeWear;
    return Fmt("%.1f µm is below -%.1f µm, 4 sd's of the gauge's noise "
               "(%.1f µm) under zero: wear is positive radius loss",
               wear_um, noise_limit, b.noise_sd_um);
  }
  if (wear_um < 0 && wear_um < b.expected_um - kNoiseSigmas * sd) {
    *kind = DataQualityKind::kNegativeWear;
    return Fmt("%.1f µm is negative on a roll expected to have lost ~%.1f "
               "µm (more than 4 sd's, %.1f µm, below)",
               wear_um, b.expected_um, sd);
  }
  if (std::isfinite(b.relative_sd) && b.expected_um > 0 && b.excess_factor > 1 &&
      std::max(wear_um, b.noise_sd_um) < b.expected_um / b.excess_factor &&
      wear_um < b.expected_um - noise_limit) {
    *kind = DataQualityKind::kLowWear;
    return Fmt("%.1f µm where its campaign predicts ~%.1f µm: below %.1f µm, "
               "the low bound of the data's spread of wear rates",
               wear_um, b.expected_um, b.expected_um / b.excess_factor);
  }
  const double limit = b.expected_um * b.excess_factor + noise_limit;
  if (wear_um > limit) {
    *kind = DataQualityKind::kExcessWear;
    if (b.expected_um <= 0) {
      return Fmt("%.1f µm on a roll position that rolled nothing in its "
                 "campaign (limit %.1f µm, 4 sd's of the gauge's noise)",
                 wear_um, limit);
    }
    return Fmt("%.1f µm is far beyond what its campaign could produce "
               "(expected ~%.1f µm, limit %.1f µm)",
               wear_um, b.expected_um, limit);
  }
  return "";
}

int DataQuality::Count(DataQualityKind kind) const {
  return static_cast<int>(std::count_if(
      issues.begin(), issues.end(),
      [kind](const DataQualityIssue& i) { return i.kind == kind; }));
}

int DataQuality::NumSuspect() const {
  return static_cast<int>(std::count_if(
      suspect.begin(), suspect.end(),
      [](const std::string& s) { return !s.empty(); }));
}

std::string JudgeLastReading(const std::vector<ReadingExposure>& readings,
                             DataQualityKind* kind) {
  if (readings.empty()) return "";
  DataQuality q;
  q.suspect.assign(readings.size(), "");
  std::vector<DataQualityKind> kinds;
  JudgeReadings(readings, readings.size() - 1, &q, &kinds);
  *kind = kinds.back();
  return q.suspect.back();
}

DataQuality AssessDataQuality(const Dataset& data,
                              const DatasetLines* source) {
  const DatasetLines no_lines;
  const DatasetLines& lines_of = source != nullptr ? *source : no_lines;
  DataQuality q;
  q.suspect.assign(data.measurements.size(), "");
  q.suspect_point.assign(data.profile_points.size(), false);
  const DatasetIndex index(data);
  std::vector<DataQualityKind> kinds;
  JudgeReadings(ExposuresOf(data, index), 0, &q, &kinds);
  for (size_t i = 0; i < data.measurements.size(); ++i) {
    if (q.suspect[i].empty()) continue;
    const Measurement& m = data.measurements[i];
    DataQualityIssue issue;
    issue.kind = kinds[i];
    issue.measurement = static_cast<int>(i);
    issue.value_um = m.wear_center_um;
    issue.where = WhereOf(data, m.campaign, m.stand, m.position);
    issue.reason = q.suspect[i];
    q.issues.push_back(std::move(issue));
  }
  FlagUnpassedPositions(data, index, &q);
  FlagProfiles(data, index, &q);
  for (DataQualityIssue& issue : q.issues) {
    const bool on_mount = issue.mount >= 0;
    const bool on_profile = issue.profile_point >= 0;
    issue.file = on_mount     ? "mounts.csv"
                 : on_profile ? "profiles.csv"
                              : "measurements.csv";
    const std::vector<int>& lines = on_mount     ? lines_of.mounts
                                    : on_profile ? lines_of.profile_points
                                                 : lines_of.measurements;
    const size_t row = on_mount     ? issue.mount
                       : on_profile ? issue.profile_point
                                    : issue.measurement;
    if (row < lines.size()) issue.line = lines[row];
  }
  return q;
}

void RemoveSuspects(const DataQuality& quality, Dataset* data) {
  const auto suspect = [&](size_t i) {
    return i < quality.suspect.size() && !quality.suspect[i].empty();
  };
  // Each kept row moves to its place among the kept rows, in order.
  ExtraColumns& extra = data->measurement_extra;
  size_t kept = 0;
  for (size_t i = 0; i < data->measurements.size(); ++i) {
    if (suspect(i)) continue;
    data->measurements[kept] = std::move(data->measurements[i]);
    for (auto& column : extra.numeric) column[kept] = column[i];
    for (auto& column : extra.factor) column[kept] = column[i];
    ++kept;
  }
  data->measurements.resize(kept);
  for (auto& column : extra.numeric) column.resize(kept);
  for (auto& column : extra.factor) column.resize(kept);
  size_t points = 0;
  for (size_t i = 0; i < data->profile_points.size(); ++i) {
    if (i < quality.suspect_point.size() && quality.suspect_point[i]) continue;
    data->profile_points[points++] = data->profile_points[i];
  }
  data->profile_points.resize(points);
}

Dataset WithoutSuspects(const Dataset& data, const DataQuality& quality) {
  Dataset out = data;
  RemoveSuspects(quality, &out);
  return out;
}

std::string DataQualitySummary(const DataQuality& q, int max_listed) {
  if (q.issues.empty()) return "data quality: no warnings\n";
  std::string out = "data quality: " + std::to_string(q.issues.size()) +
                    " warning(s), " + std::to_string(q.NumSuspect()) +
                    " suspect measurement(s) excluded from fitting:";
  for (int k = 0; k < kNumDataQualityKinds; ++k) {
    const auto kind = static_cast<DataQualityKind>(k);
    const int n = q.Count(kind);
    if (n > 0) out += " " + std::to_string(n) + " " + DataQualityKindName(kind);
  }
  out += "\n";
  const int listed = std::min<int>(max_listed, q.issues.size());
  for (int i = 0; i < listed; ++i) {
    const DataQualityIssue& issue = q.issues[i];
    out += "  " + issue.Location() + " " + issue.where + ": " +
           DataQualityKindName(issue.kind) + ": " + issue.reason + "\n";
  }
  if (listed < static_cast<int>(q.issues.size())) {
    out += "  ... and " + std::to_string(q.issues.size() - listed) +
           " more (see the JSON's data_quality)\n";
  }
  return out;
}

}  // namespace rollwear
