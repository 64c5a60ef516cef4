#include "engine/wear_prediction.h"

#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "core/model/model_eval.h"
#include "core/model/predictor.h"
#include "core/model/roll_factor_update.h"

namespace rollwear::engine {
namespace {

using storage::RollFactorReading;

class CorePredictor final : public storage::WearPredictor {
 public:
  RollWearState Mount(const WearModel& model,
                      const storage::MountedRollIn& roll,
                      UnixSeconds started_at, const ExtraFields& campaign_extra,
                      bool track_profile) const override {
    RollWearState s =
        MountRoll(model, RollPositionName(roll.stand, roll.position),
                  roll.roll_type, roll.diameter_mm, roll.hardness_hb,
                  started_at, roll.extra, campaign_extra, roll.roll_id);
    if (track_profile) TrackProfile(&s);
    return s;
  }

  double AddPass(const WearModel& model, const PassInput& pass,
                 RollWearState* state) const override {
    return rollwear::AddPass(model, pass, state);
  }

  double ReadingOffset(const WearModel& model,
                       const ReadingContext& reading) const override {
    return MeasurementTermsOffset(model, reading);
  }

  const ModelTerm* UpdatableRollTerm(const WearModel& model) const override {
    const ModelTerm* term = RollEffectTermOf(model.terms);
    if (term == nullptr || model.is_ann() || !term->scope.grade.empty() ||
        !term->scope.gate.empty()) {
      return nullptr;
    }
    return term;
  }

  double RollLogFactor(const ModelTerm& term,
                       const std::string& roll_id) const override {
    return rollwear::RollLogFactor(term, roll_id);
  }

  // The profile sums read with `shape` (core/model/barrel_profile.h:
  // ProfileStats::Evaluate per slice, ProfileGrid::Interpolate at a point).
  std::vector<double> ProfileAt(
      const RollWearState& state, const ProfileShape& shape,
      const std::vector<double>& x_mm) const override {
    std::vector<double> out;
    if (!state.profile.has_value()) return out;
    const std::vector<double> slices = state.profile->Evaluate(shape);
    out.reserve(x_mm.size());
    for (double x : x_mm) {
      out.push_back(state.profile->grid().Interpolate(slices, x));
    }
    return out;
  }

  // Each roll's posterior (core/model/roll_factor_update.h: its readings'
  // penalised least squares under the term's prior sd and the model's
  // noise), set as its level when it converged.
  WearModel WithRollFactors(
      const WearModel& model,
      const std::map<std::string, std::vector<RollFactorReading>>& readings)
      const override {
    WearModel out = model;
    ModelTerm* own = RollEffectTermOf(&out.terms);
    if (own == nullptr) return out;
    for (const auto& [roll, list] : readings) {
      std::vector<RollReading> core_list;
      core_list.reserve(list.size());
      for (const RollFactorReading& r : list) {
        core_list.push_back({r.base_um, r.offset_um, r.measured_um});
      }
      const RollFactorPosterior p = RollFactorPosteriorOf(
          own->scale, {model.noise_sd_um, model.noise_rel}, core_list);
      // Readings no roll of this type could give: the level stays.
      if (p.converged) SetRollLevel(roll, p, own);
    }
    return out;
  }
};

}  // namespace

std::shared_ptr<const storage::WearPredictor> CoreWearPredictor() {
  static const std::shared_ptr<const storage::WearPredictor> kPredictor =
      std::make_shared<CorePredictor>();
  return kPredictor;
}

storage::StoreOptions WithPredictor(storage::StoreOptions options) {
  options.predictor = CoreWearPredictor();
  return options;
}

StatusOr<std::unique_ptr<storage::MillStore>> OpenStore(
    const std::string& path, const storage::StoreOptions& options) {
  return storage::MillStore::Open(path, WithPredictor(options));
}

}  // namespace rollwear::engine
