// The stages of Calibrate() that need no Ceres (and the one-line reports of
// calibration.h): input validation, the option-2 prefit, the initial set,
// gauge fixing, the grade shrinkage's evidence update, the gauge transform
// of the result and the noise model (see calibration_internal.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "core/base/random.h"
#include "core/fit/calibration_internal.h"
#include "core/fit/robust.h"

namespace rollwear {

std::string CalibrationSummary::BriefReport() const {
  char buf[320];
  std::snprintf(buf, sizeof(buf),
                "%s after %d iterations (%d evaluations), cost %.6g -> %.6g "
                "µm², %d free parameters, %d observations, %.3f s, %s",
                termination.c_str(), iterations, evaluations, initial_cost,
                final_cost, num_free_parameters, num_observations, seconds,
                usable ? "usable" : ("NOT usable: " + message).c_str());
  return buf;
}

std::string GradeShrinkage::Sentence() const {
  if (!applied) return "grades fitted freely";
  char buf[200];
  std::snprintf(buf, sizeof(buf),
                "%d grades shrunk toward the typical grade (random effect, "
                "tau = %.3g on log kS, %.1f effective parameters%s)",
                levels, tau, effective_parameters,
                converged ? "" : ", tau not settled");
  return buf;
}

namespace calibration_internal {
namespace {

// Index of the level with the largest training load in [begin, end).
int HeaviestLevel(const std::vector<double>& load, int begin, int end) {
  int best = begin;
  for (int i = begin; i < end; ++i) {
    if (load[i] > load[best]) best = i;
  }
  return best;
}

// One random value per factor group (u follows kRS's first value), a in
// [0.5, 2] for Cao.
void RandomStart(const Fit& fit, uint64_t seed, std::vector<double>* theta) {
  const Layout& layout = fit.layout();
  const KStructure& structure = fit.structure();
  const std::vector<FactorGroup>& groups = structure.groups();
  Random rng(seed);
  for (const FactorGroup& g : groups) {
    const double v = std::log(rng.Uniform(0.1, 2.0));
    for (int i = 0; i < g.size; ++i) (*theta)[g.offset + i] = v;
  }
  if (layout.u_offset >= 0) {
    for (int r = 0; r < static_cast<int>(structure.roll_types().size()); ++r) {
      (*theta)[layout.u_offset + r] = (*theta)[groups[1].offset];
    }
  }
  if (layout.a_index >= 0) (*theta)[layout.a_index] = rng.Uniform(0.5, 2.0);
}

// Option 2's empirical start: kF from the pre-fit; kRS = kR * kS;
// u = log kR, v = log kS.
void EmpiricalStartFromPrefit(const Fit& fit, const CalibrationResult& prefit,
                              std::vector<double>* theta) {
  const Layout& layout = fit.layout();
  const KStructure& structure = fit.structure();
  const std::vector<FactorGroup>& groups = structure.groups();
  const KStructure& pks = prefit.model.structure;
  const int nr = static_cast<int>(structure.roll_types().size());
  const int ns = static_cast<int>(structure.grades().size());
  for (int p = 0; p < groups[0].size; ++p) {
    (*theta)[p] = std::log(prefit.model.k[p]);
  }
  for (int r = 0; r < nr; ++r) {
    const double lr = std::log(prefit.model.k[pks.groups()[1].offset + r]);
    (*theta)[layout.u_offset + r] = lr;
    for (int s = 0; s < ns; ++s) {
      const double ls = std::log(prefit.model.k[pks.groups()[2].offset + s]);
      (*theta)[layout.v_offset + s] = ls;
      (*theta)[groups[1].offset + r * ns + s] = lr + ls;
    }
  }
}

// kF[p] = sum d_meas / sum load over the position's training campaigns (load
// at the start exponent for Cao).
void EmpiricalStartFromData(const WearStatistics& stats,
                            const std::vector<int>& train, const Fit& fit,
                            std::vector<double>* theta) {
  const Layout& layout = fit.layout();
  const std::vector<FactorGroup>& groups = fit.structure().groups();
  WearModel unit = fit.model();
  std::fill(unit.k.begin(), unit.k.end(), 1.0);
  unit.cao_exponent = layout.a_index >= 0 ? (*theta)[layout.a_index] : 1.0;
  std::vector<double> meas(groups[0].size, 0.0), pred(groups[0].size, 0.0);
  for (int o : train) {
    const Observation& obs = stats.observations[o];
    meas[obs.position] += obs.measured_um;
    pred[obs.position] += PredictObservation(unit, stats, obs);
  }
  for (int p = 0; p < groups[0].size; ++p) {
    if (meas[p] > 0 && pred[p] > 0) (*theta)[p] = std::log(meas[p] / pred[p]);
  }
}

}  // namespace

Status ValidateInputs(const WearStatistics& stats,
                      const std::vector<int>& train,
                      const CalibrationOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) {
    return Status::InvalidArgument("calibration options: " + error);
  }
  if (options.law != stats.law) {
    return Status::InvalidArgument(
        "calibration options ask for the " +
        std::string(WearLawName(options.law)) +
        " law but the statistics were aggregated for " +
        WearLawName(stats.law));
  }
  if (train.empty()) {
    return Status::FailedPrecondition(
        "no measured training campaigns to calibrate on");
  }
  for (int o : train) {
    if (o < 0 || o >= static_cast<int>(stats.observations.size()) ||
        stats.observations[o].measurement < 0) {
      return Status::InvalidArgument("training observation " +
                                     std::to_string(o) +
                                     " does not exist or has no measurement");
    }
  }
  return Status::Ok();
}

StatusOr<CalibrationResult> Option2Prefit(const WearStatistics& stats,
                                          const std::vector<int>& train,
                                          const CalibrationOptions& options,
                                          Fit* fit) {
  CalibrationOptions pre = options;
  pre.option = 1;
  pre.initial_set = InitialSet::kEmpirical;
  pre.derivatives = DerivativeMode::kExact;
  pre.compute_covariance = false;
  pre.shrink_grades = false;  // option 2's prior is its own
  ROLLWEAR_ASSIGN_OR_RETURN(CalibrationResult prefit,
                            Calibrate(stats, train, pre));
  const int dof = std::max(
      1, static_cast<int>(train.size()) - prefit.summary.num_free_parameters);
  const double sigma_w = std::sqrt(prefit.summary.final_cost / dof);
  fit->set_prior_scale(sigma_w / options.option2_prior_sd);
  return prefit;
}

std::vector<double> InitialTheta(const WearStatistics& stats,
                                 const std::vector<int>& train,
                                 const CalibrationOptions& options,
                                 const Fit& fit,
                                 const CalibrationResult* prefit) {
  const Layout& layout = fit.layout();
  std::vector<double> theta(layout.n_full, 0.0);
  if (options.initial_set == InitialSet::kRandom) {
    RandomStart(fit, options.seed, &theta);
  } else {
    if (layout.a_index >= 0) theta[layout.a_index] = 1.0;
  }
  if (options.initial_set == InitialSet::kEmpirical) {
    if (prefit != nullptr) {
      EmpiricalStartFromPrefit(fit, *prefit, &theta);
    } else {
      EmpiricalStartFromData(stats, train, fit, &theta);
    }
  }
  return theta;
}

// Holds fixed every coefficient without training data (options 1 and 3) and
// one reference level per non-position group; option 2 fixes the reference
// of u and v instead.
std::vector<int> FreeParameters(const Fit& fit,
                                const CalibrationOptions& options) {
  const Layout& layout = fit.layout();
  const KStructure& structure = fit.structure();
  const std::vector<FactorGroup>& groups = structure.groups();
  const std::vector<double>& load = fit.coef_load();
  std::vector<bool> fixed(layout.n_full, false);
  for (size_t g = 0; g < groups.size(); ++g) {
    const FactorGroup& grp = groups[g];
    const bool cell_group = grp.key == FactorKey::kRollTypeGrade;
    for (int i = grp.offset; i < grp.offset + grp.size; ++i) {
      if (load[i] <= 0 && !cell_group) fixed[i] = true;
    }
    // A shrunk grade group needs no reference level: its prior fixes the
    // gauge (calibration.h).
    const bool shrunk =
        grp.key == FactorKey::kGrade && !fit.shrunk_grades().empty();
    if (g > 0 && !cell_group && !shrunk) {
      fixed[HeaviestLevel(load, grp.offset, grp.offset + grp.size)] = true;
    }
  }
  if (options.option == 2) {
    const int nr = static_cast<int>(structure.roll_types().size());
    const int ns = static_cast<int>(structure.grades().size());
    std::vector<double> rt_load(nr, 0.0), gr_load(ns, 0.0);
    for (int r = 0; r < nr; ++r) {
      for (int s = 0; s < ns; ++s) {
        const double l = load[groups[1].offset + r * ns + s];
        rt_load[r] += l;
        gr_load[s] += l;
      }
    }
    for (int r = 0; r < nr; ++r) fixed[layout.u_offset + r] = rt_load[r] <= 0;
    for (int s = 0; s < ns; ++s) fixed[layout.v_offset + s] = gr_load[s] <= 0;
    fixed[layout.u_offset + HeaviestLevel(rt_load, 0, nr)] = true;
    fixed[layout.v_offset + HeaviestLevel(gr_load, 0, ns)] = true;
  }
  std::vector<int> free;
  for (int i = 0; i < layout.n_full; ++i) {
    if (!fixed[i]) free.push_back(i);
  }
  return free;
}

EvidenceUpdate UpdateGradeEvidence(Fit* fit, const std::vector<int>& free,
                                   const std::vector<double>& theta) {
  EvidenceUpdate up;
  const int rows = fit->num_rows();
  const int n = fit->layout().n_full;
  const int nf = static_cast<int>(free.size());
  std::vector<double> residuals(rows), jac(static_cast<size_t>(rows) * n);
  fit->Evaluate(theta.data(), residuals.data(), jac.data());
  Eigen::MatrixXd j(rows, nf);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < nf; ++c) j(r, c) = jac[static_cast<size_t>(r) * n + free[c]];
  }
  // H = J'J, prior rows included; [H^-1]_ss of every shrunk grade.
  const Eigen::MatrixXd h = j.transpose() * j;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(h);
  if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-12)) return up;
  const Eigen::MatrixXd h_inv = ldlt.solve(Eigen::MatrixXd::Identity(nf, nf));
  const double lambda = fit->grade_scale();
  double sum_sq = 0;
  for (int c : fit->shrunk_grades()) {
    const auto at = std::find(free.begin(), free.end(), c);
    if (at == free.end()) continue;
    const long k = at - free.begin();
    up.gamma += std::clamp(1 - lambda * lambda * h_inv(k, k), 0.0, 1.0);
    sum_sq += theta[c] * theta[c];
  }
  double rss = 0;
  for (int r = 0; r < fit->num_data_rows(); ++r) rss += residuals[r] * residuals[r];
  const double levels = static_cast<double>(fit->shrunk_grades().size());
  const double dof = fit->num_data_rows() - (nf - levels) - up.gamma;
  constexpr double kTauFloor = 1e-3;
  up.tau = up.gamma > 0 ? std::max(kTauFloor, std::sqrt(sum_sq / up.gamma))
                        : kTauFloor;
  up.sigma = dof > 0 ? std::sqrt(rss / dof) : 0;
  up.ok = std::isfinite(up.gamma) && std::isfinite(up.tau) &&
          std::isfinite(up.sigma) && up.sigma > 0;
  return up;
}

Eigen::MatrixXd GaugeTransform(const Fit& fit) {
  const Layout& layout = fit.layout();
  const std::vector<FactorGroup>& groups = fit.structure().groups();
  const std::vector<double>& load = fit.coef_load();
  const int n_rep = fit.model().num_parameters();
  Eigen::MatrixXd transform = Eigen::MatrixXd::Zero(n_rep, layout.n_full);
  for (int i = 0; i < layout.n_coef; ++i) transform(i, i) = 1;
  if (layout.a_index >= 0) transform(n_rep - 1, layout.a_index) = 1;
  for (size_t g = 1; g < groups.size(); ++g) {
    const FactorGroup& grp = groups[g];
    std::vector<int> with_data;
    for (int i = grp.offset; i < grp.offset + grp.size; ++i) {
      if (load[i] > 0) with_data.push_back(i);
    }
    if (with_data.empty()) continue;
    const double w = 1.0 / static_cast<double>(with_data.size());
    for (int i = grp.offset; i < grp.offset + grp.size; ++i) {
      for (int j : with_data) transform(i, j) -= w;
    }
    for (int p = 0; p < groups[0].size; ++p) {
      for (int j : with_data) transform(p, j) += w;
    }
  }
  return transform;
}

WearModel ReportedModel(const Fit& fit, const Eigen::MatrixXd& transform,
                        const std::vector<double>& theta) {
  const Layout& layout = fit.layout();
  const int n_rep = static_cast<int>(transform.rows());
  Eigen::Map<const Eigen::VectorXd> theta_vec(theta.data(), layout.n_full);
  const Eigen::VectorXd theta_rep = transform * theta_vec;
  // The fit's evaluations (also those of the covariance) overwrite the fit's
  // model, so the reported model is a separate copy.
  WearModel model = fit.model();
  for (int i = 0; i < layout.n_coef; ++i) model.k[i] = std::exp(theta_rep[i]);
  if (layout.a_index >= 0) model.cao_exponent = theta_rep[n_rep - 1];
  return model;
}

void FitTrainingNoise(const WearStatistics& stats,
                      const std::vector<int>& train, bool robust,
                      WearModel* model) {
  std::vector<double> pred, err;
  for (int o : train) {
    const Observation& obs = stats.observations[o];
    pred.push_back(PredictObservation(*model, stats, obs));
    err.push_back(obs.measured_um - pred.back());
  }
  if (!robust) {
    FitNoiseModel(pred, err, model);
    return;
  }
  const RobustNoise noise = FitRobustNoise(pred, err);
  const double c = TailCoverageScale(noise.u);  // robust.h
  model->noise_sd_um = c * noise.noise_sd_um;
  model->noise_rel = c * noise.noise_rel;
}

}  // namespace calibration_internal
}  // namespace rollwear
