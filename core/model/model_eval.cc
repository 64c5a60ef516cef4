#include "core/model/model_eval.h"

#include <cmath>
#include <limits>

#include "core/model/covariates.h"
#include "core/model/predictor.h"

namespace rollwear {
namespace {

// Sum of the measurement terms' offsets for measurement `measurement` of
// mount `mount`.
double MeasurementOffset(const WearModel& model, const Dataset& data,
                         const std::vector<CovariateSpec>& catalog,
                         int campaign, int mount, int measurement) {
  PassContext ctx;
  ctx.mount = &data.mounts[mount];
  ctx.mount_row = mount;
  ctx.campaign = &data.campaigns[campaign];
  ctx.campaign_row = campaign;
  ctx.measurement_row = measurement;
  return MeasurementTermsOffset(model, [&](const std::string& name) {
    for (const CovariateSpec& spec : catalog) {
      // Measurement terms act on measurement-level covariates only (a
      // pass-level one has no pass here; RefitWithTerms refuses them).
      if (spec.name == name && spec.level == CovariateLevel::kMeasurement) {
        return CovariateValue(spec, data, ctx, 0);
      }
    }
    return std::numeric_limits<double>::quiet_NaN();
  });
}

}  // namespace

RollWearState MountedRollState(const WearModel& model, const Dataset& data,
                               int campaign, int mount) {
  const Mount& m = data.mounts[mount];
  return MountRoll(model, RollPositionName(m.stand, m.position),
                   data.roll_types[m.roll_type], m.diameter_mm, m.hardness_hb,
                   data.campaigns[campaign].started_at,
                   ExtraFieldsOfRow(data.mount_extra, mount),
                   ExtraFieldsOfRow(data.campaign_extra, campaign));
}

std::vector<MeasuredPrediction> PredictMeasured(
    const WearModel& model, const Dataset& data, const DatasetIndex& index,
    const std::vector<int>& campaigns) {
  const bool has_measurement_terms = HasMeasurementTerms(model);
  const std::vector<CovariateSpec> catalog = has_measurement_terms
                                                 ? CovariateCatalog(data)
                                                 : std::vector<CovariateSpec>{};
  std::vector<MeasuredPrediction> out;
  for (int c : campaigns) {
    for (int slot : index.slots()) {
      const int mi = index.MountOf(c, slot);
      const int me = index.MeasurementOf(c, slot);
      if (mi < 0 || me < 0) continue;
      const Mount& mount = data.mounts[mi];
      RollWearState state = MountedRollState(model, data, c, mi);
      for (int pi : index.PassesOf(c, mount.stand)) {
        AddPass(model, PassInputOf(data, data.passes[pi]), &state);
      }
      MeasuredPrediction p;
      p.campaign = c;
      p.slot = slot;
      p.measurement = me;
      p.measured_um = data.measurements[me].wear_center_um;
      p.wear_um = state.wear_um;
      p.expected_um = state.wear_um;
      if (has_measurement_terms) {
        p.expected_um += MeasurementOffset(model, data, catalog, c, mi, me);
      }
      out.push_back(p);
    }
  }
  return out;
}

bool HasMeasurementTerms(const WearModel& model) {
  for (const ModelTerm& t : model.terms) {
    if (t.IsMeasurementTerm()) return true;
  }
  return false;
}

double MeasurementTermsOffset(
    const WearModel& model,
    const std::function<double(const std::string& covariate)>& value) {
  double offset = 0;
  for (const ModelTerm& t : model.terms) {
    if (!t.IsMeasurementTerm()) continue;
    const double z = value(t.covariate);
    if (!std::isnan(z)) offset += TermOffset(t, z, nullptr);
  }
  return offset;
}

FitMetrics MetricsOfPredictions(const std::vector<MeasuredPrediction>& p) {
  std::vector<int> group;
  std::vector<double> measured, predicted;
  for (const MeasuredPrediction& x : p) {
    group.push_back(x.slot);
    measured.push_back(x.measured_um);
    predicted.push_back(x.expected_um);
  }
  return MetricsOf(group, measured, predicted);
}

}  // namespace rollwear
