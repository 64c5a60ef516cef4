#include "core/ann/ann_data.h"

#include <cmath>

#include "core/model/wear_law.h"

namespace rollwear {
namespace {

// Running mean and population variance (Welford 1962, Technometrics 4(3));
// a value not recorded (NaN: a real export's hardness) is skipped.
struct Moments {
  double n = 0, mean = 0, m2 = 0;
  void Add(double x) {
    if (std::isnan(x)) return;
    n += 1;
    const double d = x - mean;
    mean += d / n;
    m2 += d * (x - mean);
  }
  double Sd() const {
    const double sd = n > 0 ? std::sqrt(m2 / n) : 0;
    return sd > 1e-12 * (1 + std::abs(mean)) ? sd : 1.0;
  }
};

}  // namespace

StatusOr<AnnModel> FitAnnScaling(const Dataset& data, const DatasetIndex& index,
                                 const WearStatistics& stats,
                                 const std::vector<int>& train_campaigns,
                                 int hidden1, int hidden2) {
  if (stats.law != WearLaw::kWang) {
    return Status::InvalidArgument(
        "the ann estimates K of Wang's law; aggregate with WearLaw::kWang");
  }
  AnnModel m;
  m.hidden1 = hidden1;
  m.hidden2 = hidden2;
  std::vector<bool> is_train(data.campaigns.size(), false);
  for (int c : train_campaigns) is_train[c] = true;
  // Levels seen in training only: a level without training data would have
  // untrained (random) weights; unseen labels are "unknown" (zero one-hot).
  std::vector<bool> pos_seen(stats.positions.size(), false);
  std::vector<bool> type_seen(stats.roll_types.size(), false);
  std::vector<bool> grade_seen(stats.grades.size(), false);
  for (const Observation& obs : stats.observations) {
    if (!is_train[obs.campaign]) continue;
    pos_seen[obs.position] = true;
    if (obs.roll_type >= 0) type_seen[obs.roll_type] = true;
    for (int pi : index.PassesOf(obs.campaign, data.mounts[obs.mount].stand)) {
      if (data.passes[pi].grade >= 0) grade_seen[data.passes[pi].grade] = true;
    }
  }
  auto keep = [](const std::vector<std::string>& labels,
                 const std::vector<bool>& seen) {
    std::vector<std::string> out;
    for (size_t i = 0; i < labels.size(); ++i) {
      if (seen[i]) out.push_back(labels[i]);
    }
    return out;
  };
  m.positions = keep(stats.positions, pos_seen);
  m.roll_types = keep(stats.roll_types, type_seen);
  m.grades = keep(stats.grades, grade_seen);
  const int d = m.num_inputs();
  const int ns = m.num_static();
  const int offset = ns + static_cast<int>(m.grades.size());

  std::vector<Moments> col(d);
  double sum_m = 0, sum_m2 = 0;
  int n_meas = 0;
  double raw[kAnnNumPassContinuous];
  for (const Observation& obs : stats.observations) {
    if (!is_train[obs.campaign]) continue;
    const Mount& mount = data.mounts[obs.mount];
    for (int pi : index.PassesOf(obs.campaign, mount.stand)) {
      AnnRawPassFeatures(PassInputOf(data, data.passes[pi]),
                         mount.diameter_mm, raw);
      col[ns - 2].Add(mount.hardness_hb);
      col[ns - 1].Add(mount.diameter_mm);
      for (int j = 0; j < kAnnNumPassContinuous; ++j)
        col[offset + j].Add(raw[j]);
    }
    if (obs.measurement >= 0) {
      sum_m += obs.measured_um;
      sum_m2 += obs.measured_um * obs.measured_um;
      ++n_meas;
    }
  }
  if (col[ns - 1].n == 0 || n_meas == 0) {
    return Status::FailedPrecondition(
        "the training campaigns hold no measured roll position with coils");
  }
  m.input_mean = Eigen::VectorXd::Zero(d);
  m.input_sd = Eigen::VectorXd::Ones(d);
  for (int j : {ns - 2, ns - 1}) {
    m.input_mean[j] = col[j].mean;
    m.input_sd[j] = col[j].Sd();
  }
  for (int j = 0; j < kAnnNumPassContinuous; ++j) {
    m.input_mean[offset + j] = col[offset + j].mean;
    m.input_sd[offset + j] = col[offset + j].Sd();
  }
  // Wear state: W = t * m with t ~ U[0, 1]: E[W] = E[m]/2, E[W^2] = E[m^2]/3.
  const double mu_w = sum_m / n_meas / 2;
  const double var_w = sum_m2 / n_meas / 3 - mu_w * mu_w;
  m.input_mean[d - 1] = mu_w;
  m.input_sd[d - 1] = var_w > 0 ? std::sqrt(var_w) : std::max(mu_w, 1.0);
  return m;
}

AnnInputs BuildAnnInputs(const AnnModel& model, const Dataset& data,
                         const DatasetIndex& index,
                         const WearStatistics& stats) {
  AnnInputs in;
  int total = 0;
  for (const Observation& obs : stats.observations) {
    total += static_cast<int>(
        index.PassesOf(obs.campaign, data.mounts[obs.mount].stand).size());
  }
  in.pass_input.resize(model.num_pass(), total);
  in.load.resize(total);
  in.sequences.reserve(stats.observations.size());
  int col = 0;
  for (size_t o = 0; o < stats.observations.size(); ++o) {
    const Observation& obs = stats.observations[o];
    const Mount& mount = data.mounts[obs.mount];
    AnnSequence seq;
    seq.observation = static_cast<int>(o);
    seq.campaign = obs.campaign;
    seq.position = obs.position;
    seq.measured = obs.measurement >= 0;
    seq.measured_um = obs.measured_um;
    seq.static_input = model.EncodeStatic(
        model.PositionLevel(stats.positions[obs.position]),
        obs.roll_type >= 0
            ? model.RollTypeLevel(stats.roll_types[obs.roll_type])
            : -1,
        mount.hardness_hb, mount.diameter_mm);
    seq.begin = col;
    for (int pi : index.PassesOf(obs.campaign, mount.stand)) {
      const Pass& pass = data.passes[pi];
      model.EncodePass(PassInputOf(data, pass), mount.diameter_mm,
                       in.pass_input.col(col).data());
      in.load[col] = BaseLoad(WearLaw::kWang, MakeLoadInput(pass, mount));
      ++col;
    }
    seq.end = col;
    in.sequences.push_back(std::move(seq));
  }
  return in;
}

FitMetrics AnnMetrics(const AnnInputs& inputs, const std::vector<int>& seqs,
                      const std::vector<double>& predicted) {
  std::vector<int> position;
  std::vector<double> measured;
  for (int k : seqs) {
    position.push_back(inputs.sequences[k].position);
    measured.push_back(inputs.sequences[k].measured_um);
  }
  return MetricsOf(position, measured, predicted);
}

}  // namespace rollwear
