// `rollwear ann --data DIR [--json FILE] [--seeds N] [--split-seed N]
//  [--seed N] [--select mean|best] [--max-epochs N] [--threads N]
//  [--weight-decay X] [--no-early-stopping] [--linear-skip]
//  [--model-out FILE] [--with-diagnosis] [--figures DIR] [--split FILE]
//  [--predictions FILE]`
// Trains the recurrent K-estimator and compares it with classical
// calibration (Wang, option 1) on the same split as `calibrate`: the study's
// Table 4 analogue (core/ann/ann_study.h). --model-out writes the trained model
// in its text form (core/model/ann_model.h). --with-diagnosis adds the diagnosis
// engine's adopted model on the same split as a third row. --figures DIR
// writes measured vs calculated wear per stand, classical against the ANN
// (core/report/study_figures.h). --predictions FILE writes the network's
// prediction of every measured reading of the split, in the format of
// `calibrate --predictions` (service/predictions_csv.h), without an
// interval: the network has no noise model.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "api/json_number.h"
#include "core/ann/ann_study.h"
#include "core/dataset/dataset_io.h"
#include "core/report/study_figures.h"
#include "service/commands.h"
#include "service/data_quality_cli.h"
#include "service/predictions_csv.h"

namespace rollwear::cli {
namespace {

nlohmann::json Gaps(const FitMetrics& train, const FitMetrics& val) {
  return {{"gap_train_um", JsonNumber(train.gap_um)},
          {"gap_val_um", JsonNumber(val.gap_um)},
          {"cost_train", JsonNumber(train.cost)},
          {"cost_val", JsonNumber(val.cost)},
          {"val_over_train", JsonNumber(val.gap_um / train.gap_um)}};
}

int Fail(const std::string& message, int code) {
  std::fprintf(stderr, "rollwear ann: %s\n", message.c_str());
  return code;
}

// The spread of the ensemble members' gaps on the training (`validation`
// false) or validation campaigns.
nlohmann::json SeedSpread(const AnnComparison& c, bool validation) {
  double mean, sd, lo, hi;
  MemberGapSpread(c, validation, &mean, &sd, &lo, &hi);
  return {{"mean_um", JsonNumber(mean)},
          {"sd_um", JsonNumber(sd)},
          {"min_um", JsonNumber(lo)},
          {"max_um", JsonNumber(hi)}};
}

// --json FILE: the comparison as one JSON object.
nlohmann::json AnnJson(const AnnComparison& c,
                       const AnnComparisonOptions& options,
                       const DataQuality& quality) {
  nlohmann::json j;
  j["classical"] = Gaps(c.classical_train, c.classical_val);
  j["classical"]["model"] = "wang";
  j["classical"]["option"] = options.classical.option;
  j["classical"]["parameters"] = c.classical_parameters;
  j["classical"]["bias_above_300_um"] = JsonNumber(c.classical_bias_above_300_um);
  j["classical"]["seconds"] = c.classical_seconds;
  j["ann"] = Gaps(c.ann_train, c.ann_val);
  j["ann"]["mode"] = c.ann_mode;
  j["ann"]["parameters_per_member"] = c.ann_parameters;
  j["ann"]["hidden"] = {options.training.hidden1, options.training.hidden2};
  j["ann"]["weight_decay"] = options.training.weight_decay;
  j["ann"]["early_stopping"] = options.training.early_stopping;
  j["ann"]["linear_skip"] = options.training.linear_skip;
  j["ann"]["max_epochs"] = options.training.max_epochs;
  j["ann"]["bias_above_300_um"] = JsonNumber(c.ann_bias_above_300_um);
  j["ann"]["seconds"] = c.ann_seconds;
  j["ann"]["best_member"] = c.best_member;
  if (c.has_adopted) {
    j["adopted"] = Gaps(c.adopted_train, c.adopted_val);
    j["adopted"]["findings"] = c.adopted_findings;
    j["adopted"]["parameters"] = c.adopted_parameters;
    j["adopted"]["seconds"] = c.adopted_seconds;
  }
  j["delta_percent"] = {
      {"train", JsonNumber(100 * (c.ann_train.gap_um - c.classical_train.gap_um) /
                    c.classical_train.gap_um)},
      {"val", JsonNumber(100 * (c.ann_val.gap_um - c.classical_val.gap_um) /
                  c.classical_val.gap_um)}};
  j["seed_spread"]["train"] = SeedSpread(c, false);
  j["seed_spread"]["val"] = SeedSpread(c, true);
  nlohmann::json members = nlohmann::json::array();
  for (const AnnMemberFigures& f : c.members) {
    members.push_back({{"seed", f.training.seed},
                       {"epochs", f.training.epochs},
                       {"best_epoch", f.training.best_epoch},
                       {"holdout_gap_um", JsonNumber(f.training.holdout_gap_um)},
                       {"gap_train_um", JsonNumber(f.train.gap_um)},
                       {"gap_val_um", JsonNumber(f.validation.gap_um)}});
  }
  j["members"] = members;
  j["split_seed"] = options.split_seed;
  j["n_train"] = c.n_train;
  j["n_val"] = c.n_val;
  j["n_above_300"] = c.n_above_300;
  j["seconds"] = c.seconds;
  j["data_quality"] = DataQualityJson(quality);
  return j;
}

// --predictions FILE: the ensemble's prediction of each measured reading of
// the comparison's split (core/ann/ann_study.h PredictAnnOnSplit), train
// then validation, lo_um/hi_um empty.
Status WriteAnnPredictions(const std::string& file, const Dataset& data,
                           const AnnComparisonOptions& options,
                           const AnnComparison& c,
                           const std::vector<std::string>& original_id) {
  ROLLWEAR_ASSIGN_OR_RETURN(AnnSplitPredictions p,
                            PredictAnnOnSplit(data, options, c));
  std::unordered_map<int, double> of;
  for (size_t i = 0; i < p.observations.size(); ++i) {
    of[p.observations[i]] = p.predicted_um[i];
  }
  return WritePredictionsCsv(
      file, PredictionRows(data, p.stats, p.split, original_id,
                           [&of](int o, double* predicted, double* sd) {
                             *predicted = of.at(o);
                             *sd = NAN;
                           }));
}

}  // namespace

int RunAnn(const AnnArgs& args) {
  AnnComparisonOptions options = args.options;
  options.training.early_stopping = !args.no_early_stopping;
  const std::string& select = args.select;
  if (select == "best") {
    options.training.ensemble = AnnEnsembleMode::kBestOnHoldout;
  } else if (select != "mean") {
    return Fail("--select must be mean or best", 2);
  }
  std::string error;
  if (!options.training.IsValid(&error)) return Fail(error, 2);

  CheckedDataset checked;
  if (int code = ReadCheckedDataset("ann", args.data, args.strict, &checked)) {
    return code;
  }
  SplitDataset applied;
  if (int code = ApplySplitFile("ann", args.split, &checked,
                                &options.given_split, &applied)) {
    return code;
  }
  const Dataset* data = &checked.fit;
  StatusOr<AnnComparison> c = CompareAnnWithClassical(*data, options);
  if (!c.ok()) return Fail(c.status().message(), 1);
  std::printf("%s", AnnComparisonMarkdown(*c).c_str());

  if (!args.figures.empty()) {
    StatusOr<SvgFigure> figure = AnnFigure(*data, options, *c);
    const Status written =
        figure.ok() ? WriteFigures(args.figures, {*figure}) : figure.status();
    if (!written.ok()) return Fail(written.message(), 1);
    std::printf("wrote %s/%s\n", args.figures.c_str(), figure->file_name.c_str());
  }

  if (!args.predictions.empty()) {
    const Status written = WriteAnnPredictions(args.predictions, *data, options,
                                               *c, applied.original_id);
    if (!written.ok()) return Fail(written.message(), 1);
  }
  if (!args.model_out.empty()) {
    std::ofstream out(args.model_out);
    out << SerializeAnnModel(c->model);
    if (!out) return Fail("cannot write " + args.model_out, 1);
  }
  if (!args.json.empty()) {
    const nlohmann::json j = AnnJson(*c, options, checked.quality);
    std::ofstream out(args.json);
    out << j.dump(2) << "\n";
    if (!out) return Fail("cannot write " + args.json, 1);
  }
  return 0;
}

}  // namespace rollwear::cli
