// `rollwear ann --data DIR [--json FILE] [--seeds N] [--split-seed N]
//  [--seed N] [--select mean|best] [--max-epochs N] [--threads N]
//  [--weight-decay X] [--no-early-stopping] [--linear-skip]
//  [--model-out FILE] [--with-diagnosis] [--figures DIR]`
// Trains the recurrent K-estimator and compares it with classical
// calibration (Wang, option 1) on the same split as `calibrate`: the study's
// Table 4 analogue (core/ann/ann_study.h). --model-out writes the trained model
// in its text form (core/model/ann_model.h). --with-diagnosis adds the diagnosis
// engine's adopted model on the same split as a third row. --figures DIR
// writes measured vs calculated wear per stand, classical against the ANN
// (core/report/study_figures.h).
#include <cmath>
#include <cstdio>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/ann/ann_study.h"
#include "core/dataset/dataset_io.h"
#include "core/report/study_figures.h"
#include "service/commands.h"
#include "service/flags.h"

namespace rollwear::cli {
namespace {

nlohmann::json Num(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

nlohmann::json Gaps(const FitMetrics& train, const FitMetrics& val) {
  return {{"gap_train_um", Num(train.gap_um)},
          {"gap_val_um", Num(val.gap_um)},
          {"cost_train", Num(train.cost)},
          {"cost_val", Num(val.cost)},
          {"val_over_train", Num(val.gap_um / train.gap_um)}};
}

int Fail(const std::string& message, int code) {
  std::fprintf(stderr, "rollwear ann: %s\n", message.c_str());
  return code;
}

}  // namespace

int RunAnn(const Args& args) {
  Flags flags;
  std::string error;
  if (!flags.Parse(args,
                   {"data", "json", "seeds", "split-seed", "seed", "select",
                    "max-epochs", "threads", "model-out", "weight-decay",
                    "no-early-stopping", "linear-skip", "with-diagnosis", "figures"},
                   {"no-early-stopping", "linear-skip", "with-diagnosis"}, &error)) {
    return Fail(error, 2);
  }
  if (!flags.Has("data")) return Fail("--data DIR is required", 2);
  AnnComparisonOptions options;
  long long seeds = 5, split_seed = 1, seed = 1, max_epochs = 0, threads = 2;
  if (!flags.GetInt("seeds", 5, &seeds, &error) ||
      !flags.GetInt("split-seed", 1, &split_seed, &error) ||
      !flags.GetInt("seed", 1, &seed, &error) ||
      !flags.GetInt("max-epochs", options.training.max_epochs, &max_epochs,
                    &error) ||
      !flags.GetInt("threads", 2, &threads, &error) ||
      !flags.GetDouble("weight-decay", options.training.weight_decay,
                       &options.training.weight_decay, &error)) {
    return Fail(error, 2);
  }
  options.training.early_stopping = !flags.Has("no-early-stopping");
  options.training.linear_skip = flags.Has("linear-skip");
  options.compare_adopted = flags.Has("with-diagnosis");
  options.split_seed = static_cast<uint64_t>(split_seed);
  options.training.members = static_cast<int>(seeds);
  options.training.seed = static_cast<uint64_t>(seed);
  options.training.max_epochs = static_cast<int>(max_epochs);
  options.training.threads = static_cast<int>(threads);
  const std::string select = flags.Get("select", "mean");
  if (select == "best") {
    options.training.ensemble = AnnEnsembleMode::kBestOnHoldout;
  } else if (select != "mean") {
    return Fail("--select must be mean or best", 2);
  }
  if (!options.training.IsValid(&error)) return Fail(error, 2);

  StatusOr<Dataset> data = ReadDataset(flags.Get("data"));
  if (!data.ok()) return Fail(data.status().message(), 1);
  StatusOr<AnnComparison> c = CompareAnnWithClassical(*data, options);
  if (!c.ok()) return Fail(c.status().message(), 1);
  std::printf("%s", AnnComparisonMarkdown(*c).c_str());

  if (flags.Has("figures")) {
    StatusOr<SvgFigure> figure = AnnFigure(*data, options, *c);
    const Status written =
        figure.ok() ? WriteFigures(flags.Get("figures"), {*figure}) : figure.status();
    if (!written.ok()) return Fail(written.message(), 1);
    std::printf("wrote %s/%s\n", flags.Get("figures").c_str(), figure->file_name.c_str());
  }

  if (flags.Has("model-out")) {
    std::ofstream out(flags.Get("model-out"));
    out << SerializeAnnModel(c->model);
    if (!out) return Fail("cannot write " + flags.Get("model-out"), 1);
  }
  if (flags.Has("json")) {
    nlohmann::json j;
    j["classical"] = Gaps(c->classical_train, c->classical_val);
    j["classical"]["model"] = "wang";
    j["classical"]["option"] = options.classical.option;
    j["classical"]["parameters"] = c->classical_parameters;
    j["classical"]["bias_above_300_um"] = Num(c->classical_bias_above_300_um);
    j["classical"]["seconds"] = c->classical_seconds;
    j["ann"] = Gaps(c->ann_train, c->ann_val);
    j["ann"]["mode"] = c->ann_mode;
    j["ann"]["parameters_per_member"] = c->ann_parameters;
    j["ann"]["hidden"] = {options.training.hidden1, options.training.hidden2};
    j["ann"]["weight_decay"] = options.training.weight_decay;
    j["ann"]["early_stopping"] = options.training.early_stopping;
    j["ann"]["linear_skip"] = options.training.linear_skip;
    j["ann"]["max_epochs"] = options.training.max_epochs;
    j["ann"]["bias_above_300_um"] = Num(c->ann_bias_above_300_um);
    j["ann"]["seconds"] = c->ann_seconds;
    j["ann"]["best_member"] = c->best_member;
    if (c->has_adopted) {
      j["adopted"] = Gaps(c->adopted_train, c->adopted_val);
      j["adopted"]["findings"] = c->adopted_findings;
      j["adopted"]["parameters"] = c->adopted_parameters;
      j["adopted"]["seconds"] = c->adopted_seconds;
    }
    j["delta_percent"] = {
        {"train", Num(100 * (c->ann_train.gap_um - c->classical_train.gap_um) /
                      c->classical_train.gap_um)},
        {"val", Num(100 * (c->ann_val.gap_um - c->classical_val.gap_um) /
                    c->classical_val.gap_um)}};
    double mean, sd, lo, hi;
    MemberGapSpread(*c, false, &mean, &sd, &lo, &hi);
    j["seed_spread"]["train"] = {{"mean_um", Num(mean)},
                                 {"sd_um", Num(sd)},
                                 {"min_um", Num(lo)},
                                 {"max_um", Num(hi)}};
    MemberGapSpread(*c, true, &mean, &sd, &lo, &hi);
    j["seed_spread"]["val"] = {{"mean_um", Num(mean)},
                               {"sd_um", Num(sd)},
                               {"min_um", Num(lo)},
                               {"max_um", Num(hi)}};
    nlohmann::json members = nlohmann::json::array();
    for (const AnnMemberFigures& f : c->members) {
      members.push_back({{"seed", f.training.seed},
                         {"epochs", f.training.epochs},
                         {"best_epoch", f.training.best_epoch},
                         {"holdout_gap_um", Num(f.training.holdout_gap_um)},
                         {"gap_train_um", Num(f.train.gap_um)},
                         {"gap_val_um", Num(f.validation.gap_um)}});
    }
    j["members"] = members;
    j["split_seed"] = split_seed;
    j["n_train"] = c->n_train;
    j["n_val"] = c->n_val;
    j["n_above_300"] = c->n_above_300;
    j["seconds"] = c->seconds;
    std::ofstream out(flags.Get("json"));
    out << j.dump(2) << "\n";
    if (!out) return Fail("cannot write " + flags.Get("json"), 1);
  }
  return 0;
}

}  // namespace rollwear::cli
