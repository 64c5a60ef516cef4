#include "service/calibrate_per_roll.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "api/json_number.h"
#include "service/predictions_csv.h"

namespace rollwear::cli {
namespace {

constexpr double kZ95 = 1.959964;

void PrintPerRoll(const CalibrationOptions& options, const RollEffectsFit& fit,
                  const Identification& id) {
  const CalibrationResult& r = fit.result;
  std::printf(
      "%s law, option %d, per-roll wear multipliers (empirical Bayes)\n",
      WearLawName(options.law), options.option);
  std::printf("%s\n", r.summary.BriefReport().c_str());
  if (r.grade_shrinkage.applied) {
    std::printf("grades: %s\n", r.grade_shrinkage.Sentence().c_str());
  }
  std::printf("%-28s %12s %10s\n", "coefficient", "value", "s.e. log");
  const auto named = r.model.NamedCoefficients();
  for (size_t i = 0; i < named.size(); ++i) {
    std::printf("%-28s %12.6g %10.3g\n", named[i].first.c_str(),
                named[i].second, r.std_error[i]);
  }
  const RollEffects& e = fit.effects;
  std::printf(
      "rolls: %zu with training readings; between-roll sd of the multiplier "
      "tau = %.3f, within-roll noise sd %.1f µm + %.1f %% of wear; %d "
      "rounds%s; %.1f effective parameters\n",
      e.rolls.size(), e.tau, e.sigma_um, 100 * e.noise_rel, e.iterations,
      e.converged ? "" : " (not converged)", e.effective_parameters);
  std::vector<RollEffect> sorted = e.rolls;
  std::sort(sorted.begin(), sorted.end(),
            [](const RollEffect& a, const RollEffect& b) {
              return a.value > b.value;
            });
  const size_t shown = std::min<size_t>(5, sorted.size());
  for (size_t k = 0; k < sorted.size(); ++k) {
    if (k >= shown && k + shown < sorted.size()) continue;
    const RollEffect& x = sorted[k];
    std::printf("  roll %-12s x%.3f [%.3f, %.3f] (own %.3f over %d readings)\n",
                x.roll_id.c_str(), x.value, x.value - kZ95 * x.sd,
                x.value + kZ95 * x.sd, x.raw, x.readings);
  }
  std::printf("training:   %d measurements, gap %.1f µm, cost %.1f µm²\n",
              fit.train.n, fit.train.gap_um, fit.train.cost);
  std::printf("validation: %d measurements, gap %.1f µm, cost %.1f µm²\n",
              fit.validation.n, fit.validation.gap_um, fit.validation.cost);
  std::printf("identification: %s\n", id.Sentence().c_str());
}

}  // namespace

nlohmann::json IdentificationJson(const Identification& id) {
  return {{"identified", id.identified},
          {"sentence", id.Sentence()},
          {"at_bound", id.at_bound},
          {"large_error", id.large_error},
          {"gap_ratio", JsonNumber(id.gap_ratio)},
          {"expected_ratio", JsonNumber(id.expected_ratio)},
          {"z", JsonNumber(id.z)}};
}

nlohmann::json RollEffectsJson(const RollEffects& e) {
  nlohmann::json rolls = nlohmann::json::array();
  for (const RollEffect& r : e.rolls) {
    rolls.push_back(
        {{"roll_id", r.roll_id},
         {"value", r.value},
         {"interval", {r.value - kZ95 * r.sd, r.value + kZ95 * r.sd}},
         {"raw", JsonNumber(r.raw)},
         {"readings", r.readings}});
  }
  return {{"tau", e.tau},
          {"sigma_um", e.sigma_um},
          {"noise_rel", e.noise_rel},
          {"iterations", e.iterations},
          {"converged", e.converged},
          {"rolls", rolls}};
}

int RunCalibratePerRoll(const CalibrateArgs& args,
                        const CalibrationOptions& options,
                        const CheckedDataset& checked,
                        const WearStatistics& stats, const CampaignSplit& split,
                        const std::vector<std::string>& original_id) {
  const Dataset& data = checked.fit;
  StatusOr<RollEffectsFit> fit =
      CalibrateWithRollEffects(data, stats, split, options);
  if (!fit.ok()) {
    std::fprintf(stderr, "rollwear calibrate: %s\n",
                 fit.status().message().c_str());
    return 1;
  }
  const Identification id =
      JudgeIdentification(fit->result, fit->train, fit->validation,
                          fit->effects.effective_parameters);
  const bool usable = fit->result.summary.usable && id.identified &&
                      !SpoilsCalibration(checked.quality);
  PrintPerRoll(options, *fit, id);
  const RollEffects& e = fit->effects;
  const WearModel& model = fit->result.model;
  if (!args.predictions.empty()) {
    ObservationPredictor predict = [&](int o, double* pred, double* sd) {
      const Observation& ob = stats.observations[o];
      const std::string& roll = data.mounts[ob.mount].roll_id;
      const double x = PredictObservation(model, stats, ob);
      const double s = e.SdOf(roll);
      *pred = e.ValueOf(roll) * x;
      *sd = std::sqrt(e.sigma_um * e.sigma_um + std::pow(e.noise_rel * x, 2) +
                      x * x * s * s);
    };
    const Status written = WritePredictionsCsv(
        args.predictions,
        PredictionRows(data, stats, split, original_id, predict));
    if (!written.ok()) {
      std::fprintf(stderr, "rollwear calibrate: %s\n",
                   written.message().c_str());
      return 1;
    }
  }
  if (!args.json.empty()) {
    nlohmann::json j;
    j["model"] = WearLawName(options.law);
    j["option"] = options.option;
    j["k_structure"] = "per_roll";
    nlohmann::json coef = nlohmann::json::object();
    for (const auto& [name, value] : model.NamedCoefficients())
      coef[name] = value;
    j["coefficients"] = coef;
    j["cost"] = fit->train.cost;
    j["gap_train_um"] = fit->train.gap_um;
    j["gap_val_um"] = fit->validation.gap_um;
    j["n_train"] = fit->train.n;
    j["n_val"] = fit->validation.n;
    j["seconds"] = fit->result.summary.seconds;
    j["usable"] = usable;
    j["identification"] = IdentificationJson(id);
    j["roll_effects"] = RollEffectsJson(e);
    j["data_quality"] = DataQualityJson(checked.quality);
    std::ofstream out(args.json);
    out << j.dump(2) << "\n";
    if (!out) {
      std::fprintf(stderr, "rollwear calibrate: cannot write %s\n",
                   args.json.c_str());
      return 1;
    }
  }
  return usable ? 0 : 1;
}

}  // namespace rollwear::cli
