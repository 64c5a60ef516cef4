#include "core/report/study_figures.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <utility>

#include "core/fit/calibration.h"
#include "core/fit/profile_fit.h"
#include "core/model/metrics.h"
#include "core/report/profile_figures.h"
#include "core/report/svg_plot.h"

namespace rollwear {
namespace {

std::string GapLabel(const std::string& name,
                     const std::vector<double>& measured,
                     const std::vector<double>& calculated) {
  double sum = 0;
  int n = 0;
  for (size_t i = 0; i < measured.size() && i < calculated.size(); ++i) {
    if (!std::isfinite(calculated[i])) continue;
    sum += std::abs(measured[i] - calculated[i]);
    ++n;
  }
  char buf[160];
  std::snprintf(buf, sizeof(buf), "%s (gap %.1f µm)", name.c_str(),
                n > 0 ? sum / n : NAN);
  return buf;
}

// The validation observations of one law's statistics, keyed by
// (campaign, slot) so that the laws' figures line up.
struct LawRun {
  WearStatistics stats;
  CampaignSplit split;
  std::vector<int> train, val;
};

StatusOr<LawRun> Prepare(const Dataset& data, const DatasetIndex& index,
                         WearLaw law, const StudyOptions& options) {
  LawRun run;
  ROLLWEAR_ASSIGN_OR_RETURN(run.stats, Aggregate(data, index, law));
  run.split = SplitOrGiven(run.stats, options.split_seed, options.given_split);
  run.train = run.stats.MeasuredObservations(run.split.train);
  run.val = run.stats.MeasuredObservations(run.split.validation);
  return run;
}

StatusOr<WearModel> Fit(const LawRun& run, WearLaw law, int option,
                        uint64_t seed) {
  CalibrationOptions o;
  o.law = law;
  o.option = option;
  o.initial_set = InitialSet::kEmpirical;
  o.derivatives = DerivativeMode::kExact;
  o.compute_covariance = false;
  o.shrink_grades = false;  // the study's fits (study.h)
  o.seed = seed;
  ROLLWEAR_ASSIGN_OR_RETURN(CalibrationResult r,
                            Calibrate(run.stats, run.train, o));
  return std::move(r.model);
}

// Predictions of `model` (over `run`'s levels) at the observations `keys`.
std::vector<double> PredictAt(const WearModel& model, const LawRun& run,
                              const std::vector<int>& keys) {
  std::map<int, double> by_key;
  for (int o : run.val) {
    const Observation& obs = run.stats.observations[o];
    by_key[obs.campaign * kNumRollPositionSlots + obs.slot] =
        PredictObservation(model, run.stats, obs);
  }
  std::vector<double> out;
  out.reserve(keys.size());
  for (int k : keys) {
    auto it = by_key.find(k);
    out.push_back(it == by_key.end() ? NAN : it->second);
  }
  return out;
}

}  // namespace

std::string ParityFigureSvg(const std::string& title,
                            const std::vector<int>& stands,
                            const std::vector<double>& measured_um,
                            const std::vector<ParitySeries>& series) {
  std::vector<int> stand_list = stands;
  std::sort(stand_list.begin(), stand_list.end());
  stand_list.erase(std::unique(stand_list.begin(), stand_list.end()),
                   stand_list.end());
  const int columns = std::min<int>(3, std::max<size_t>(1, stand_list.size()));
  std::vector<PlotSpec> panels;
  for (int stand : stand_list) {
    PlotSpec spec;
    spec.title = "stand F" + std::to_string(stand);
    spec.x_label = "measured centre wear (µm)";
    spec.y_label = "calculated centre wear (µm)";
    spec.identity_line = true;
    spec.width = 480;
    spec.height = 460;
    spec.font_size = 13;
    for (size_t si = 0; si < series.size(); ++si) {
      const ParitySeries& s = series[si];
      PlotSeries pts = PlotSeries::Make(
          s.name,
          s.color.empty() ? PaletteColor(static_cast<int>(si)) : s.color,
          PlotSeries::Style::kPoints);
      pts.radius = 3.2;
      pts.opacity = 0.65;
      for (size_t i = 0; i < stands.size() && i < measured_um.size() &&
                         i < s.calculated_um.size();
           ++i) {
        if (stands[i] != stand) continue;
        pts.x.push_back(measured_um[i]);
        pts.y.push_back(s.calculated_um[i]);
      }
      spec.series.push_back(std::move(pts));
    }
    panels.push_back(std::move(spec));
  }
  return RenderSvgGrid(title, panels, columns);
}

std::string ParityFigureSvg(const std::string& title,
                            const WearStatistics& stats,
                            const std::vector<int>& obs,
                            const std::vector<ParitySeries>& series) {
  std::vector<int> stands;
  std::vector<double> measured;
  for (int o : obs) {
    stands.push_back(SlotStand(stats.observations[o].slot));
    measured.push_back(stats.observations[o].measured_um);
  }
  return ParityFigureSvg(title, stands, measured, series);
}

StatusOr<std::vector<SvgFigure>> StudyFigures(const Dataset& data,
                                              const StudyOptions& options) {
  const DatasetIndex index(data);
  const uint64_t seed = options.random_start_seed;
  ROLLWEAR_ASSIGN_OR_RETURN(
      LawRun wang, Prepare(data, index, WearLaw::kWang, options));
  std::vector<int> keys, stands;
  std::vector<double> measured;
  for (int o : wang.val) {
    const Observation& obs = wang.stats.observations[o];
    keys.push_back(obs.campaign * kNumRollPositionSlots + obs.slot);
    stands.push_back(SlotStand(obs.slot));
    measured.push_back(obs.measured_um);
  }
  char caption[200];
  std::snprintf(caption, sizeof(caption),
                "%zu validation rolls, split seed %llu", keys.size(),
                static_cast<unsigned long long>(options.split_seed));
  std::vector<SvgFigure> figures;

  // Wang option 1: the empirical start, then calibrated.
  ROLLWEAR_ASSIGN_OR_RETURN(WearModel wang1,
                            Fit(wang, WearLaw::kWang, 1, seed));
  WearModel initial = wang1;
  std::fill(initial.k.begin(), initial.k.end(), 1.0);
  {
    std::map<int, std::pair<double, double>> sums;  // position level
    for (int o : wang.train) {
      const Observation& obs = wang.stats.observations[o];
      sums[obs.position].first += obs.measured_um;
      sums[obs.position].second += PredictObservation(initial, wang.stats, obs);
    }
    for (const auto& [p, s] : sums) {
      if (s.second > 0) initial.k[p] = s.first / s.second;
    }
  }
  {
    std::vector<ParitySeries> series(2);
    series[0].calculated_um = PredictAt(initial, wang, keys);
    series[0].name =
        GapLabel("initial (empirical kF)", measured, series[0].calculated_um);
    series[1].calculated_um = PredictAt(wang1, wang, keys);
    series[1].name = GapLabel("optimised", measured, series[1].calculated_um);
    figures.push_back(
        {"measured_vs_calculated_initial_vs_optimised.svg",
         ParityFigureSvg(
             std::string("Wang option 1, initial vs optimised — ") + caption,
             stands, measured, series)});
  }
  // With profiles: Wang option 1's measured vs predicted profiles (the
  // shape fitted with its K, profile_fit.h).
  if (!data.profile_points.empty()) {
    StatusOr<ProfileFit> fit = FitProfileShape(wang1, data, index, wang.split);
    if (fit.ok()) {
      ROLLWEAR_ASSIGN_OR_RETURN(
          SvgFigure figure,
          ProfileFigure("Wang option 1, measured vs predicted profiles of "
                        "validation rolls",
                        wang1, fit->shape, data, wang.split));
      figures.push_back(std::move(figure));
    }
  }
  // The three laws, option 1.
  {
    std::vector<ParitySeries> series;
    for (WearLaw law : {WearLaw::kWang, WearLaw::kNikitenko, WearLaw::kCao}) {
      ParitySeries s;
      if (law == WearLaw::kWang) {
        s.calculated_um = PredictAt(wang1, wang, keys);
      } else {
        ROLLWEAR_ASSIGN_OR_RETURN(
            LawRun run, Prepare(data, index, law, options));
        ROLLWEAR_ASSIGN_OR_RETURN(WearModel m, Fit(run, law, 1, seed));
        s.calculated_um = PredictAt(m, run, keys);
      }
      s.name = GapLabel(WearLawName(law), measured, s.calculated_um);
      series.push_back(std::move(s));
    }
    figures.push_back(
        {"measured_vs_calculated_laws.svg",
         ParityFigureSvg(std::string("Wear laws, option 1 — ") + caption,
                         stands, measured, series)});
  }
  // Wang's law, the three K structures.
  {
    std::vector<ParitySeries> series;
    for (int option : {1, 2, 3}) {
      ParitySeries s;
      if (option == 1) {
        s.calculated_um = PredictAt(wang1, wang, keys);
      } else {
        ROLLWEAR_ASSIGN_OR_RETURN(WearModel m,
                                  Fit(wang, WearLaw::kWang, option, seed));
        s.calculated_um = PredictAt(m, wang, keys);
      }
      s.name = GapLabel("option " + std::to_string(option), measured,
                        s.calculated_um);
      series.push_back(std::move(s));
    }
    figures.push_back(
        {"measured_vs_calculated_options.svg",
         ParityFigureSvg(std::string("Wang's law, K options 1-3 — ") + caption,
                         stands, measured, series)});
  }
  return figures;
}

StatusOr<SvgFigure> AnnFigure(const Dataset& data,
                              const AnnComparisonOptions& options,
                              const AnnComparison& comparison) {
  // The comparison's split and models again: the classical fit is
  // deterministic and the network is evaluated as trained.
  ROLLWEAR_ASSIGN_OR_RETURN(AnnSplitPredictions p,
                            PredictAnnOnSplit(data, options, comparison));
  const WearStatistics& stats = p.stats;
  const std::vector<int> val(p.observations.begin() + p.num_train,
                             p.observations.end());
  ROLLWEAR_ASSIGN_OR_RETURN(SplitCalibration classical,
                            CalibrateOnSplit(stats, p.split, options.classical));
  std::vector<double> measured;
  for (int o : val) measured.push_back(stats.observations[o].measured_um);
  ParitySeries cl, ann;
  cl.calculated_um = PredictAll(classical.result.model, stats, val);
  cl.name = GapLabel("classical (Wang, option " +
                         std::to_string(options.classical.option) + ")",
                     measured, cl.calculated_um);
  ann.calculated_um.assign(p.predicted_um.begin() + p.num_train,
                           p.predicted_um.end());
  ann.name = GapLabel("ANN", measured, ann.calculated_um);
  char title[160];
  std::snprintf(title, sizeof(title),
                "Classical vs ANN — %zu validation rolls, split seed %llu",
                val.size(),
                static_cast<unsigned long long>(options.split_seed));
  return SvgFigure{"measured_vs_calculated_classical_vs_ann.svg",
                   ParityFigureSvg(title, stats, val, {cl, ann})};
}

Status WriteFigures(const std::string& dir,
                    const std::vector<SvgFigure>& figures) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec)
    return Status::IoError(dir + ": cannot create folder: " + ec.message());
  for (const SvgFigure& f : figures) {
    const std::string path =
        (std::filesystem::path(dir) / f.file_name).string();
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << f.svg;
    out.close();
    if (!out) return Status::IoError(path + ": cannot write");
  }
  return Status::Ok();
}

}  // namespace rollwear
