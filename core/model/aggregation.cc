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

std::vector<std::string> PositionLevelNames(const DatasetIndex& index) {
  std::vector<std::string> names;
  for (int slot : index.slots()) {
    names.push_back(RollPositionName(SlotStand(slot), SlotPosition(slot)));
  }
  return names;
}

std::vector<MountedRoll> MountedRolls(const Dataset& data,
                                      const DatasetIndex& index) {
  std::vector<int> slot_level(kNumRollPositionSlots, -1);
  for (size_t l = 0; l < index.slots().size(); ++l) {
    slot_level[index.slots()[l]] = static_cast<int>(l);
  }
  std::vector<MountedRoll> rolls;
  for (int c = 0; c < static_cast<int>(data.campaigns.size()); ++c) {
    for (int slot : index.slots()) {
      const int m = index.MountOf(c, slot);
      if (m < 0) continue;
      MountedRoll r;
      r.campaign = c;
      r.slot = slot;
      r.position = slot_level[slot];
      r.roll_type = data.mounts[m].roll_type;
      r.mount = m;
      r.measurement = index.MeasurementOf(c, slot);
      if (r.measurement >= 0) {
        r.measured_um = data.measurements[r.measurement].wear_center_um;
      }
      rolls.push_back(r);
    }
  }
  return rolls;
}

StatusOr<WearStatistics> Aggregate(const Dataset& data,
                                   const DatasetIndex& index, WearLaw law) {
  WearStatistics st;
  st.law = law;
  st.roll_types = data.roll_types;
  st.grades = data.grades;
  st.positions = PositionLevelNames(index);
  st.position_slots = index.slots();
  const int num_grades = static_cast<int>(data.grades.size());
  std::vector<double> grade_load(num_grades);
  std::vector<std::vector<std::pair<double, double>>> grade_passes(
      law == WearLaw::kCao ? num_grades : 0);
  for (const MountedRoll& roll : MountedRolls(data, index)) {
    const Mount& mount = data.mounts[roll.mount];
    if (law == WearLaw::kNikitenko && std::isnan(mount.hardness_hb)) {
      return Status::InvalidArgument(
          "mounts.csv: hardness_hb is empty for roll " + mount.roll_id +
          " at " + RollPositionName(mount.stand, mount.position) +
          " of campaign " + data.campaigns[mount.campaign].id +
          ": the Nikitenko law needs the roll's hardness (Wang and Cao do "
          "not)");
    }
    Observation obs;
    static_cast<MountedRoll&>(obs) = roll;
    std::fill(grade_load.begin(), grade_load.end(), 0.0);
    for (auto& v : grade_passes) v.clear();
    for (int pi : index.PassesOf(roll.campaign, mount.stand)) {
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
