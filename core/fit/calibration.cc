// Calibration of K by Levenberg-Marquardt; see calibration.h for the cost,
// the parameterisation, the gauge and the option-2 prior.
#include "core/fit/calibration.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>

#include <ceres/ceres.h>

#include "core/fit/lm_setup.h"
#include "core/base/random.h"

namespace rollwear {

const char* InitialSetName(InitialSet s) {
  switch (s) {
    case InitialSet::kOnes: return "ones";
    case InitialSet::kRandom: return "random";
    case InitialSet::kEmpirical: return "empirical";
  }
  return "unknown";
}

bool CalibrationOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& what) {
    if (error != nullptr) *error = what;
    return false;
  };
  if (option < 1 || option > 3) return fail("option must be 1, 2 or 3");
  if (!(fd_relative_step > 0 && fd_relative_step < 1)) {
    return fail("fd_relative_step must be in (0, 1)");
  }
  if (max_evaluations_per_parameter < 2) {
    return fail("max_evaluations_per_parameter must be >= 2");
  }
  if (!(log_bound > 0)) return fail("log_bound must be > 0");
  if (!(paper_k_lower > 0 && paper_k_upper > paper_k_lower)) {
    return fail("paper k bounds must satisfy 0 < lower < upper");
  }
  if (!(cao_a_lower < cao_a_upper)) return fail("cao_a_lower must be < cao_a_upper");
  if (!(option2_prior_sd > 0)) return fail("option2_prior_sd must be > 0");
  return lm.IsValid(error);
}

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

namespace {

// The full parameter vector theta: log k (n_coef), then for option 2 the
// prior surface u (roll types) and v (grades), then Cao's a.
struct Layout {
  int n_coef = 0;
  int u_offset = -1;
  int v_offset = -1;
  int a_index = -1;
  int n_full = 0;
  bool IsLog(int i) const { return i != a_index; }
};

class Fit {
 public:
  Fit(const WearStatistics& stats, const std::vector<int>& train,
      const CalibrationOptions& options, KStructure structure)
      : stats_(stats), train_(train), options_(options) {
    model_.law = options.law;
    model_.structure = std::move(structure);
    const KStructure& ks = model_.structure;
    layout_.n_coef = ks.num_coefficients();
    layout_.n_full = layout_.n_coef;
    num_rt_ = static_cast<int>(ks.roll_types().size());
    num_gr_ = static_cast<int>(ks.grades().size());
    if (options.option == 2) {
      layout_.u_offset = layout_.n_full;
      layout_.v_offset = layout_.n_full + num_rt_;
      layout_.n_full += num_rt_ + num_gr_;
    }
    if (options.law == WearLaw::kCao) layout_.a_index = layout_.n_full++;
    model_.k.assign(layout_.n_coef, 1.0);
    // Eq. 9 weights: 1/n_p per roll position.
    std::vector<int> n_per_position(ks.positions().size(), 0);
    for (int o : train) ++n_per_position[stats.observations[o].position];
    for (int o : train) {
      weight_.push_back(
          1.0 / std::sqrt(n_per_position[stats.observations[o].position]));
    }
    // Training load carried by each coefficient (identifiability).
    coef_load_.assign(layout_.n_coef, 0.0);
    for (int o : train) {
      const Observation& obs = stats.observations[o];
      for (const CellLoad& cell : obs.cells) {
        for (size_t g = 0; g < ks.groups().size(); ++g) {
          const int c = ks.CoefficientOf(static_cast<int>(g), obs.position,
                                         obs.roll_type, cell.grade);
          if (c >= 0) coef_load_[c] += cell.load;
        }
      }
    }
    num_rows_ = static_cast<int>(train.size()) +
                (options.option == 2 ? num_rt_ * num_gr_ : 0);
  }

  const Layout& layout() const { return layout_; }
  int num_rows() const { return num_rows_; }
  int num_data_rows() const { return static_cast<int>(train_.size()); }
  const KStructure& structure() const { return model_.structure; }
  const std::vector<double>& coef_load() const { return coef_load_; }
  void set_prior_scale(double lambda) { prior_scale_ = lambda; }
  long evaluations() const { return evaluations_; }

  // Residuals (size num_rows) and, when `jac` is non-null, the row-major
  // Jacobian d(residual)/d(theta) (num_rows x n_full) at theta.
  void Evaluate(const double* theta, double* residuals, double* jac) {
    ++evaluations_;
    for (int i = 0; i < layout_.n_coef; ++i) model_.k[i] = std::exp(theta[i]);
    if (layout_.a_index >= 0) model_.cao_exponent = theta[layout_.a_index];
    const int n = layout_.n_full;
    const int np = model_.num_parameters();
    grad_.assign(np, 0.0);
    if (jac != nullptr) std::fill(jac, jac + static_cast<size_t>(num_rows_) * n, 0.0);
    for (size_t row = 0; row < train_.size(); ++row) {
      const Observation& obs = stats_.observations[train_[row]];
      double* g = nullptr;
      if (jac != nullptr) {
        std::fill(grad_.begin(), grad_.end(), 0.0);
        g = grad_.data();
      }
      const double pred = PredictObservation(model_, stats_, obs, g);
      residuals[row] = weight_[row] * (obs.measured_um - pred);
      if (jac != nullptr) {
        double* jr = jac + row * n;
        for (int j = 0; j < layout_.n_coef; ++j) jr[j] = -weight_[row] * grad_[j];
        if (layout_.a_index >= 0) {
          jr[layout_.a_index] = -weight_[row] * grad_[layout_.n_coef];
        }
      }
    }
    if (options_.option != 2) return;
    // Prior rows: lambda * (log kRS[r,s] - u_r - v_s).
    const int rs_offset = model_.structure.groups()[1].offset;
    int row = static_cast<int>(train_.size());
    for (int r = 0; r < num_rt_; ++r) {
      for (int s = 0; s < num_gr_; ++s, ++row) {
        const int c = rs_offset + r * num_gr_ + s;
        residuals[row] = prior_scale_ * (theta[c] - theta[layout_.u_offset + r] -
                                         theta[layout_.v_offset + s]);
        if (jac != nullptr) {
          double* jr = jac + static_cast<size_t>(row) * n;
          jr[c] = prior_scale_;
          jr[layout_.u_offset + r] = -prior_scale_;
          jr[layout_.v_offset + s] = -prior_scale_;
        }
      }
    }
  }

  // Eq. 9 cost of the data rows of a residual vector.
  double DataCost(const std::vector<double>& residuals) const {
    double c = 0;
    for (size_t i = 0; i < train_.size(); ++i) c += residuals[i] * residuals[i];
    return c;
  }

  WearModel& model() { return model_; }

 private:
  const WearStatistics& stats_;
  const std::vector<int>& train_;
  const CalibrationOptions& options_;
  WearModel model_;
  Layout layout_;
  int num_rt_ = 0, num_gr_ = 0, num_rows_ = 0;
  std::vector<double> weight_;
  std::vector<double> coef_load_;
  std::vector<double> grad_;
  double prior_scale_ = 0;
  long evaluations_ = 0;
};

// Ceres view of the fit in exact mode: one parameter block holding the
// free entries of theta.
class ExactCost : public ceres::CostFunction {
 public:
  ExactCost(Fit* fit, std::vector<double> theta0, std::vector<int> free)
      : fit_(fit), theta_(std::move(theta0)), free_(std::move(free)) {
    set_num_residuals(fit->num_rows());
    mutable_parameter_block_sizes()->push_back(static_cast<int>(free_.size()));
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    for (size_t j = 0; j < free_.size(); ++j) theta_[free_[j]] = parameters[0][j];
    const bool want_jac = jacobians != nullptr && jacobians[0] != nullptr;
    const int n = fit_->layout().n_full;
    if (want_jac) jac_full_.resize(static_cast<size_t>(num_residuals()) * n);
    fit_->Evaluate(theta_.data(), residuals, want_jac ? jac_full_.data() : nullptr);
    if (want_jac) {
      const size_t nf = free_.size();
      for (int r = 0; r < num_residuals(); ++r) {
        for (size_t j = 0; j < nf; ++j) {
          jacobians[0][r * nf + j] = jac_full_[static_cast<size_t>(r) * n + free_[j]];
        }
      }
    }
    for (int r = 0; r < num_residuals(); ++r) {
      if (!std::isfinite(residuals[r])) return false;
    }
    return true;
  }

 private:
  Fit* fit_;
  mutable std::vector<double> theta_;
  std::vector<int> free_;
  mutable std::vector<double> jac_full_;
};

// The study's protocol: natural parameters (k, not log k), residuals only;
// Ceres differentiates by forward differences.
struct PaperResiduals {
  Fit* fit;
  std::vector<int> free;
  mutable std::vector<double> theta;
  bool operator()(double const* const* parameters, double* residuals) const {
    const Layout& l = fit->layout();
    for (size_t j = 0; j < free.size(); ++j) {
      const double x = parameters[0][j];
      if (l.IsLog(free[j])) {
        if (!(x > 0)) return false;
        theta[free[j]] = std::log(x);
      } else {
        theta[free[j]] = x;
      }
    }
    fit->Evaluate(theta.data(), residuals, nullptr);
    for (int r = 0; r < fit->num_rows(); ++r) {
      if (!std::isfinite(residuals[r])) return false;
    }
    return true;
  }
};

// Stops the paper-mode solve before it exceeds its evaluation budget; one
// LM iteration costs n+1 evaluations for the Jacobian and one for the step.
class BudgetCallback : public ceres::IterationCallback {
 public:
  BudgetCallback(const Fit* fit, long budget, long per_iteration)
      : fit_(fit), budget_(budget), per_iteration_(per_iteration) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
    return fit_->evaluations() + per_iteration_ > budget_
               ? ceres::SOLVER_TERMINATE_SUCCESSFULLY
               : ceres::SOLVER_CONTINUE;
  }

 private:
  const Fit* fit_;
  long budget_, per_iteration_;
};

// Index of the level with the largest training load in [begin, end).
int HeaviestLevel(const std::vector<double>& load, int begin, int end) {
  int best = begin;
  for (int i = begin; i < end; ++i) {
    if (load[i] > load[best]) best = i;
  }
  return best;
}

}  // namespace

StatusOr<CalibrationResult> Calibrate(const WearStatistics& stats,
                                      const std::vector<int>& train,
                                      const CalibrationOptions& options) {
  const auto start_time = std::chrono::steady_clock::now();
  std::string error;
  if (!options.IsValid(&error)) {
    return Status::InvalidArgument("calibration options: " + error);
  }
  if (options.law != stats.law) {
    return Status::InvalidArgument(
        "calibration options ask for the " + std::string(WearLawName(options.law)) +
        " law but the statistics were aggregated for " + WearLawName(stats.law));
  }
  if (train.empty()) {
    return Status::FailedPrecondition("no measured training campaigns to calibrate on");
  }
  for (int o : train) {
    if (o < 0 || o >= static_cast<int>(stats.observations.size()) ||
        stats.observations[o].measurement < 0) {
      return Status::InvalidArgument("training observation " + std::to_string(o) +
                                     " does not exist or has no measurement");
    }
  }
  ROLLWEAR_ASSIGN_OR_RETURN(
      const KStructure ks,
      KStructure::ForOption(options.option, stats.positions, stats.roll_types,
                            stats.grades));
  Fit fit(stats, train, options, ks);
  const Layout& layout = fit.layout();
  const KStructure& structure = fit.structure();
  const std::vector<FactorGroup>& groups = structure.groups();
  const std::vector<double>& load = fit.coef_load();

  // Option 2: prior scale from an option-1 pre-fit, which also gives the
  // empirical start.
  std::vector<double> theta(layout.n_full, 0.0);
  std::unique_ptr<CalibrationResult> prefit;
  if (options.option == 2) {
    CalibrationOptions pre = options;
    pre.option = 1;
    pre.initial_set = InitialSet::kEmpirical;
    pre.derivatives = DerivativeMode::kExact;
    pre.compute_covariance = false;
    ROLLWEAR_ASSIGN_OR_RETURN(CalibrationResult r,
                              Calibrate(stats, train, pre));
    prefit = std::make_unique<CalibrationResult>(std::move(r));
    const int dof = std::max(1, static_cast<int>(train.size()) -
                                    prefit->summary.num_free_parameters);
    const double sigma_w = std::sqrt(prefit->summary.final_cost / dof);
    fit.set_prior_scale(sigma_w / options.option2_prior_sd);
  }

  // Initial set.
  if (options.initial_set == InitialSet::kRandom) {
    Random rng(options.seed);
    for (const FactorGroup& g : groups) {
      const double v = std::log(rng.Uniform(0.1, 2.0));
      for (int i = 0; i < g.size; ++i) theta[g.offset + i] = v;
    }
    if (layout.u_offset >= 0) {
      for (int r = 0; r < static_cast<int>(structure.roll_types().size()); ++r) {
        theta[layout.u_offset + r] = theta[groups[1].offset];
      }
    }
    if (layout.a_index >= 0) theta[layout.a_index] = rng.Uniform(0.5, 2.0);
  } else {
    if (layout.a_index >= 0) theta[layout.a_index] = 1.0;
  }
  if (options.initial_set == InitialSet::kEmpirical) {
    if (prefit != nullptr) {
      // kF from the pre-fit; kRS = kR * kS; u = log kR, v = log kS.
      const KStructure& pks = prefit->model.structure;
      const int nr = static_cast<int>(structure.roll_types().size());
      const int ns = static_cast<int>(structure.grades().size());
      for (int p = 0; p < groups[0].size; ++p) theta[p] = std::log(prefit->model.k[p]);
      for (int r = 0; r < nr; ++r) {
        const double lr = std::log(prefit->model.k[pks.groups()[1].offset + r]);
        theta[layout.u_offset + r] = lr;
        for (int s = 0; s < ns; ++s) {
          const double ls = std::log(prefit->model.k[pks.groups()[2].offset + s]);
          theta[layout.v_offset + s] = ls;
          theta[groups[1].offset + r * ns + s] = lr + ls;
        }
      }
    } else {
      // kF[p] = sum d_meas / sum load over the position's training
      // campaigns (load at the start exponent for Cao).
      WearModel unit = fit.model();
      std::fill(unit.k.begin(), unit.k.end(), 1.0);
      unit.cao_exponent = layout.a_index >= 0 ? theta[layout.a_index] : 1.0;
      std::vector<double> meas(groups[0].size, 0.0), pred(groups[0].size, 0.0);
      for (int o : train) {
        const Observation& obs = stats.observations[o];
        meas[obs.position] += obs.measured_um;
        pred[obs.position] += PredictObservation(unit, stats, obs);
      }
      for (int p = 0; p < groups[0].size; ++p) {
        if (meas[p] > 0 && pred[p] > 0) theta[p] = std::log(meas[p] / pred[p]);
      }
    }
  }

  // Gauge and identifiability: hold fixed every coefficient without
  // training data (options 1 and 3) and one reference level per
  // non-position group; option 2 fixes the reference of u and v instead.
  std::vector<bool> fixed(layout.n_full, false);
  for (size_t g = 0; g < groups.size(); ++g) {
    const FactorGroup& grp = groups[g];
    const bool cell_group = grp.key == FactorKey::kRollTypeGrade;
    for (int i = grp.offset; i < grp.offset + grp.size; ++i) {
      if (load[i] <= 0 && !cell_group) fixed[i] = true;
    }
    if (g > 0 && !cell_group) {
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
  const int nf = static_cast<int>(free.size());

  std::vector<double> residuals(fit.num_rows());
  fit.Evaluate(theta.data(), residuals.data(), nullptr);
  CalibrationResult result;
  result.summary.initial_cost = fit.DataCost(residuals);
  result.summary.num_free_parameters = nf;
  result.summary.num_observations = static_cast<int>(train.size());

  const bool paper = options.derivatives == DerivativeMode::kPaperForwardDifference;
  std::vector<double> x(nf);
  for (int j = 0; j < nf; ++j) {
    x[j] = (paper && layout.IsLog(free[j])) ? std::exp(theta[free[j]]) : theta[free[j]];
  }
  ceres::Problem problem;
  ceres::Solver::Options solver_options = MakeLmSolverOptions(options.lm);
  std::unique_ptr<BudgetCallback> budget;
  if (paper) {
    auto* functor = new PaperResiduals{&fit, free, theta};
    ceres::NumericDiffOptions nd;
    nd.relative_step_size = options.fd_relative_step;
    auto* cost = new ceres::DynamicNumericDiffCostFunction<PaperResiduals, ceres::FORWARD>(
        functor, ceres::TAKE_OWNERSHIP, nd);
    cost->AddParameterBlock(nf);
    cost->SetNumResiduals(fit.num_rows());
    problem.AddResidualBlock(cost, nullptr, x.data());
    const long eval_budget = static_cast<long>(options.max_evaluations_per_parameter) * nf;
    budget = std::make_unique<BudgetCallback>(&fit, fit.evaluations() + eval_budget, nf + 2);
    solver_options.callbacks.push_back(budget.get());
  } else {
    problem.AddResidualBlock(new ExactCost(&fit, theta, free), nullptr, x.data());
  }
  for (int j = 0; j < nf; ++j) {
    const int i = free[j];
    double lo, hi;
    if (!layout.IsLog(i)) {
      lo = options.cao_a_lower;
      hi = options.cao_a_upper;
    } else if (paper) {
      lo = options.paper_k_lower;
      hi = options.paper_k_upper;
    } else {
      lo = -options.log_bound;
      hi = options.log_bound;
    }
    x[j] = std::clamp(x[j], lo, hi);
    problem.SetParameterLowerBound(x.data(), j, lo);
    problem.SetParameterUpperBound(x.data(), j, hi);
  }
  const long evals_before = fit.evaluations();
  ceres::Solver::Summary summary;
  if (nf > 0) ceres::Solve(solver_options, &problem, &summary);

  for (int j = 0; j < nf; ++j) {
    theta[free[j]] = (paper && layout.IsLog(free[j])) ? std::log(x[j]) : x[j];
  }
  fit.Evaluate(theta.data(), residuals.data(), nullptr);
  CalibrationSummary& s = result.summary;
  s.final_cost = fit.DataCost(residuals);
  s.iterations = nf > 0 ? static_cast<int>(summary.iterations.size()) - 1 : 0;
  s.evaluations = static_cast<int>(fit.evaluations() - evals_before - 1);
  s.termination = nf > 0 ? ceres::TerminationTypeToString(summary.termination_type)
                         : "NO_FREE_PARAMETERS";
  s.message = nf > 0 ? summary.message : "nothing to fit";
  bool finite = std::isfinite(s.final_cost);
  for (double t : theta) finite = finite && std::isfinite(t);
  s.usable = finite && (nf == 0 || summary.IsSolutionUsable()) &&
             s.final_cost <= s.initial_cost * (1 + 1e-12);
  if (!finite) s.message = "non-finite parameters or cost";

  // Reported gauge: every non-position group has geometric mean 1 over its
  // levels with data; kF carries the scale. theta_rep = T * theta.
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
  Eigen::Map<const Eigen::VectorXd> theta_vec(theta.data(), layout.n_full);
  const Eigen::VectorXd theta_rep = transform * theta_vec;
  // The fit's evaluations (also those of the covariance below) overwrite
  // the fit's model, so the reported model is a separate copy.
  WearModel model = fit.model();
  for (int i = 0; i < layout.n_coef; ++i) model.k[i] = std::exp(theta_rep[i]);
  if (layout.a_index >= 0) model.cao_exponent = theta_rep[n_rep - 1];

  result.identified.assign(n_rep, true);
  for (int i = 0; i < layout.n_coef; ++i) result.identified[i] = load[i] > 0;
  result.std_error.assign(n_rep, std::numeric_limits<double>::quiet_NaN());
  if (options.compute_covariance && nf > 0 && s.usable) {
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::DENSE_SVD;
    co.null_space_rank = -1;
    co.min_reciprocal_condition_number = 1e-12;
    ceres::Covariance covariance(co);
    std::vector<std::pair<const double*, const double*>> blocks = {{x.data(), x.data()}};
    Eigen::MatrixXd cx(nf, nf);
    if (covariance.Compute(blocks, &problem) &&
        covariance.GetCovarianceBlock(x.data(), x.data(), cx.data())) {
      // Ceres returns row-major; the block is symmetric so layout is moot.
      double rss = 0;
      for (double r : residuals) rss += r * r;
      const double s2 = rss / std::max(1, fit.num_rows() - nf);
      Eigen::MatrixXd a = Eigen::MatrixXd::Zero(layout.n_full, nf);
      for (int j = 0; j < nf; ++j) {
        // Paper mode works in k; d(log k) = dk / k.
        a(free[j], j) = (paper && layout.IsLog(free[j])) ? 1.0 / x[j] : 1.0;
      }
      const Eigen::MatrixXd ta = transform * a;
      model.covariance = s2 * ta * cx * ta.transpose();
      for (int i = 0; i < n_rep; ++i) {
        if (result.identified[i]) result.std_error[i] = std::sqrt(model.covariance(i, i));
      }
    }
  }
  // Noise model on training residuals.
  std::vector<double> pred, err;
  for (int o : train) {
    const Observation& obs = stats.observations[o];
    pred.push_back(PredictObservation(model, stats, obs));
    err.push_back(obs.measured_um - pred.back());
  }
  FitNoiseModel(pred, err, &model);
  result.model = std::move(model);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time)
                  .count();
  return result;
}

}  // namespace rollwear
