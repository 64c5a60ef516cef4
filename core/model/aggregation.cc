#include "core/model/aggregation.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace rollwear {

PassLoadInput MakeLoadInput(const Pass& pass, const Mount& mount) {
  return PassLoadInput{pass.force_kn,           pass.width_mm,
                       pass.length_m,           pass.entry_thickness_mm,
                       pass.exit_thickness_mm,  mount.diameter_mm,
                       mount.hardness_hb};
}

std::vector<int> WearStatistics::MeasuredObservations(
    const std::vector<int>& campaigns) const {
  std::unordered_set<int> keep(campaigns.begin(), campaigns.end());
  std::vector<int> out;
  for (size_t i = 0; i < observations.size(); ++i) {
    const Observation& o = observations[i];
    if (o.measurement >= 0 && keep.count(o.campaign) > 0) {
      out.push_back(static_cast<int>(i));
    }
  }
  return out;
}

std::vector<int> WearStatistics::MeasuredObservations() const {
  std::vector<int> out;
  for (size_t i = 0; i < observations.size(); ++i) {
    if (observations[i].measurement >= 0) out.push_back(static_cast<int>(i));
  }
  return out;
}

StatusOr<WearStatistics> Aggregate(const Dataset& data,
                                   const DatasetIndex& index, WearLaw law) {
  WearStatistics st;
  st.law = law;
  st.roll_types = data.roll_types;
  st.grades = data.grades;
  std::vector<int> slot_level(kNumRollPositionSlots, -1);
  for (int slot : index.slots()) {
    slot_level[slot] = static_cast<int>(st.positions.size());
    st.positions.push_back(RollPositionName(SlotStand(slot), SlotPosition(slot)));
    st.position_slots.push_back(slot);
  }
  const int num_grades = static_cast<int>(data.grades.size());
  std::vector<double> grade_load(num_grades);
  std::vector<std::vector<std::pair<double, double>>> grade_passes(
      law == WearLaw::kCao ? num_grades : 0);
  for (int c = 0; c < static_cast<int>(data.campaigns.size()); ++c) {
    for (int slot : index.slots()) {
      const int m = index.MountOf(c, slot);
      if (m < 0) continue;
      const Mount& mount = data.mounts[m];
      Observation obs;
      obs.campaign = c;
      obs.slot = slot;
      obs.position = slot_level[slot];
      obs.roll_type = mount.roll_type;
      obs.mount = m;
      obs.measurement = index.MeasurementOf(c, slot);
      if (obs.measurement >= 0) {
        obs.measured_um = data.measurements[obs.measurement].wear_center_um;
      }
      std::fill(grade_load.begin(), grade_load.end(), 0.0);
      for (auto& v : grade_passes) v.clear();
      for (int pi : index.PassesOf(c, mount.stand)) {
        const Pass& pass = data.passes[pi];
        const PassLoadInput in = MakeLoadInput(pass, mount);
        const double base = BaseLoad(law, in);
        if (!std::isfinite(base) || base < 0) {
          return Status::InvalidArgument(
              "coil " + data.coil_ids[pass.coil] + " at " +
              RollPositionName(mount.stand, mount.position) +
              ": wear load is not a finite non-negative number");
        }
        grade_load[pass.grade] += base;
        if (law == WearLaw::kCao) {
          grade_passes[pass.grade].emplace_back(base, std::log(CaoStress(in)));
        }
        ++obs.coils;
        obs.rolled_length_m += pass.length_m;
      }
      for (int s = 0; s < num_grades; ++s) {
        if (grade_load[s] <= 0) continue;
        CellLoad cell;
        cell.grade = s;
        cell.load = grade_load[s];
        if (law == WearLaw::kCao) {
          cell.pass_begin = static_cast<int>(st.cao_base.size());
          for (const auto& [b, ls] : grade_passes[s]) {
            st.cao_base.push_back(b);
            st.cao_log_stress.push_back(ls);
          }
          cell.pass_end = static_cast<int>(st.cao_base.size());
        }
        obs.cells.push_back(cell);
      }
      st.observations.push_back(std::move(obs));
    }
  }
  return st;
}

double PredictObservation(const WearModel& model, const WearStatistics& stats,
                          const Observation& obs, double* grad) {
  const KStructure& ks = model.structure;
  const int num_groups = static_cast<int>(ks.groups().size());
  const int a_index = ks.num_coefficients();
  double total = 0;
  for (const CellLoad& cell : obs.cells) {
    const double k = ks.K(model.k, obs.position, obs.roll_type, cell.grade);
    double load = cell.load;
    double dload_da = 0;
    if (model.law == WearLaw::kCao) {
      // Load(a) = sum_i base_i * exp(a * ln stress_i)  (Cao's law).
      load = 0;
      for (int i = cell.pass_begin; i < cell.pass_end; ++i) {
        const double term =
            stats.cao_base[i] * std::exp(model.cao_exponent * stats.cao_log_stress[i]);
        load += term;
        dload_da += term * stats.cao_log_stress[i];
      }
    }
    const double wear = k * load;
    total += wear;
    if (grad != nullptr) {
      for (int g = 0; g < num_groups; ++g) {
        const int c = ks.CoefficientOf(g, obs.position, obs.roll_type, cell.grade);
        if (c >= 0) grad[c] += wear;
      }
      if (model.law == WearLaw::kCao) grad[a_index] += k * dload_da;
    }
  }
  return total;
}

}  // namespace rollwear
