#include "core/predictor.h"

namespace rollwear {

RollWearState MountRoll(const WearModel& model, const std::string& position_label,
                        const std::string& roll_type, double diameter_mm,
                        double hardness_hb) {
  RollWearState s;
  s.position = model.structure.PositionLevel(position_label);
  s.roll_type = model.structure.RollTypeLevel(roll_type);
  s.diameter_mm = diameter_mm;
  s.hardness_hb = hardness_hb;
  s.gradient.assign(model.num_parameters(), 0.0);
  return s;
}

double AddPass(const WearModel& model, const PassInput& pass, RollWearState* state) {
  const PassLoadInput in{pass.force_kn,           pass.width_mm,
                         pass.length_m,           pass.entry_thickness_mm,
                         pass.exit_thickness_mm,  state->diameter_mm,
                         state->hardness_hb};
  const int grade = model.structure.GradeLevel(pass.grade);
  const double wear = model.PassWear(in, state->position, state->roll_type, grade);
  if (static_cast<int>(state->gradient.size()) != model.num_parameters()) {
    state->gradient.assign(model.num_parameters(), 0.0);
  }
  model.AddPassGradient(in, state->position, state->roll_type, grade,
                        state->gradient.data());
  state->wear_um += wear;
  state->coils += 1;
  state->rolled_length_m += pass.length_m;
  return wear;
}

std::pair<double, double> WearInterval(const WearModel& model,
                                       const RollWearState& state) {
  return model.Interval(state.wear_um, state.gradient.data());
}

}  // namespace rollwear
