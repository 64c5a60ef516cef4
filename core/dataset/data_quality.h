// Data quality of a mill dataset: the values that are valid numbers but
// cannot be physical wear (docs/data-format.md, "Implausible values"). They
// are warnings, not rule breaks: the row is kept, flagged as suspect with
// its reason, excluded from fitting (WithoutSuspects) and listed by every
// tool; `--strict` on the CLI turns them into errors.
//
// Kinds (name in JSON and in the summary):
//   negative_wear  a centre wear below -4 sigma0, sigma0 the gauge's noise
//   excess_wear    far more than the campaign could have produced
//   unit_mm        a whole measurements.csv whose values look like mm
//   no_passes      a mounted roll position without a pass in a campaign
//                  that has coils (a warning; nothing is flagged)
//   low_wear       near zero (or mildly negative) where the campaign
//                  predicts far more: the mirror of excess_wear
//   profile_not_wear  a profile whose values are not wear (diameters or
//                  offsets: its median |value| beyond any campaign's wear);
//                  all its points are set aside
//   centre_vs_profile  a centre reading far from its own profile's centre
//                  (the reading is set aside, the profile kept)
// The thresholds and why they are what they are: data_quality.cc, top.
//
// Thread-safety: pure functions of their arguments.
#ifndef ROLLWEAR_CORE_DATASET_DATA_QUALITY_H_
#define ROLLWEAR_CORE_DATASET_DATA_QUALITY_H_

#include <string>
#include <vector>

#include "core/dataset/dataset.h"
#include "core/dataset/dataset_io.h"

namespace rollwear {

// A reading below -kSuspectNoiseSigmas sd's of the gauge's noise is
// negative_wear (see data_quality.cc for why 4).
inline constexpr double kSuspectNoiseSigmas = 4.0;

enum class DataQualityKind {
  kNegativeWear, kExcessWear, kUnitMm, kNoPasses, kLowWear, kProfileNotWear,
  kCentreVsProfile,
};
inline constexpr int kNumDataQualityKinds = 7;
// "negative_wear", "excess_wear", "unit_mm", "no_passes", "low_wear",
// "profile_not_wear", "centre_vs_profile".
const char* DataQualityKindName(DataQualityKind kind);

struct DataQualityIssue {
  DataQualityKind kind = DataQualityKind::kNegativeWear;
  std::string file;  // "measurements.csv", "mounts.csv"
  int line = 0;      // line in `file`; 0 when its line is not known
  int measurement = -1;  // index into Dataset::measurements, or -1
  int mount = -1;        // index into Dataset::mounts, or -1
  int profile_point = -1;  // first point of a flagged profile, or -1
  std::string where;     // "F6/top of campaign 'C0042'"
  double value_um = 0;   // the reading (measurement kinds)
  std::string reason;    // one sentence, with the threshold it broke
  // "measurements.csv:17" (or `file` alone when the line is unknown).
  std::string Location() const;
};

// The bounds a single reading is judged by (see data_quality.cc).
struct ReadingBounds {
  double expected_um = 0;  // rough expected wear of the roll position
  double noise_sd_um = 0;  // sigma0, the gauge's noise on a barely worn roll
  // Relative spread of wear about expected_um; INFINITY when unknown (too
  // few readings to tell): then only the absolute bound applies.
  double relative_sd = 0;
  // A reading above expected_um * excess_factor + 4 sigma0 is "far beyond".
  double excess_factor = 0;
};

// The reason a single reading is suspect, or "" when it is plausible:
// negative beyond -4 sigma0 (or negative and 4 sd's below expected_um, sd
// = hypot(noise_sd_um, relative_sd * expected_um)), beyond the excess
// bound, or (relative_sd known) below its mirror: max(wear, sigma0) under
// expected_um / excess_factor and more than 4 sigma0 below expected_um. (The mm-for-µm
// check needs a whole file: AssessDataQuality.) `kind` is set when suspect.
std::string SuspectReading(double wear_um, const ReadingBounds& bounds,
                           DataQualityKind* kind);

struct DataQuality {
  std::vector<DataQualityIssue> issues;  // in file order per kind
  // Parallel to Dataset::measurements: "" = plausible, else the reason.
  std::vector<std::string> suspect;
  // Parallel to Dataset::profile_points: true = set aside (its profile is
  // profile_not_wear).
  std::vector<bool> suspect_point;
  // The figures the thresholds were derived from (reported in JSON).
  double wear_rate_um_per_unit = 0;  // median wear / Wang load (um·mm/kN/m)
  double noise_sd_um = 0;            // sigma0
  double log_ratio_scale = 0;        // robust sd of log(wear / load)
  double excess_factor = 0;

  int Count(DataQualityKind kind) const;
  int NumSuspect() const;
};

// Checks every measurement and mount of `data`; `lines` (may be null: no
// line numbers) are where its rows came from (DatasetLines, dataset_io.h).
DataQuality AssessDataQuality(const Dataset& data,
                              const DatasetLines* lines = nullptr);

// One centre reading as the reading checks see it: its wear and what its
// roll position rolled in its campaign (Wang's load, sum force / width *
// length over the stand's passes, kN/mm*m, and the rolled length, m).
struct ReadingExposure {
  double wear_um = 0;
  double load = 0;
  double length_m = 0;
};

// The reason the last of `readings` is suspect ("" when plausible), with
// its kind: judged among all of them by the same bounds and in the same
// words as AssessDataQuality judges a file's measurements (unit_mm,
// negative_wear, low_wear, excess_wear; the profile checks need a profile,
// the no_passes check a mount). What the daemon runs on each new reading,
// on the exposures its catalog keeps instead of re-reading the passes.
std::string JudgeLastReading(const std::vector<ReadingExposure>& readings,
                             DataQualityKind* kind);

// `data` without its suspect measurements (what fitting sees), in place:
// the kept rows keep their order; profile points set aside go too.
void RemoveSuspects(const DataQuality& quality, Dataset* data);

// `data` without its suspect measurements (what fitting sees).
Dataset WithoutSuspects(const Dataset& data, const DataQuality& quality);

// A short text: counts by kind and the first `max_listed` issues with their
// location, e.g.
//   data quality: 1 suspect measurement (excluded from fitting): 1 negative_wear
//     measurements.csv:17 F6/top of campaign 'C0042': -62.6 um is below ...
// "data quality: no warnings" when there is none.
std::string DataQualitySummary(const DataQuality& quality, int max_listed = 5);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_DATASET_DATA_QUALITY_H_
