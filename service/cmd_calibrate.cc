// `rollwear calibrate --data DIR [--model wang|nikitenko|cao] [--option 1|2|3]
//  [--json FILE] [--start ones|random|empirical] [--protocol exact|paper]
//  [--split-seed N] [--seed N] [--terms FILE]`
// (--terms: see service/calibrate_terms.h)
// Calibrates on a seeded 2/3 training / 1/3 validation split by campaign and
// prints the coefficients with standard errors and the figures of merit.
// --figures DIR: measured vs calculated wear per stand (training and
// validation campaigns) as DIR/measured_vs_calculated_<law>_option<N>.svg,
// and with profiles DIR/profiles_measured_vs_predicted.svg
// (core/report/profile_figures.h).
// With profiles.csv it also fits the shape of the wear across the barrel,
// first with the centre's K (core/fit/profile_fit.h), then jointly with K
// (core/fit/profile_joint.h), and prints both with the profile gap; --json
// then holds the "profile" object of api.md (the joint fit's). When the
// first stage fails (too few points) it says so on stderr and omits the
// object; when the joint fit fails, the object is the first stage's.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <utility>

#include <nlohmann/json.hpp>

#include "api/json_number.h"
#include "core/dataset/dataset_io.h"
#include "core/model/metrics.h"
#include "core/fit/identification.h"
#include "core/fit/profile_fit.h"
#include "core/fit/profile_joint.h"
#include "core/fit/study.h"
#include "core/report/profile_figures.h"
#include "core/report/study_figures.h"
#include "service/calibrate_terms.h"
#include "service/commands.h"
#include "service/data_quality_cli.h"
#include "service/calibrate_per_roll.h"
#include "service/predictions_csv.h"

namespace rollwear::cli {
namespace {

bool ParseStart(const std::string& s, InitialSet* out) {
  if (s == "ones") *out = InitialSet::kOnes;
  else if (s == "random") *out = InitialSet::kRandom;
  else if (s == "empirical") *out = InitialSet::kEmpirical;
  else return false;
  return true;
}

// --figures DIR: the calibrated model's measured vs calculated wear per
// stand, training and validation campaigns as two series.
Status WriteCalibrationFigure(const std::string& dir, const CalibrationOptions& options,
                              const WearStatistics& stats, const CampaignSplit& split,
                              const SplitCalibration& run) {
  const std::vector<int> train = stats.MeasuredObservations(split.train);
  const std::vector<int> val = stats.MeasuredObservations(split.validation);
  std::vector<int> obs = train;
  obs.insert(obs.end(), val.begin(), val.end());
  const std::vector<double> pred = PredictAll(run.result.model, stats, obs);
  ParitySeries train_s, val_s;
  char name[96];
  std::snprintf(name, sizeof(name), "training (gap %.1f µm)", run.train.gap_um);
  train_s.name = name;
  train_s.color = "#8c99a6";
  std::snprintf(name, sizeof(name), "validation (gap %.1f µm)", run.validation.gap_um);
  val_s.name = name;
  val_s.color = "#D55E00";
  for (size_t i = 0; i < obs.size(); ++i) {
    const bool is_train = i < train.size();
    train_s.calculated_um.push_back(is_train ? pred[i] : NAN);
    val_s.calculated_um.push_back(is_train ? NAN : pred[i]);
  }
  const std::string law = WearLawName(options.law);
  const std::string option = std::to_string(options.option);
  const SvgFigure figure{
      "measured_vs_calculated_" + law + "_option" + option + ".svg",
      ParityFigureSvg(law + " law, option " + option + ": measured vs calculated", stats,
                      obs, {train_s, val_s})};
  ROLLWEAR_RETURN_IF_ERROR(WriteFigures(dir, {figure}));
  std::printf("wrote %s/%s\n", dir.c_str(), figure.file_name.c_str());
  return Status::Ok();
}

// --start, --protocol and the options' own check, into `options`; 0, or
// exit code 2 after the message on stderr.
int CheckCalibrationOptions(const CalibrateArgs& args,
                            CalibrationOptions* options) {
  if (!ParseStart(args.start, &options->initial_set)) {
    std::fprintf(
        stderr,
        "rollwear calibrate: --start must be ones, random or empirical\n");
    return 2;
  }
  const std::string& protocol = args.protocol;
  if (protocol == "paper") {
    options->derivatives = DerivativeMode::kPaperForwardDifference;
  } else if (protocol != "exact") {
    std::fprintf(stderr,
                 "rollwear calibrate: --protocol must be exact or paper\n");
    return 2;
  }
  std::string error;
  if (!options->IsValid(&error)) {
    std::fprintf(stderr, "rollwear calibrate: %s\n", error.c_str());
    return 2;
  }
  return 0;
}

// A relative standard error as "12.3%" (at most 5 characters before the
// '%'), or "n/a" when it is not finite.
std::string RelativeError(double se) {
  if (!std::isfinite(se)) return "n/a";
  return std::to_string(std::lround(se * 1000) / 10.0).substr(0, 5) + "%";
}

// The report on stdout: settings, brief summary, coefficients with relative
// standard errors, training and validation figures, noise model.
void PrintCalibration(const CalibrationOptions& options,
                      const std::string& protocol, const SplitCalibration& run,
                      bool usable) {
  const CalibrationResult& r = run.result;
  const WearModel& m = r.model;
  std::printf("%s law, option %d, start %s, %s derivatives\n",
              WearLawName(options.law), options.option,
              InitialSetName(options.initial_set), protocol.c_str());
  std::printf("%s\n", r.summary.BriefReport().c_str());
  if (r.grade_shrinkage.applied) {
    std::printf("grades: %s\n", r.grade_shrinkage.Sentence().c_str());
  }
  if (r.summary.usable && !usable) {
    std::printf(
        "not usable: a roll position received no pass, or the fit is not "
        "identified (see the data quality above and the identification "
        "below)\n");
  }
  std::printf("%-28s %12s %10s\n", "coefficient", "value", "rel. s.e.");
  const auto named = m.NamedCoefficients();
  for (size_t i = 0; i < named.size(); ++i) {
    std::printf("%-28s %12.6g %10s\n", named[i].first.c_str(), named[i].second,
                RelativeError(r.std_error[i]).c_str());
  }
  std::printf("training:   %d measurements, gap %.1f µm, cost %.1f µm²\n",
              run.train.n, run.train.gap_um, run.train.cost);
  std::printf("validation: %d measurements, gap %.1f µm, cost %.1f µm²\n",
              run.validation.n, run.validation.gap_um, run.validation.cost);
  std::printf("noise model: sd %.1f µm + %.1f %% of wear\n", m.noise_sd_um,
              100 * m.noise_rel);
}

// With profiles.csv: the shape of g fitted with the centre's K, with
// standard errors, and the profile gap on training and validation.
void PrintProfileFit(const ProfileFit& fit) {
  std::printf("%-28s %12s %10s\n", "shape", "value", "s.e.");
  const auto values = ProfileShapeValues(fit.shape);
  for (int i = 0; i < kProfileShapeParameters; ++i) {
    std::printf("%-28s %12.4g %10.2g\n", ProfileShapeNames()[i].c_str(),
                values[i], fit.std_error[i]);
  }
  for (const ProfileGap* g : {&fit.train, &fit.validation}) {
    std::printf(
        "profile %-10s %d profiles, %d points, gap %.1f µm (edge zone %.1f "
        "µm over %d points, body %.1f µm over %d)\n",
        g == &fit.train ? "training:" : "validation:", g->n_profiles,
        g->n_points, g->gap_um, g->edge_um, g->n_edge, g->body_um, g->n_body);
  }
}

// The contract's "profile" object of calibrate --json (api.md).
nlohmann::json ProfileJson(const ProfileFit& fit) {
  nlohmann::json shape = nlohmann::json::object();
  nlohmann::json se = nlohmann::json::object();
  const auto values = ProfileShapeValues(fit.shape);
  for (int i = 0; i < kProfileShapeParameters; ++i) {
    shape[ProfileShapeNames()[i]] = values[i];
    se[ProfileShapeNames()[i]] = JsonNumber(fit.std_error[i]);
  }
  return {{"gap_train_um", JsonNumber(fit.train.gap_um)},
          {"gap_val_um", JsonNumber(fit.validation.gap_um)},
          {"n_points_train", fit.train.n_points},
          {"n_points_val", fit.validation.n_points},
          {"gap_edge_train_um", JsonNumber(fit.train.edge_um)},
          {"gap_body_train_um", JsonNumber(fit.train.body_um)},
          {"gap_edge_val_um", JsonNumber(fit.validation.edge_um)},
          {"gap_body_val_um", JsonNumber(fit.validation.body_um)},
          {"n_profiles_train", fit.train.n_profiles},
          {"n_profiles_val", fit.validation.n_profiles},
          {"residual_sd_um", JsonNumber(fit.residual_sd_um)},
          {"shape", shape},
          {"standard_errors", se}};
}

// The profile: the first stage (K from the centre), then the joint LM fit
// of K and shape (core/fit/profile_joint.h), printed; the "profile" object
// of --json is the joint fit's, with the first stage inside it. When a
// stage fails, says why on stderr; nullopt when there is no profile fit.
std::optional<nlohmann::json> FitProfile(const SplitCalibration& run,
                                         const Dataset& data,
                                         const DatasetIndex& index,
                                         const CampaignSplit& split,
                                         WearModel* model,
                                         ProfileShape* shape) {
  StatusOr<ProfileFit> first =
      FitProfileShape(run.result.model, data, index, split);
  if (!first.ok()) {  // the centre calibration stands; say why
    std::fprintf(stderr, "rollwear calibrate: no profile fit: %s\n",
                 first.status().message().c_str());
    return std::nullopt;
  }
  std::printf("profile shape (K from the centre fit, linear least squares):\n");
  PrintProfileFit(*first);
  StatusOr<JointProfileFit> joint =
      FitProfileJoint(run.result.model, data, index, split, *first);
  if (!joint.ok()) {
    std::fprintf(stderr, "rollwear calibrate: no joint profile fit: %s\n",
                 joint.status().message().c_str());
    nlohmann::json j = ProfileJson(*first);
    j["stage"] = "first";
    *model = run.result.model;
    *shape = first->shape;
    return j;
  }
  std::printf(
      "profile shape (K and shape jointly, Levenberg-Marquardt; roll-clustered "
      "s.e.; intra-roll correlation %.2f):\n",
      joint->intra_roll_correlation);
  PrintProfileFit(joint->profile);
  std::printf("centre gap under the joint K: training %.1f µm, validation %.1f µm\n",
              joint->centre_gap_train_um, joint->centre_gap_val_um);
  if (!joint->at_bound.empty()) {
    std::printf("at a bound (standard error not meaningful):");
    for (const std::string& name : joint->at_bound) std::printf(" %s", name.c_str());
    std::printf("\n");
  }
  nlohmann::json j = ProfileJson(joint->profile);
  j["stage"] = "joint";
  j["centre_gap_train_um"] = JsonNumber(joint->centre_gap_train_um);
  j["centre_gap_val_um"] = JsonNumber(joint->centre_gap_val_um);
  j["intra_roll_correlation"] = joint->intra_roll_correlation;
  j["converged"] = joint->converged;
  j["at_bound"] = joint->at_bound;
  j["first_stage"] = ProfileJson(*first);
  *model = joint->model;
  *shape = joint->profile.shape;
  return j;
}

// --json FILE: the same figures as one JSON object.
nlohmann::json CalibrationJson(const CalibrateArgs& args,
                               const CalibrationOptions& options,
                               const SplitCalibration& run,
                               const DataQuality& quality, bool usable) {
  const CalibrationResult& r = run.result;
  const WearModel& m = r.model;
  nlohmann::json j;
  j["model"] = WearLawName(options.law);
  j["option"] = options.option;
  j["start"] = InitialSetName(options.initial_set);
  j["protocol"] = args.protocol;
  j["split_seed"] = args.split_seed;
  nlohmann::json coef = nlohmann::json::object(), se = nlohmann::json::object();
  const auto named = m.NamedCoefficients();
  for (size_t i = 0; i < named.size(); ++i) {
    coef[named[i].first] = named[i].second;
    se[named[i].first] = JsonNumber(r.std_error[i]);
  }
  j["coefficients"] = coef;
  j["std_errors_log"] = se;
  j["cost"] = run.train.cost;
  j["cost_val"] = run.validation.cost;
  j["gap_train_um"] = run.train.gap_um;
  j["gap_val_um"] = run.validation.gap_um;
  j["n_train"] = run.train.n;
  j["n_val"] = run.validation.n;
  j["seconds"] = r.summary.seconds;
  j["iterations"] = r.summary.iterations;
  j["evaluations"] = r.summary.evaluations;
  j["termination"] = r.summary.termination;
  j["usable"] = usable;
  const GradeShrinkage& g = r.grade_shrinkage;
  j["grade_shrinkage"] = {{"applied", g.applied},
                          {"levels", g.levels},
                          {"tau_log", JsonNumber(g.tau)},
                          {"effective_parameters", g.effective_parameters},
                          {"converged", g.converged}};
  j["data_quality"] = DataQualityJson(quality, &run.suspected_outliers);
  j["noise"] = {{"sd_um", m.noise_sd_um}, {"rel", m.noise_rel}};
  j["bias_above_300_um"] = JsonNumber(run.bias_above_300_um);
  return j;
}

}  // namespace

int RunCalibrate(const CalibrateArgs& args) {
  CalibrationOptions options = args.options;
  if (!ParseWearLaw(args.model, &options.law)) {
    std::fprintf(stderr, "rollwear calibrate: --model must be wang, nikitenko or cao\n");
    return 2;
  }
  if (!args.terms.empty()) {
    if (options.law != WearLaw::kWang || options.option != 1) {
      std::fprintf(stderr, "rollwear calibrate: --terms refits Wang's law, option 1\n");
      return 2;
    }
    if (args.per_roll) {
      std::fprintf(stderr, "rollwear calibrate: --per-roll does not take --terms\n");
      return 2;
    }
    return RunCalibrateWithTerms(args);
  }
  if (int code = CheckCalibrationOptions(args, &options)) return code;

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
  StatusOr<WearStatistics> stats = Aggregate(*data, index, options.law);
  if (!stats.ok()) {
    std::fprintf(stderr, "rollwear calibrate: %s\n", stats.status().message().c_str());
    return 1;
  }
  const CampaignSplit split = SplitOrGiven(*stats, args.split_seed, given);
  if (args.per_roll) {
    return RunCalibratePerRoll(args, options, checked, *stats, split,
                               applied.original_id);
  }
  StatusOr<SplitCalibration> run = CalibrateOnSplit(*stats, split, options);
  if (!run.ok()) {
    std::fprintf(stderr, "rollwear calibrate: %s\n", run.status().message().c_str());
    return 1;
  }
  // Not "usable" on data a calibration cannot stand for (a roll position
  // without a pass: its measurements compare with a zero prediction), nor
  // when the data do not identify the fit (identification.h).
  const Identification id =
      JudgeIdentification(run->result, run->train, run->validation);
  const bool usable = run->result.summary.usable && id.identified &&
                      !SpoilsCalibration(checked.quality);
  NameOutliers(*data, &run->suspected_outliers);
  PrintCalibration(options, args.protocol, *run, usable);
  std::printf("identification: %s\n", id.Sentence().c_str());
  if (!args.predictions.empty()) {
    const Status written = WritePredictionsCsv(
        args.predictions,
        PredictionRows(*data, *stats, split, applied.original_id,
                       LawPredictor(run->result.model, *stats)));
    if (!written.ok()) {
      std::fprintf(stderr, "rollwear calibrate: %s\n", written.message().c_str());
      return 1;
    }
  }
  if (options.robust && options.derivatives == DerivativeMode::kExact) {
    PrintSuspectedOutliers(run->suspected_outliers);
  }
  // With profiles.csv: the profile's shape and gap (nothing otherwise).
  std::optional<nlohmann::json> profile;
  WearModel profile_model;
  ProfileShape profile_shape;
  if (!data->profile_points.empty()) {
    profile = FitProfile(*run, *data, index, split, &profile_model, &profile_shape);
  }
  if (!args.json.empty()) {
    nlohmann::json j =
        CalibrationJson(args, options, *run, checked.quality, usable);
    j["identification"] = IdentificationJson(id);
    if (profile) j["profile"] = *profile;
    std::ofstream out(args.json);
    out << j.dump(2) << "\n";
    if (!out) {
      std::fprintf(stderr, "rollwear calibrate: cannot write %s\n", args.json.c_str());
      return 1;
    }
  }
  if (!args.figures.empty()) {
    Status written =
        WriteCalibrationFigure(args.figures, options, *stats, split, *run);
    if (written.ok() && profile) {
      StatusOr<SvgFigure> figure = ProfileFigure(
          "Measured vs predicted profiles of validation rolls (" +
              std::string(WearLawName(options.law)) + ", option " +
              std::to_string(options.option) + ")",
          profile_model, profile_shape, *data, split);
      written = figure.ok() ? WriteFigures(args.figures, {*figure})
                            : figure.status();
      if (written.ok()) {
        std::printf("wrote %s/%s\n", args.figures.c_str(), kProfileFigureName);
      }
    }
    if (!written.ok()) {
      std::fprintf(stderr, "rollwear calibrate: %s\n", written.message().c_str());
      return 1;
    }
  }
  return usable ? 0 : 1;
}

}  // namespace rollwear::cli
