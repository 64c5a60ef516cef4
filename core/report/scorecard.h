// Scorecard of the diagnosis against known truths: for each case (one
// dataset with concealed effects whose truth is known, e.g. a simulator run)
// did the diagnosis name the concealed physics (covariate, and scope where
// there is one), did it name wrong physics, did it stay quiet on clean
// data, and how close did the adopted model bring the validation gap to the
// noise floor. `rollwear scorecard` (service/cmd_scorecard.cc) runs the
// simulator and Diagnose and prints these; the scoring is here so that it
// can be tested on hand-built reports. No simulator types: the truth comes
// in as a ScoreTruth, so an independent generator's truth fits as well.
//
// Covariate names count as the same physics (SameCovariate) only within
// these classes: the wear rate over calendar time {started_at, ended_at,
// rolled_at}; rolled amount along the campaign {campaign_length_before_m,
// campaign_coils_before}. measured_at (a drift of the reading, the gauge)
// and hours in service (hours_since_mount: what stoppages part from the
// rolled length) are classes of their own. Scopes must be equal (an
// everywhere-effect named at one stand is the wrong scope, and the other
// way round). Levels: when the truth lists levels, the finding must list
// them too (among others at most). An inexpressible effect is named right
// by the third verdict with its location in the unexplained list
// (LocatesMismatch).
//
// Thread-safety: pure functions over values.
#ifndef ROLLWEAR_CORE_REPORT_SCORECARD_H_
#define ROLLWEAR_CORE_REPORT_SCORECARD_H_

#include <cstdint>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "core/dataset/dataset.h"
#include "core/diagnosis/diagnosis.h"

namespace rollwear {

// One concealed effect as the scorecard sees it.
struct ConcealedEffect {
  std::string name;       // e.g. "grade_stand"
  std::string covariate;  // data-format name; "" when not expressible
  std::map<std::string, std::string> scope;  // empty: everywhere
  std::vector<std::string> levels;
  bool expressible = true;
  std::string mismatch;  // where it lives when not expressible
  // The truth's form where a form is its physics ("per_coil": wear per
  // coil, which a growth of the wear rate along the campaign, on the same
  // coil count, does not describe); "" otherwise.
  std::string form;
};

// The truth of one case. Effects that change no wear or reading (gross
// grinder errors, null variants) are not listed: a case with none is clean.
struct ScoreTruth {
  std::vector<ConcealedEffect> effects;
  // Noise-free centre wear per measurement, keyed by (campaign id, stand,
  // position): the noise floor is mean |measured - noise-free| over the
  // report's validation points.
  std::map<std::tuple<std::string, int, int>, double> noise_free_um;
};

struct CaseScore {
  std::string effect;  // the case's name ("clean", "grade_stand", ...)
  uint64_t seed = 0;
  bool clean = false;       // no concealed effect: quiet is right
  bool expressible = true;  // every concealed effect expressible
  // Every concealed effect matched by a finding (covariate, scope, levels);
  // inexpressible: verdict mismatch_located_unexplained, no finding, and
  // the unexplained list locating each effect's mismatch (LocatesMismatch).
  bool named_right = false;
  // Findings that match no concealed effect; a finding on an effect's
  // covariate and scope that names no level (e.g. an offset stated between
  // the levels) says less, not something wrong, and is not counted.
  int wrong_physics = 0;
  int num_findings = 0;
  std::string verdict;
  double gap_val_um = 0;
  double baseline_gap_val_um = 0;  // the baseline's, same campaigns
  double noise_floor_um = 0;
  double gap_ratio = 0;               // gap_val_um / noise_floor_um
  double seconds = 0;                 // wall time of Diagnose
  std::vector<std::string>
      findings;  // "covariate {scope} [levels] ?undetermined"
};

// Per case name over its seeds.
struct EffectScore {
  std::string effect;
  int cases = 0;
  bool clean = false;
  int named_right = 0;         // cases (not clean)
  int with_wrong_physics = 0;  // cases with at least one wrong finding
  int quiet = 0;               // cases with no finding
  double mean_gap_ratio = 0, max_gap_ratio = 0;
  double mean_seconds = 0;
  std::map<std::string, int> verdicts;
};

// The scope of a finding (the one place that reads Finding::scope), without
// a gate's threshold: a gated effect is named right by its gate covariate
// and side (the diagnosis places the threshold on a grid of quantiles, the
// truth anywhere).
std::map<std::string, std::string> FindingScope(const Finding& f);
// True when a finding's covariate names the same physics as the truth's.
bool SameCovariate(const std::string& truth, const std::string& found);
// True when `f` describes `e`: covariate, scope and levels.
bool Describes(const Finding& f, const ConcealedEffect& e);

// The parts of a truth's mismatch location ("campaign order x grade",
// "time (campaign order), by roll position"): split at " x " and ", by ".
std::vector<std::string> MismatchParts(const std::string& mismatch);

// True when the report's unexplained list locates the mismatch at one of
// the parts of `mismatch` (a truth's ConcealedEffect::mismatch). A part is
// read by its words: "time" or "calendar" is located by the checks along
// time (time_*, lag1_along_time, runs_along_time, spread_by_time,
// position_by_time_half, a calendar-time covariate); "campaign order"
// (without time: the order within a campaign) by campaign_coils_before,
// campaign_length_before_m, campaign_rolled_length_m or hours_since_mount;
// "grade" by dominant_grade, position_by_grade*, effect_by_grade,
// stand_by_grade or grade_by_campaign_order; "roll type" by roll_type,
// position_by_roll_type, effect_by_roll_type, effect_by_stand_roll_type or
// stand_by_roll_type; "after a stop" by after_stop or effect_by_after_stop;
// "time of day" by time_of_day; "position" or "stand"
// by roll_position, position_by_*, spread_by_position, effect_by_position,
// effect_by_stand or stand_by_*; any other
// part is a covariate name, located by that covariate's own breakdown
// (SameCovariate).
bool LocatesMismatch(const DiagnosisReport& report, const std::string& mismatch);

CaseScore ScoreCase(const std::string& effect, uint64_t seed,
                    const DiagnosisReport& report, const ScoreTruth& truth);
// In order of first appearance of each case name.
std::vector<EffectScore> Summarise(const std::vector<CaseScore>& cases);
// Markdown table of the summary (one row per case name and a total).
std::string ScorecardTable(const std::vector<EffectScore>& scores);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_REPORT_SCORECARD_H_
