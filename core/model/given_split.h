// A split given as a file (`--split FILE` of calibrate, study, diagnose and
// ann; ../shared/api.md): CSV `campaign_id,stand,position,set`, set =
// `train` or `validation`, one row per measured reading. Readings the file
// does not list are not used. Unlike the seeded split (SplitCampaigns,
// metrics.h), a given split may put the readings of one campaign in both
// sets (the study's authors split roll by roll).
//
// Every tool computes on a CampaignSplit (lists of campaign indices), so a
// campaign whose readings fall in both sets is split into two campaigns of
// the same passes: the original (its training readings, the rolls they
// measure and the passes of their stands) and a copy "<id>~validation"
// (its validation readings, their rolls, the passes of their stands under
// coil ids "<coil>~validation"). A roll's predicted wear depends only on
// the passes of its own stand in its own campaign, so every prediction is
// the one the unsplit campaign gives; a roll appears in one of the two only.
//
// Thread-safety: pure functions.
#ifndef ROLLWEAR_CORE_MODEL_GIVEN_SPLIT_H_
#define ROLLWEAR_CORE_MODEL_GIVEN_SPLIT_H_

#include <string>
#include <string_view>
#include <vector>

#include "core/base/status.h"
#include "core/dataset/dataset.h"
#include "core/model/metrics.h"

namespace rollwear {

struct SplitRow {
  std::string campaign_id;
  int stand = 0;
  Position position = Position::kTop;
  bool train = true;
  int line = 0;  // line in the file, for messages
};

// Parses the split file's text; `file` labels errors ("split.csv:12:
// set must be train or validation, got 'dev'"). A duplicate reading, an
// unknown stand or position, or a missing column is an error.
StatusOr<std::vector<SplitRow>> ParseSplitCsv(std::string text,
                                              std::string_view file);

struct SplitDataset {
  Dataset data;         // the readings of the split only, campaigns split
  CampaignSplit split;  // over data's campaign indices
  // The campaign id each of data's campaigns came from (the copy's too).
  std::vector<std::string> original_id;
  int readings_train = 0;
  int readings_validation = 0;
  int readings_not_listed = 0;  // measured, not in the file: not used
  int rows_not_measured = 0;    // in the file, no such reading: ignored
  int campaigns_split = 0;      // campaigns with readings in both sets
};

// The dataset restricted to the readings of `rows`, with the split.
StatusOr<SplitDataset> ApplySplit(const Dataset& data,
                                  const std::vector<SplitRow>& rows);

// The sentence a command prints: "split FILE: 812 training and 418
// validation readings (37 campaigns have both; 12 measured readings not
// listed, not used; 3 listed readings not measured)".
std::string DescribeSplit(const SplitDataset& s, const std::string& file);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_GIVEN_SPLIT_H_
