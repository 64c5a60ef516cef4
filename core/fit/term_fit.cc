// Joint LM fit of option-1 coefficients and model terms; see term_fit.h.
#include "core/fit/term_fit.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <utility>

#include "core/fit/calibration.h"
#include "core/fit/lm_setup.h"
#include "core/fit/robust.h"
#include "core/fit/term_model_internal.h"

namespace rollwear {

using fit_internal::TermModel;

namespace {

class TermCost : public ceres::CostFunction {
 public:
  // `prior`: (index into the free parameters, 1 / prior sd) of every
  // parameter with a normal prior, one pseudo-residual each.
  TermCost(TermModel* model, const std::vector<int>& subset, const std::vector<double>& sd,
           std::vector<double> full, std::vector<int> free,
           std::vector<std::pair<int, double>> prior)
      : model_(model),
        subset_(subset),
        sd_(sd),
        full_(std::move(full)),
        free_(std::move(free)),
        prior_(std::move(prior)) {
    set_num_residuals(static_cast<int>(subset_.size() + prior_.size()));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(free_.size()));
    grad_.resize(model_->num_params());
  }

  // Every evaluation computes the Jacobian too (the exp's of the
  // multipliers dominate and are shared); a residual-only evaluation keeps
  // it, and the Jacobian that Levenberg-Marquardt asks for at the same
  // point once the step is accepted is that kept one, bit for bit.
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const bool jac = jacobians != nullptr && jacobians[0] != nullptr;
    const size_t nf = free_.size();
    const size_t nr = subset_.size() + prior_.size();
    if (jac && kept_ && SameBits(parameters[0], kept_x_)) {
      std::copy(kept_res_.begin(), kept_res_.end(), residuals);
      std::copy(kept_jac_.begin(), kept_jac_.end(), jacobians[0]);
      return true;
    }
    kept_ = false;
    kept_jac_.resize(nr * nf);
    double* jout = jac ? jacobians[0] : kept_jac_.data();
    for (size_t j = 0; j < nf; ++j) full_[free_[j]] = parameters[0][j];
    model_->SetParams(full_.data());
    for (size_t row = 0; row < subset_.size(); ++row) {
      const int o = subset_[row];
      std::fill(grad_.begin(), grad_.end(), 0.0);
      const double y = model_->Predict(full_.data(), o, grad_.data());
      const double w = 1.0 / sd_[o];
      residuals[row] = w * (data_y(o) - y);
      if (!std::isfinite(residuals[row])) return false;
      for (size_t j = 0; j < nf; ++j) jout[row * nf + j] = -w * grad_[free_[j]];
    }
    for (size_t q = 0; q < prior_.size(); ++q) {
      const size_t row = subset_.size() + q;
      const auto [j, inv_sd] = prior_[q];
      residuals[row] = inv_sd * parameters[0][j];
      std::fill(jout + row * nf, jout + (row + 1) * nf, 0.0);
      jout[row * nf + j] = inv_sd;
    }
    if (!jac) {
      kept_x_.assign(parameters[0], parameters[0] + nf);
      kept_res_.assign(residuals, residuals + nr);
      kept_ = true;
    }
    return true;
  }

  void set_measured(const std::vector<double>* y) { y_ = y; }

 private:
  double data_y(int o) const { return (*y_)[o]; }
  static bool SameBits(const double* x, const std::vector<double>& kept) {
    return std::memcmp(x, kept.data(), kept.size() * sizeof(double)) == 0;
  }
  TermModel* model_;
  const std::vector<int>& subset_;
  const std::vector<double>& sd_;
  mutable std::vector<double> full_;
  std::vector<int> free_;
  std::vector<std::pair<int, double>> prior_;
  mutable std::vector<double> grad_;
  const std::vector<double>* y_ = nullptr;
  // The last residual-only evaluation: its point, residuals and Jacobian.
  mutable bool kept_ = false;
  mutable std::vector<double> kept_x_, kept_res_, kept_jac_;
};

// Gauge: fixes levels without data and the heaviest kR and kS level (a
// reference per group); with a grade prior (TermData::grade_prior_sd) the kS
// levels with load need no reference and are listed in *shrunk_grades
// (calibration.h). Returns the free parameter indices.
std::vector<int> FreeTermParameters(const TermModel& model, const std::vector<double>& load,
                                    double grade_prior_sd, std::vector<int>* shrunk_grades) {
  const int n = model.num_params();
  const int n_coef = model.num_coef();
  shrunk_grades->clear();
  for (int i = model.s_offset(); i < n_coef && grade_prior_sd > 0; ++i) {
    if (load[i] > 0) shrunk_grades->push_back(i);
  }
  if (static_cast<int>(shrunk_grades->size()) < kMinShrunkGrades) shrunk_grades->clear();
  std::vector<bool> fixed(n, false);
  for (int i = 0; i < n_coef; ++i) fixed[i] = load[i] <= 0;
  auto heaviest = [&load](int b, int e) {
    int best = b;
    for (int i = b; i < e; ++i) {
      if (load[i] > load[best]) best = i;
    }
    return best;
  };
  if (model.s_offset() > model.r_offset()) {
    fixed[heaviest(model.r_offset(), model.s_offset())] = true;
  }
  if (shrunk_grades->empty()) fixed[heaviest(model.s_offset(), n_coef)] = true;
  std::vector<int> free;
  for (int i = 0; i < n; ++i) {
    if (!fixed[i]) free.push_back(i);
  }
  return free;
}

}  // namespace

StatusOr<TermFitResult> FitTerms(const TermData& data, const std::vector<int>& subset,
                                 const std::vector<double>& sd,
                                 const std::vector<double>& log_k_start,
                                 const std::vector<TermSpec>& terms, bool compute_errors) {
  if (subset.empty()) return Status::FailedPrecondition("no observations to fit");
  TermModel model(data, terms);
  const int n = model.num_params();
  const int n_coef = model.num_coef();
  std::vector<double> full(n, 0.0);
  // Load carried by each coefficient in the subset (identifiability).
  std::vector<double> load(n_coef, 0.0);
  std::vector<double> meas_pos(data.positions.size(), 0.0), load_pos(data.positions.size(), 0.0);
  for (int o : subset) {
    const TermObservation& obs = data.obs[o];
    double total = 0;
    for (int i = obs.pass_begin; i < obs.pass_end; ++i) {
      load[model.s_offset() + data.grade[i]] += data.load[i];
      total += data.load[i];
    }
    load[obs.position] += total;
    if (obs.roll_type >= 0) load[model.r_offset() + obs.roll_type] += total;
    meas_pos[obs.position] += obs.measured_um;
    load_pos[obs.position] += total;
  }
  if (static_cast<int>(log_k_start.size()) == n_coef) {
    std::copy(log_k_start.begin(), log_k_start.end(), full.begin());
  } else {
    for (size_t p = 0; p < data.positions.size(); ++p) {
      if (meas_pos[p] > 0 && load_pos[p] > 0) full[p] = std::log(meas_pos[p] / load_pos[p]);
    }
  }
  int off = n_coef;
  for (const TermSpec& t : terms) {
    for (int j = 0; j < t.term.NumParams(); ++j) {
      full[off + j] = std::clamp(t.term.params[j], t.lower[j], t.upper[j]);
    }
    off += t.term.NumParams();
  }
  std::vector<int> shrunk_grades;
  const std::vector<int> free =
      FreeTermParameters(model, load, data.grade_prior_sd, &shrunk_grades);
  std::vector<double> x;
  for (int i : free) x.push_back(full[i]);
  std::vector<double> y(data.obs.size(), 0.0);
  for (int o : subset) y[o] = data.obs[o].measured_um;
  std::vector<std::pair<int, double>> prior;
  off = n_coef;
  for (const TermSpec& t : terms) {
    for (int j = 0; j < t.term.NumParams() && t.prior_sd > 0; ++j) {
      const int fj = static_cast<int>(std::find(free.begin(), free.end(), off + j) - free.begin());
      prior.emplace_back(fj, 1.0 / t.prior_sd);
    }
    off += t.term.NumParams();
  }
  for (int i : shrunk_grades) {
    const int fj = static_cast<int>(std::find(free.begin(), free.end(), i) - free.begin());
    prior.emplace_back(fj, 1.0 / data.grade_prior_sd);
  }
  auto* cost = new TermCost(&model, subset, sd, full, free, std::move(prior));
  cost->set_measured(&y);
  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, x.data());
  off = n_coef;
  for (const TermSpec& t : terms) {
    for (int j = 0; j < t.term.NumParams(); ++j) {
      const int fj = static_cast<int>(std::find(free.begin(), free.end(), off + j) - free.begin());
      problem.SetParameterLowerBound(x.data(), fj, t.lower[j]);
      problem.SetParameterUpperBound(x.data(), fj, t.upper[j]);
    }
    off += t.term.NumParams();
  }
  LmOptions lm;
  lm.max_iterations = 60;
  lm.function_tolerance = 1e-9;
  lm.parameter_tolerance = 1e-9;
  ceres::Solver::Summary summary;
  ceres::Solve(MakeLmSolverOptions(lm), &problem, &summary);
  for (size_t j = 0; j < free.size(); ++j) full[free[j]] = x[j];
  model.SetParams(full.data());

  TermFitResult r;
  r.log_k.assign(full.begin(), full.begin() + n_coef);
  r.terms = model.terms();
  r.iterations = static_cast<int>(summary.iterations.size());
  r.num_free = static_cast<int>(free.size());
  r.weighted_rss = 2 * summary.final_cost;
  r.usable = summary.IsSolutionUsable() && std::isfinite(r.weighted_rss);
  if (compute_errors && r.usable) {
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::DENSE_SVD;
    co.null_space_rank = -1;
    co.min_reciprocal_condition_number = 1e-12;
    ceres::Covariance covariance(co);
    const int nf = static_cast<int>(free.size());
    std::vector<double> cx(static_cast<size_t>(nf) * nf);
    std::vector<std::pair<const double*, const double*>> blocks = {{x.data(), x.data()}};
    if (covariance.Compute(blocks, &problem) &&
        covariance.GetCovarianceBlock(x.data(), x.data(), cx.data())) {
      // The grade prior's rows are in weighted_rss and its G grades in nf.
      const int rows = static_cast<int>(subset.size() + shrunk_grades.size());
      const double s2 = r.weighted_rss / std::max(1, rows - nf);
      for (int i = n_coef; i < n; ++i) {
        const int fj = static_cast<int>(std::find(free.begin(), free.end(), i) - free.begin());
        r.term_std_error.push_back(std::sqrt(std::max(0.0, s2 * cx[fj * nf + fj])));
      }
    }
  }
  return r;
}

namespace {

// The score statistic from the current model's weighted Jacobian j0 (its QR
// decomposition `qr`), the candidate's weighted derivative columns jc and
// the weighted residuals r (term_fit.h).
double ScoreFromColumns(const Eigen::MatrixXd& j0,
                        const Eigen::ColPivHouseholderQR<Eigen::MatrixXd>& qr,
                        const Eigen::MatrixXd& jc, const Eigen::VectorXd& r, int* df) {
  const Eigen::Index m = r.size();
  // Drop candidate columns that are identically zero (parameters whose
  // derivative vanishes at the start, such as a length scale at b = 0).
  std::vector<int> keep;
  for (int j = 0; j < jc.cols(); ++j) {
    if (jc.col(j).squaredNorm() > 0) keep.push_back(j);
  }
  *df = 0;
  if (keep.empty()) return 0;
  Eigen::MatrixXd jk(m, keep.size());
  for (size_t j = 0; j < keep.size(); ++j) jk.col(j) = jc.col(keep[j]);
  // Project out the current model's Jacobian (rank-revealing QR handles the
  // gauge directions), then S = r' P (P'P)^+ P' r / sigma^2.
  const Eigen::MatrixXd resid_cols = jk - j0 * qr.solve(jk);
  const Eigen::VectorXd g = resid_cols.transpose() * r;
  const Eigen::MatrixXd info = resid_cols.transpose() * resid_cols;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(info);
  const double top = es.eigenvalues().maxCoeff();
  double s = 0;
  for (int i = 0; i < es.eigenvalues().size(); ++i) {
    const double lambda = es.eigenvalues()[i];
    if (!(lambda > 1e-10 * top) || !(top > 0)) continue;
    const double proj = es.eigenvectors().col(i).dot(g);
    s += proj * proj / lambda;
    ++*df;
  }
  const double sigma2 = r.squaredNorm() / static_cast<double>(m);
  return sigma2 > 0 ? s / sigma2 : 0.0;
}

// The full parameter vector (log_k, then every term's params) of `terms`.
std::vector<double> FullParams(const TermModel& model, const std::vector<double>& log_k,
                               const std::vector<TermSpec>& terms) {
  std::vector<double> full(model.num_params(), 0.0);
  std::copy(log_k.begin(), log_k.end(), full.begin());
  int off = model.num_coef();
  for (const TermSpec& t : terms) {
    std::copy(t.term.params.begin(), t.term.params.end(), full.begin() + off);
    off += t.term.NumParams();
  }
  return full;
}

// Weighted residuals r_o = (y_o - yhat_o) / sd_o of `subset` under `model`
// at `full`, and the weighted derivative columns: the first n_cur in j0,
// the rest in jc.
void WeightedJacobian(const TermData& data, const std::vector<int>& subset,
                      const std::vector<double>& sd, const std::vector<double>& full, int n_cur,
                      TermModel* model, Eigen::MatrixXd* j0, Eigen::MatrixXd* jc,
                      Eigen::VectorXd* r) {
  const int n = model->num_params();
  const int m = static_cast<int>(subset.size());
  j0->resize(m, n_cur);
  jc->resize(m, n - n_cur);
  r->resize(m);
  std::vector<double> grad(n);
  for (int row = 0; row < m; ++row) {
    const int o = subset[row];
    std::fill(grad.begin(), grad.end(), 0.0);
    const double y = model->Predict(full.data(), o, grad.data());
    const double w = 1.0 / sd[o];
    (*r)[row] = w * (data.obs[o].measured_um - y);
    for (int j = 0; j < n_cur; ++j) (*j0)(row, j) = w * grad[j];
    for (int j = n_cur; j < n; ++j) (*jc)(row, j - n_cur) = w * grad[j];
  }
}

}  // namespace

double ScoreStatistic(const TermData& data, const std::vector<int>& subset,
                      const std::vector<double>& sd, const std::vector<double>& log_k,
                      const std::vector<TermSpec>& terms, const TermSpec& candidate, int* df) {
  std::vector<TermSpec> all = terms;
  all.push_back(candidate);
  TermModel model(data, all);
  const int n = model.num_params();
  const int n_cur = n - candidate.term.NumParams();
  const std::vector<double> full = FullParams(model, log_k, all);
  model.SetParams(full.data());
  Eigen::MatrixXd j0, jc;
  Eigen::VectorXd r;
  WeightedJacobian(data, subset, sd, full, n_cur, &model, &j0, &jc, &r);
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(j0);
  return ScoreFromColumns(j0, qr, jc, r, df);
}

struct ScoreScreen::Impl {
  const TermData* data = nullptr;
  const std::vector<int>* subset = nullptr;
  const std::vector<double>* sd = nullptr;
  std::vector<double> log_k;
  std::vector<TermSpec> terms;
  Eigen::MatrixXd j0;
  Eigen::VectorXd r;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr;
  std::vector<double> pass_c;  // per pass: the current model's contribution
};

ScoreScreen::ScoreScreen(const TermData& data, const std::vector<int>& subset,
                         const std::vector<double>& sd, const std::vector<double>& log_k,
                         const std::vector<TermSpec>& terms)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.data = &data;
  s.subset = &subset;
  s.sd = &sd;
  s.log_k = log_k;
  s.terms = terms;
  TermModel model(data, terms);
  const std::vector<double> full = FullParams(model, log_k, terms);
  model.SetParams(full.data());
  s.pass_c.assign(data.load.size(), 0.0);
  model.set_pass_contributions(&s.pass_c, false);
  Eigen::MatrixXd none;
  WeightedJacobian(data, subset, sd, full, model.num_params(), &model, &s.j0, &none, &s.r);
  s.qr.compute(s.j0);
}

ScoreScreen::~ScoreScreen() = default;

namespace {

// The parameter whose derivative is 1 (the others' are 0) of a binned,
// per-level or cell multiplier at all-zero parameters, where it is exactly
// 1 (TermMultiplier, model_terms.cc); -1 where z has none (m = 1, dm = 0).
int UnitColumnAtZero(const ModelTerm& term, double z) {
  if (std::isnan(z)) return -1;
  if (term.form == TermForm::kCell) return 0;
  if (term.form == TermForm::kBinned) return TermBin(term, z) - 1;
  const int l = static_cast<int>(z);  // kPerLevel
  return l <= 0 || l >= term.num_levels ? -1 : l - 1;
}

}  // namespace

double ScoreScreen::Statistic(const TermSpec& candidate, int* df) const {
  const Impl& s = *impl_;
  const TermData& data = *s.data;
  // The candidate alone, for its scope and parameter layout.
  const TermModel scope(data, {candidate});
  const ModelTerm& term = candidate.term;
  const int np = term.NumParams();
  const bool measurement = term.IsMeasurementTerm();
  const bool additive = term.IsAdditiveTerm();
  const bool all_zero =
      std::all_of(term.params.begin(), term.params.end(), [](double b) { return b == 0.0; });
  const bool exp_at_zero = !measurement && all_zero && TermModel::IsExpForm(term);
  const bool level_at_zero = !measurement && all_zero &&
                             (term.form == TermForm::kBinned || term.form == TermForm::kPerLevel ||
                              term.form == TermForm::kCell);
  const int m = static_cast<int>(s.subset->size());
  Eigen::MatrixXd jc(m, np);
  std::vector<double> grad(np), dm(std::max(np, 1));
  for (int row = 0; row < m; ++row) {
    const int o = (*s.subset)[row];
    const TermObservation& obs = data.obs[o];
    std::fill(grad.begin(), grad.end(), 0.0);
    if (scope.CoversRoll(0, obs)) {
      if (measurement) {
        // A reading offset: null at the start, or the full computation.
        if (TermOffset(term, data.obs_z[candidate.covariate][o], dm.data()) != 0.0) {
          return ScoreStatistic(data, *s.subset, *s.sd, s.log_k, s.terms, candidate, df);
        }
        for (int j = 0; j < np; ++j) grad[j] += dm[j];
      } else {
        const std::vector<double>& z = data.z[candidate.covariate];
        for (int i = obs.pass_begin; i < obs.pass_end; ++i) {
          if (!scope.CoversPass(0, data.grade[i], i)) continue;
          // Wear added per pass: none at the start (the candidate's columns
          // alone are new, da/d(param)), or the full computation.
          if (additive) {
            if (TermAddend(term, z[i], dm.data()) != 0.0) {
              return ScoreStatistic(data, *s.subset, *s.sd, s.log_k, s.terms,
                                    candidate, df);
            }
            for (int j = 0; j < np; ++j) grad[j] += dm[j];
            continue;
          }
          // m = exp(b u) at b = 0 is 1 with dm/db = u wherever u is finite
          // (TermModel::ExpMultiplier): u alone, no exp.
          if (exp_at_zero) {
            if (std::isnan(z[i])) continue;  // m = 1, dm = 0
            const double u = scope.ExponentOf(0, z[i]);
            if (std::isfinite(u)) {
              grad[0] += s.pass_c[i] * u;
              continue;
            }
          }
          // A level's or bin's exp(b_l) at b = 0: 1, dm/db_l = 1 for z's own.
          if (level_at_zero) {
            const int j = UnitColumnAtZero(term, z[i]);
            if (j >= 0) grad[j] += s.pass_c[i];
            continue;
          }
          // A multiplier of exactly 1 leaves every current prediction and
          // derivative as they are, so only the candidate's columns are new
          // (d(c)/d(param) = c / 1 * dm/d(param)); otherwise the full
          // computation.
          if (TermMultiplier(term, z[i], dm.data()) != 1.0) {
            return ScoreStatistic(data, *s.subset, *s.sd, s.log_k, s.terms, candidate, df);
          }
          for (int j = 0; j < np; ++j) grad[j] += s.pass_c[i] * dm[j];
        }
      }
    }
    const double w = 1.0 / (*s.sd)[o];
    for (int j = 0; j < np; ++j) jc(row, j) = w * grad[j];
  }
  return ScoreFromColumns(s.j0, s.qr, jc, s.r, df);
}

std::vector<double> PredictTerms(const TermData& data, const std::vector<int>& subset,
                                 const std::vector<double>& log_k,
                                 const std::vector<TermSpec>& terms, bool wear_only) {
  TermModel model(data, terms);
  const std::vector<double> full = FullParams(model, log_k, terms);
  model.SetParams(full.data());
  std::vector<double> out;
  out.reserve(subset.size());
  for (int o : subset) out.push_back(model.Predict(full.data(), o, nullptr, wear_only));
  return out;
}

std::vector<double> PredictPassWear(const TermData& data, const std::vector<int>& subset,
                                    const std::vector<double>& log_k,
                                    const std::vector<TermSpec>& terms) {
  TermModel model(data, terms);
  const std::vector<double> full = FullParams(model, log_k, terms);
  model.SetParams(full.data());
  std::vector<double> out(data.load.size(), 0.0);
  model.set_pass_contributions(&out, true);
  for (int o : subset) model.Predict(full.data(), o, nullptr, true);
  return out;
}

std::vector<double> TermNoiseSd(const TermData& td, const std::vector<int>& train,
                                const std::vector<double>& log_k,
                                const std::vector<TermSpec>& terms, WearModel* noise_out,
                                bool robust) {
  std::vector<int> all(td.obs.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  const std::vector<double> pred = PredictTerms(td, all, log_k, terms);
  std::vector<double> p, e;
  for (int o : train) {
    p.push_back(pred[o]);
    e.push_back(td.obs[o].measured_um - pred[o]);
  }
  RobustNoise noise;
  if (robust) {
    noise = FitRobustNoise(p, e);
  } else {
    WearModel ls;
    FitNoiseModel(p, e, &ls);
    noise.noise_sd_um = ls.noise_sd_um;
    noise.noise_rel = ls.noise_rel;
  }
  std::vector<double> sd(td.obs.size());
  for (size_t i = 0; i < sd.size(); ++i) {
    sd[i] = noise.SdAt(pred[i]);
    // Huber IRLS weight w folded into the sd: residual / (sd / sqrt(w)).
    if (robust) {
      sd[i] /= std::sqrt(HuberWeight((td.obs[i].measured_um - pred[i]) / sd[i]));
    }
  }
  if (noise_out != nullptr) {
    noise_out->noise_sd_um = noise.noise_sd_um;
    noise_out->noise_rel = noise.noise_rel;
  }
  return sd;
}

}  // namespace rollwear
