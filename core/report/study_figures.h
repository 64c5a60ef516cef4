// The study's figures as SVG (core/report/svg_plot.h): measured against calculated
// centre wear of the validation campaigns, one panel per stand, each with
// the 1:1 line, axes in µm and a legend of the compared models.
//   measured_vs_calculated_initial_vs_optimised.svg  Wang, option 1: the
//       empirical initial coefficients (kF = sum measured / sum load per
//       position, other factors 1) and the calibrated ones;
//   measured_vs_calculated_laws.svg     Wang, Nikitenko, Cao (option 1);
//   measured_vs_calculated_options.svg  Wang, options 1, 2, 3;
// all calibrated on the training campaigns of the seeded 2/3-1/3 split that
// RunStudy (study.h) uses, with the empirical start and exact derivatives
// (the rows of Tables 1 and 2). `rollwear calibrate` and `rollwear ann`
// draw their single comparisons with ParityFigureSvg.
//
// Thread-safety: pure functions, except WriteFigures, which writes files
// into the folder the caller names.
#ifndef ROLLWEAR_CORE_REPORT_STUDY_FIGURES_H_
#define ROLLWEAR_CORE_REPORT_STUDY_FIGURES_H_

#include <string>
#include <vector>

#include "core/model/aggregation.h"
#include "core/ann/ann_study.h"
#include "core/dataset/dataset.h"
#include "core/base/status.h"
#include "core/fit/study.h"
#include "core/report/svg_plot.h"  // SvgFigure

namespace rollwear {

// Predictions of one model, aligned with the observations of a figure.
struct ParitySeries {
  std::string name;   // legend entry, e.g. "Wang (gap 23.1 µm)"
  std::string color;  // "" = the palette's next colour
  std::vector<double> calculated_um;
};

// One panel per stand of `measured_um` (x) against each series (y); the
// stand of observation i is stands[i]. Panels share the figure's title.
std::string ParityFigureSvg(const std::string& title,
                            const std::vector<int>& stands,
                            const std::vector<double>& measured_um,
                            const std::vector<ParitySeries>& series);

// Convenience over WearStatistics: observations `obs` (measured) of `stats`.
std::string ParityFigureSvg(const std::string& title,
                            const WearStatistics& stats,
                            const std::vector<int>& obs,
                            const std::vector<ParitySeries>& series);

StatusOr<std::vector<SvgFigure>> StudyFigures(const Dataset& data,
                                              const StudyOptions& options);

// `rollwear ann --figures`: measured_vs_calculated_classical_vs_ann.svg,
// the classical model and the network of `comparison` (the result of
// CompareAnnWithClassical(data, options)) on its validation campaigns.
StatusOr<SvgFigure> AnnFigure(const Dataset& data,
                              const AnnComparisonOptions& options,
                              const AnnComparison& comparison);

// Writes each figure to dir/file_name (creating dir); the first failure.
Status WriteFigures(const std::string& dir,
                    const std::vector<SvgFigure>& figures);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_REPORT_STUDY_FIGURES_H_
