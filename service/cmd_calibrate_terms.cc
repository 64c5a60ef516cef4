// `rollwear calibrate --data DIR --terms FILE [--split-seed N | --split FILE]
// [--predictions FILE] [--json FILE]`:
// recalibrates a model whose definition includes terms adopted from a
// diagnosis. FILE is the JSON of `rollwear diagnose --json` (its
// "adopted_model") or a model JSON with a "terms" array. The option-1
// coefficients and the terms' parameters are refitted jointly on the seeded
// training campaigns (core/fit/term_refit.h) and evaluated coil by coil on the
// validation campaigns (core/model/model_eval.h), beside the plain option-1
// calibration on the same split, so the gain of the adopted physics is shown.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/dataset/dataset_io.h"
#include "core/model/metrics.h"
#include "core/model/model_eval.h"
#include "core/fit/identification.h"
#include "core/fit/study.h"
#include "core/fit/term_refit.h"
#include "service/calibrate_per_roll.h"
#include "service/calibrate_terms.h"
#include "service/data_quality_cli.h"
#include "service/predictions_csv.h"
#include "storage/model_codec.h"

namespace rollwear::cli {

namespace {

// One line per refitted term: its parameters, or for the per-roll family
// the range of its multipliers (not 50 numbers).
void PrintTerm(const ModelTerm& t) {
  std::printf("  term %-28s %-12s", t.covariate.c_str(), TermFormName(t.form));
  if (t.form == TermForm::kRollEffect && !t.params.empty()) {
    const auto [lo, hi] = std::minmax_element(t.params.begin(), t.params.end());
    std::printf(" %d rolls, multipliers x %.2f to x %.2f, prior sd %.3f\n",
                t.num_levels, std::exp(*lo), std::exp(*hi), t.scale);
    return;
  }
  std::printf(" params");
  for (double p : t.params) std::printf(" %.5g", p);
  std::printf("\n");
}

// The terms ride on option 1's K: when that K is not identified by this
// data on its own, say so (identification.h).
Identification PrintBaseIdentification(const SplitCalibration& baseline) {
  const Identification id =
      JudgeIdentification(baseline.result, baseline.train, baseline.validation);
  std::printf("option 1's K on this data, without the terms: %s\n",
              id.Sentence().c_str());
  return id;
}

}  // namespace

int RunCalibrateWithTerms(const CalibrateArgs& args) {
  const std::string& terms_file = args.terms;
  const std::string& json_file = args.json;
  const uint64_t split_seed = args.split_seed;
  const auto start = std::chrono::steady_clock::now();
  std::ifstream in(terms_file);
  if (!in) {
    std::fprintf(stderr, "rollwear calibrate: cannot read --terms %s\n",
                 terms_file.c_str());
    return 1;
  }
  std::stringstream text;
  text << in.rdbuf();
  StatusOr<std::vector<ModelTerm>> terms =
      storage::DecodeModelTerms(text.str());
  if (!terms.ok()) {
    std::fprintf(stderr, "rollwear calibrate: %s: %s\n", terms_file.c_str(),
                 terms.status().message().c_str());
    return 1;
  }
  CheckedDataset checked;
  if (int code = ReadCheckedDataset("calibrate", args.data, args.strict, &checked)) {
    return code;
  }
  std::optional<CampaignSplit> given;
  SplitDataset applied;
  if (int code = ApplySplitFile("calibrate", args.split, &checked, &given, &applied)) {
    return code;
  }
  const Dataset* data = &checked.fit;
  const DatasetIndex index(*data);
  StatusOr<WearStatistics> stats = Aggregate(*data, index, WearLaw::kWang);
  if (!stats.ok()) {
    std::fprintf(stderr, "rollwear calibrate: %s\n",
                 stats.status().message().c_str());
    return 1;
  }
  const CampaignSplit split = SplitOrGiven(*stats, split_seed, given);
  StatusOr<SplitCalibration> baseline =
      CalibrateOnSplit(*stats, split, CalibrationOptions{});
  if (!baseline.ok()) {
    std::fprintf(stderr, "rollwear calibrate: %s\n",
                 baseline.status().message().c_str());
    return 1;
  }
  StatusOr<WearModel> model =
      RefitWithTerms(*data, WearLaw::kWang, *terms, split.train);
  if (!model.ok()) {
    std::fprintf(stderr, "rollwear calibrate: %s\n",
                 model.status().message().c_str());
    return 1;
  }
  const std::vector<MeasuredPrediction> pred_train =
      PredictMeasured(*model, *data, index, split.train);
  const std::vector<MeasuredPrediction> pred_val =
      PredictMeasured(*model, *data, index, split.validation);
  const FitMetrics train = MetricsOfPredictions(pred_train);
  const FitMetrics val = MetricsOfPredictions(pred_val);
  if (!args.predictions.empty()) {
    std::vector<PredictionRow> rows =
        MeasuredPredictionRows(*data, *model, pred_train, true, applied.original_id);
    const std::vector<PredictionRow> v =
        MeasuredPredictionRows(*data, *model, pred_val, false, applied.original_id);
    rows.insert(rows.end(), v.begin(), v.end());
    const Status written = WritePredictionsCsv(args.predictions, rows);
    if (!written.ok()) {
      std::fprintf(stderr, "rollwear calibrate: %s\n", written.message().c_str());
      return 1;
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();

  std::printf("wang law, option 1 with %zu adopted term(s) from %s\n",
              terms->size(), terms_file.c_str());
  for (const ModelTerm& t : model->terms) PrintTerm(t);
  const Identification id = PrintBaseIdentification(*baseline);
  std::printf("%-28s %12s\n", "coefficient", "value");
  for (const auto& [name, value] : model->NamedCoefficients()) {
    std::printf("%-28s %12.6g\n", name.c_str(), value);
  }
  std::printf("                 %14s %14s\n", "option 1", "with terms");
  std::printf("training gap     %11.1f µm %11.1f µm   (%d measurements)\n",
              baseline->train.gap_um, train.gap_um, train.n);
  std::printf("validation gap   %11.1f µm %11.1f µm   (%d measurements)\n",
              baseline->validation.gap_um, val.gap_um, val.n);
  std::printf("noise model: sd %.1f µm + %.1f %% of wear\n", model->noise_sd_um,
              100 * model->noise_rel);

  if (!json_file.empty()) {
    nlohmann::json j;
    j["model"] = "wang";
    j["option"] = 1;
    nlohmann::json coef = nlohmann::json::object();
    for (const auto& [name, value] : model->NamedCoefficients())
      coef[name] = value;
    j["coefficients"] = coef;
    j["terms"] = nlohmann::json::parse(storage::EncodeTerms(model->terms));
    j["data_quality"] = DataQualityJson(checked.quality);
    j["cost"] = train.cost;
    j["gap_train_um"] = train.gap_um;
    j["gap_val_um"] = val.gap_um;
    j["n_train"] = train.n;
    j["n_val"] = val.n;
    j["baseline"] = {{"gap_train_um", baseline->train.gap_um},
                     {"gap_val_um", baseline->validation.gap_um},
                     {"identification", IdentificationJson(id)}};
    j["noise"] = {{"sd_um", model->noise_sd_um}, {"rel", model->noise_rel}};
    j["split_seed"] = split_seed;
    j["seconds"] = seconds;
    std::ofstream out(json_file);
    out << j.dump(2) << "\n";
    if (!out) {
      std::fprintf(stderr, "rollwear calibrate: cannot write %s\n",
                   json_file.c_str());
      return 1;
    }
  }
  return 0;
}

}  // namespace rollwear::cli
