#include "core/ann/ann_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include "core/model/aggregation.h"
#include "core/ann/ann_data.h"
#include "core/ann/ann_bptt.h"
#include "core/diagnosis/diagnosis.h"
#include "core/model/model_eval.h"
#include "core/fit/study.h"

namespace rollwear {
namespace {

double BiasAbove300(const AnnInputs& in, const std::vector<int>& seqs,
                    const std::vector<double>& pred) {
  double sum = 0;
  int n = 0;
  for (size_t k = 0; k < seqs.size(); ++k) {
    if (pred[k] > 300) {  // by prediction, as CalibrateOnSplit does
      sum += in.sequences[seqs[k]].measured_um - pred[k];
      ++n;
    }
  }
  return n > 0 ? sum / n : std::numeric_limits<double>::quiet_NaN();
}

std::string Fmt(const char* format, double v) {
  if (!std::isfinite(v)) return "–";
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

}  // namespace

StatusOr<AnnComparison> CompareAnnWithClassical(
    const Dataset& data, const AnnComparisonOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (options.classical.law != WearLaw::kWang) {
    return Status::InvalidArgument(
        "ann comparison: the classical model must use Wang's law, as the "
        "ANN does");
  }
  const DatasetIndex index(data);
  ROLLWEAR_ASSIGN_OR_RETURN(WearStatistics stats,
                            Aggregate(data, index, WearLaw::kWang));
  const CampaignSplit split =
      SplitOrGiven(stats, options.split_seed, options.given_split);
  // Observation indices double as sequence indices (BuildAnnInputs keeps the
  // order of stats.observations).
  const std::vector<int> train = stats.MeasuredObservations(split.train);
  const std::vector<int> val = stats.MeasuredObservations(split.validation);

  AnnComparison c;
  c.n_campaigns = static_cast<int>(data.campaigns.size());
  c.n_coils = static_cast<int>(data.coil_ids.size());
  c.n_train = static_cast<int>(train.size());
  c.n_val = static_cast<int>(val.size());
  c.split_seed = options.split_seed;

  ROLLWEAR_ASSIGN_OR_RETURN(SplitCalibration classical,
                            CalibrateOnSplit(stats, split, options.classical));
  c.classical_train = classical.train;
  c.classical_val = classical.validation;
  c.classical_bias_above_300_um = classical.bias_above_300_um;
  c.n_above_300 = classical.n_above_300;
  c.classical_parameters = classical.result.summary.num_free_parameters;
  c.classical_seconds = classical.result.summary.seconds;

  const AnnTrainingOptions& to = options.training;
  ROLLWEAR_ASSIGN_OR_RETURN(
      AnnModel skeleton,
      FitAnnScaling(data, index, stats, split.train, to.hidden1, to.hidden2));
  const AnnInputs inputs = BuildAnnInputs(skeleton, data, index, stats);
  ROLLWEAR_ASSIGN_OR_RETURN(AnnTrainingResult trained,
                            TrainAnn(skeleton, inputs, train, to));
  c.ann_seconds = trained.seconds;
  c.model = trained.model;
  c.best_member = trained.best_member;
  // Trained weights per member (q is frozen at 0 without the skip path).
  c.ann_parameters = trained.all_members[0].num_parameters() -
                     (to.linear_skip ? 0 : skeleton.num_inputs());
  c.ann_mode = to.ensemble == AnnEnsembleMode::kMean
                   ? "ensemble mean of " +
                         std::to_string(c.model.members.size()) + " members" +
                         (to.linear_skip ? ", linear skip" : "")
                   : "best-on-holdout member (seed " +
                         std::to_string(c.best_member) + ")";
  const std::vector<double> pred_train = PredictAnn(c.model, inputs, train);
  const std::vector<double> pred_val = PredictAnn(c.model, inputs, val);
  c.ann_train = AnnMetrics(inputs, train, pred_train);
  c.ann_val = AnnMetrics(inputs, val, pred_val);
  c.ann_bias_above_300_um = BiasAbove300(inputs, val, pred_val);
  for (size_t m = 0; m < trained.all_members.size(); ++m) {
    AnnModel single = skeleton;
    single.members = {trained.all_members[m]};
    AnnMemberFigures f;
    f.training = trained.members[m];
    f.train = AnnMetrics(inputs, train, PredictAnn(single, inputs, train));
    f.validation = AnnMetrics(inputs, val, PredictAnn(single, inputs, val));
    c.members.push_back(f);
  }
  if (options.compare_adopted) {
    DiagnosisOptions d;
    d.split_seed = options.split_seed;
    d.given_split = options.given_split;
    ROLLWEAR_ASSIGN_OR_RETURN(DiagnosisReport r, Diagnose(data, d));
    c.has_adopted = true;
    c.adopted_seconds = r.seconds;
    c.adopted_train = MetricsOfPredictions(
        PredictMeasured(r.adopted_model, data, index, split.train));
    c.adopted_val = MetricsOfPredictions(
        PredictMeasured(r.adopted_model, data, index, split.validation));
    c.adopted_parameters = static_cast<int>(r.coefficients.size());
    for (const ModelTerm& t : r.adopted_model.terms)
      c.adopted_parameters += t.NumParams();
    for (const Finding& f : r.findings) {
      c.adopted_findings.push_back(f.covariate + " (" + f.mechanism + ")");
    }
  }
  c.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  return c;
}

StatusOr<AnnSplitPredictions> PredictAnnOnSplit(
    const Dataset& data, const AnnComparisonOptions& options,
    const AnnComparison& comparison) {
  const DatasetIndex index(data);
  AnnSplitPredictions p;
  ROLLWEAR_ASSIGN_OR_RETURN(p.stats, Aggregate(data, index, WearLaw::kWang));
  p.split = SplitOrGiven(p.stats, options.split_seed, options.given_split);
  p.observations = p.stats.MeasuredObservations(p.split.train);
  p.num_train = static_cast<int>(p.observations.size());
  for (int o : p.stats.MeasuredObservations(p.split.validation)) {
    p.observations.push_back(o);
  }
  // Observation indices double as sequence indices (BuildAnnInputs).
  const AnnInputs inputs = BuildAnnInputs(comparison.model, data, index, p.stats);
  p.predicted_um = PredictAnn(comparison.model, inputs, p.observations);
  return p;
}

StatusOr<WearModel> TrainServableAnn(const Dataset& data,
                                     const std::vector<int>& train_campaigns,
                                     const AnnTrainingOptions& options) {
  const DatasetIndex index(data);
  ROLLWEAR_ASSIGN_OR_RETURN(WearStatistics stats,
                            Aggregate(data, index, WearLaw::kWang));
  const std::vector<int> train = stats.MeasuredObservations(train_campaigns);
  if (train.empty()) {
    return Status::FailedPrecondition("no measured roll in the training campaigns");
  }
  ROLLWEAR_ASSIGN_OR_RETURN(AnnModel skeleton,
                            FitAnnScaling(data, index, stats, train_campaigns,
                                          options.hidden1, options.hidden2));
  const AnnInputs inputs = BuildAnnInputs(skeleton, data, index, stats);
  ROLLWEAR_ASSIGN_OR_RETURN(AnnTrainingResult trained,
                            TrainAnn(skeleton, inputs, train, options));
  WearModel model;
  model.law = WearLaw::kWang;
  model.ann = std::make_shared<const AnnModel>(std::move(trained.model));
  const std::vector<MeasuredPrediction> fit =
      PredictMeasured(model, data, index, train_campaigns);
  std::vector<double> pred, err;
  for (const MeasuredPrediction& p : fit) {
    pred.push_back(p.wear_um);
    err.push_back(p.measured_um - p.wear_um);
  }
  FitNoiseModel(pred, err, &model);
  return model;
}

void MemberGapSpread(const AnnComparison& c, bool validation, double* mean,
                     double* sd, double* min, double* max) {
  const size_t n = c.members.size();
  double s = 0, s2 = 0;
  *min = std::numeric_limits<double>::infinity();
  *max = -*min;
  for (const AnnMemberFigures& f : c.members) {
    const double g = validation ? f.validation.gap_um : f.train.gap_um;
    s += g;
    *min = std::min(*min, g);
    *max = std::max(*max, g);
  }
  *mean = n > 0 ? s / n : std::numeric_limits<double>::quiet_NaN();
  for (const AnnMemberFigures& f : c.members) {
    const double g = validation ? f.validation.gap_um : f.train.gap_um;
    s2 += (g - *mean) * (g - *mean);
  }
  *sd = n > 1 ? std::sqrt(s2 / (n - 1)) : 0;
}

std::string AnnComparisonMarkdown(const AnnComparison& c) {
  std::string out = StudyDatasetMarkdown(c);
  char buf[512];
  out += "Table 4 - classical calibration vs recurrent ANN (Wang's law)\n\n";
  out +=
      "| model | params | gap train µm | gap val µm | val/train | "
      "bias pred >300 µm (n) | s |\n|---|---|---|---|---|---|---|\n";
  auto row = [&](const std::string& name, int params, const FitMetrics& tr,
                 const FitMetrics& va, double bias, double seconds) {
    std::snprintf(
        buf, sizeof(buf), "| %s | %d | %s | %s | %s | %s (%d) | %s |\n",
        name.c_str(), params, Fmt("%.1f", tr.gap_um).c_str(),
        Fmt("%.1f", va.gap_um).c_str(),
        Fmt("%.2f", va.gap_um / tr.gap_um).c_str(), Fmt("%+.1f", bias).c_str(),
        c.n_above_300, Fmt("%.2f", seconds).c_str());
    out += buf;
  };
  row("classical (option 1)", c.classical_parameters, c.classical_train,
      c.classical_val, c.classical_bias_above_300_um, c.classical_seconds);
  row("ANN, " + c.ann_mode, c.ann_parameters, c.ann_train, c.ann_val,
      c.ann_bias_above_300_um, c.ann_seconds);
  if (c.has_adopted) {
    row("diagnosis, adopted model", c.adopted_parameters, c.adopted_train,
        c.adopted_val, std::numeric_limits<double>::quiet_NaN(), c.adopted_seconds);
  }
  auto delta = [](double ann, double cl) { return 100 * (ann - cl) / cl; };
  std::snprintf(
      buf, sizeof(buf), "| Δ %% (ANN vs classical) | | %s | %s | | | |\n\n",
      Fmt("%+.1f", delta(c.ann_train.gap_um, c.classical_train.gap_um)).c_str(),
      Fmt("%+.1f", delta(c.ann_val.gap_um, c.classical_val.gap_um)).c_str());
  out += buf;
  if (c.has_adopted) {
    std::string names;
    for (const std::string& f : c.adopted_findings) names += (names.empty() ? "" : ", ") + f;
    out += "Diagnosis findings adopted: " + (names.empty() ? std::string("none") : names) +
           ".\n\n";
  }
  double mt, st, lot, hit, mv, sv, lov, hiv;
  MemberGapSpread(c, false, &mt, &st, &lot, &hit);
  MemberGapSpread(c, true, &mv, &sv, &lov, &hiv);
  std::snprintf(buf, sizeof(buf),
                "Seed spread over %zu members (each alone): training gap "
                "%.1f ± %.1f µm [%.1f, %.1f], validation gap %.1f ± %.1f µm "
                "[%.1f, %.1f] (mean ± sd [min, max]).\n\n",
                c.members.size(), mt, st, lot, hit, mv, sv, lov, hiv);
  out += buf;
  out +=
      "| member | seed | epochs | best epoch | holdout gap µm | gap train µm "
      "| gap val µm |\n|---|---|---|---|---|---|---|\n";
  for (size_t m = 0; m < c.members.size(); ++m) {
    const AnnMemberFigures& f = c.members[m];
    std::snprintf(buf, sizeof(buf),
                  "| %zu%s | %016llx | %d | %d | %.1f | %.1f | %.1f |\n", m,
                  static_cast<int>(m) == c.best_member ? " (best holdout)" : "",
                  static_cast<unsigned long long>(f.training.seed),
                  f.training.epochs, f.training.best_epoch,
                  f.training.holdout_gap_um, f.train.gap_um,
                  f.validation.gap_um);
    out += buf;
  }
  return out;
}

}  // namespace rollwear
