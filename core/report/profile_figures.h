// Measured against predicted wear profiles across the barrel as SVG
// (core/report/svg_plot.h): one panel per roll for a few validation rolls,
// the grinder's points and the model's predicted profile (its K and the
// fitted shape, profile_fit.h), x in mm from the barrel centre, wear in
// µm. `rollwear calibrate --figures` and `rollwear study --figures` write
// it as profiles_measured_vs_predicted.svg when the dataset has profiles.
//
// Thread-safety: pure function.
#ifndef ROLLWEAR_CORE_REPORT_PROFILE_FIGURES_H_
#define ROLLWEAR_CORE_REPORT_PROFILE_FIGURES_H_

#include <string>

#include "core/base/status.h"
#include "core/dataset/dataset.h"
#include "core/model/barrel_profile.h"
#include "core/model/metrics.h"
#include "core/model/wear_model.h"
#include "core/report/svg_plot.h"

namespace rollwear {

inline constexpr const char* kProfileFigureName =
    "profiles_measured_vs_predicted.svg";

// Up to `max_panels` validation rolls with profiles, evenly spread over the
// validation campaigns in campaign order (deterministic), each panel
// titled "<campaign> <stand/position>: gap G µm". Error: no validation
// roll has a profile.
StatusOr<SvgFigure> ProfileFigure(const std::string& title,
                                  const WearModel& model,
                                  const ProfileShape& shape,
                                  const Dataset& data,
                                  const CampaignSplit& split,
                                  int max_panels = 6);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_REPORT_PROFILE_FIGURES_H_
