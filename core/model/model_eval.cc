#include "core/model/model_eval.h"

#include <cmath>
#include <limits>
#include <string_view>

#include "core/model/covariates.h"
#include "core/model/predictor.h"

namespace rollwear {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The value of measurement term `t`'s covariate for `r` (ReadingContext in
// model_eval.h): an offset_per_level term's level index by label.
double ReadingValue(const ModelTerm& t, const ReadingContext& r) {
  if (t.covariate == kCoolingHoursName) {
    return r.ended_at.has_value() ? CoolingHours(r.measured_at, *r.ended_at) : kNaN;
  }
  if (t.covariate == "measured_at") {  // days since 1970 (covariates.h, origin 0)
    return static_cast<double>(r.measured_at) / 86400.0;
  }
  if (t.form != TermForm::kOffsetPerLevel) {
    const double* v = r.extra != nullptr ? r.extra->Numeric(t.covariate) : nullptr;
    return v != nullptr ? *v : kNaN;
  }
  const std::string* field = r.extra != nullptr ? r.extra->Factor(t.covariate) : nullptr;
  const std::string_view label = field != nullptr ? std::string_view(*field) : "";
  for (size_t l = 0; l < t.levels.size(); ++l) {
    if (t.levels[l] == label) return static_cast<double>(l);
  }
  return kNaN;
}

}  // namespace

RollWearState MountedRollState(const WearModel& model, const Dataset& data,
                               int campaign, int mount) {
  const Mount& m = data.mounts[mount];
  return MountRoll(model, RollPositionName(m.stand, m.position),
                   data.roll_types[m.roll_type], m.diameter_mm, m.hardness_hb,
                   data.campaigns[campaign].started_at,
                   ExtraFieldsOfRow(data.mount_extra, mount),
                   ExtraFieldsOfRow(data.campaign_extra, campaign), m.roll_id);
}

std::vector<MeasuredPrediction> PredictMeasured(
    const WearModel& model, const Dataset& data, const DatasetIndex& index,
    const std::vector<int>& campaigns) {
  const bool has_measurement_terms = HasMeasurementTerms(model);
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
        const ExtraFields fields = ExtraFieldsOfRow(data.measurement_extra, me);
        ReadingContext reading;
        reading.stand = mount.stand;
        reading.position = static_cast<int>(mount.position);
        reading.roll_type = data.roll_types[mount.roll_type];
        reading.measured_at = data.measurements[me].measured_at;
        reading.ended_at = data.campaigns[c].ended_at;
        reading.extra = &fields;
        p.expected_um += MeasurementTermsOffset(model, reading);
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

double MeasurementTermsOffset(const WearModel& model, const ReadingContext& reading) {
  double offset = 0;
  for (const ModelTerm& t : model.terms) {
    if (!t.IsMeasurementTerm() ||
        !t.scope.CoversRoll(reading.stand, reading.position, reading.roll_type)) {
      continue;
    }
    const double z = ReadingValue(t, reading);
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
