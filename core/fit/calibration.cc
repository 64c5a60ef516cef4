// Calibration of K by Levenberg-Marquardt; see calibration.h for the cost,
// the parameterisation, the gauge and the option-2 prior. This file holds
// the least-squares problem (Fit), its Ceres side (solver set-up, solve,
// covariance) and Calibrate(), which runs the stages in order; the stages
// without Ceres are in calibration_stages.cc (calibration_internal.h).
#include "core/fit/calibration.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include <ceres/ceres.h>

#include "core/fit/calibration_internal.h"
#include "core/fit/lm_setup.h"
#include "core/fit/robust.h"

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

namespace calibration_internal {

Fit::Fit(const WearStatistics& stats, const std::vector<int>& train,
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
    eq9_weight_.push_back(
        1.0 / std::sqrt(n_per_position[stats.observations[o].position]));
  }
  robust_sqrt_.assign(train.size(), 1.0);
  weight_ = eq9_weight_;
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
  // Grade shrinkage: a prior row per grade with training load.
  if (options.shrink_grades && options.option == 1 &&
      options.derivatives == DerivativeMode::kExact) {
    for (const FactorGroup& g : ks.groups()) {
      if (g.key != FactorKey::kGrade) continue;
      for (int c = g.offset; c < g.offset + g.size; ++c) {
        if (coef_load_[c] > 0) shrunk_grades_.push_back(c);
      }
    }
    if (static_cast<int>(shrunk_grades_.size()) < kMinShrunkGrades) {
      shrunk_grades_.clear();
    }
    num_rows_ += static_cast<int>(shrunk_grades_.size());
  }
}

void Fit::Evaluate(const double* theta, double* residuals, double* jac) {
  ++evaluations_;
  for (int i = 0; i < layout_.n_coef; ++i) model_.k[i] = std::exp(theta[i]);
  if (layout_.a_index >= 0) model_.cao_exponent = theta[layout_.a_index];
  const int n = layout_.n_full;
  const int np = model_.num_parameters();
  grad_.assign(np, 0.0);
  if (jac != nullptr)
    std::fill(jac, jac + static_cast<size_t>(num_rows_) * n, 0.0);
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
  int row = static_cast<int>(train_.size());
  // Grade shrinkage rows: (sigma / tau) * log kS[s].
  for (int c : shrunk_grades_) {
    residuals[row] = grade_scale_ * theta[c];
    if (jac != nullptr) jac[static_cast<size_t>(row) * n + c] = grade_scale_;
    ++row;
  }
  if (options_.option != 2) return;
  // Prior rows: lambda * (log kRS[r,s] - u_r - v_s).
  const int rs_offset = model_.structure.groups()[1].offset;
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

double Fit::DataCost(const std::vector<double>& residuals) const {
  double c = 0;
  for (size_t i = 0; i < train_.size(); ++i) {
    const double r = residuals[i] / robust_sqrt_[i];
    c += r * r;
  }
  return c;
}

void Fit::SetRobustWeights(const std::vector<double>& w) {
  for (size_t i = 0; i < train_.size(); ++i) {
    robust_sqrt_[i] = std::sqrt(w[i]);
    weight_[i] = eq9_weight_[i] * robust_sqrt_[i];
  }
}

void Fit::DataErrors(const std::vector<double>& residuals,
                     std::vector<double>* pred,
                     std::vector<double>* err) const {
  pred->resize(train_.size());
  err->resize(train_.size());
  for (size_t i = 0; i < train_.size(); ++i) {
    (*err)[i] = residuals[i] / weight_[i];
    (*pred)[i] = stats_.observations[train_[i]].measured_um - (*err)[i];
  }
}

namespace {

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

// The Ceres problem over the free entries x of theta (k rather than log k in
// paper mode). Built in place: the problem holds pointers to x and budget.
struct SolverSetup {
  bool paper = false;
  std::vector<double> x;
  ceres::Problem problem;
  ceres::Solver::Options options;
  std::unique_ptr<BudgetCallback> budget;
};

// The bounds of layout parameter i in the solver's space.
void BoundsOf(const Layout& layout, int i, const CalibrationOptions& options,
              bool paper, double* lo, double* hi) {
  if (!layout.IsLog(i)) {
    *lo = options.cao_a_lower;
    *hi = options.cao_a_upper;
  } else if (paper) {
    *lo = options.paper_k_lower;
    *hi = options.paper_k_upper;
  } else {
    *lo = -options.log_bound;
    *hi = options.log_bound;
  }
}

// Per reported parameter (n_rep): whether the solver's value of its free
// layout parameter sits within 1e-6 (relative) of a bound. Coefficient i of
// the layout is coefficient i of the reported model (GaugeTransform); Cao's
// a is the last.
std::vector<bool> AtBound(const Layout& layout, const std::vector<int>& free,
                          const SolverSetup& setup,
                          const CalibrationOptions& options, int n_rep) {
  std::vector<bool> at(n_rep, false);
  for (size_t j = 0; j < free.size() && j < setup.x.size(); ++j) {
    const int i = free[j];
    double lo, hi;
    BoundsOf(layout, i, options, setup.paper, &lo, &hi);
    const double tol = 1e-6 * std::max({1.0, std::abs(lo), std::abs(hi)});
    if (!(setup.x[j] <= lo + tol || setup.x[j] >= hi - tol)) continue;
    if (!layout.IsLog(i)) {
      at[n_rep - 1] = true;  // Cao's a
    } else if (i < layout.n_coef) {
      at[i] = true;  // option 2's prior surface (u, v) is not reported
    }
  }
  return at;
}

// Stage 5. The residual block (analytic Jacobian, or forward differences
// within the evaluation budget in paper mode) and the bounds; x starts at
// theta, clamped into its bounds.
void SetUpSolver(Fit* fit, const std::vector<double>& theta,
                 const std::vector<int>& free,
                 const CalibrationOptions& options, SolverSetup* s) {
  const Layout& layout = fit->layout();
  const int nf = static_cast<int>(free.size());
  s->paper = options.derivatives == DerivativeMode::kPaperForwardDifference;
  const bool paper = s->paper;
  s->x.resize(nf);
  std::vector<double>& x = s->x;
  for (int j = 0; j < nf; ++j) {
    x[j] = (paper && layout.IsLog(free[j])) ? std::exp(theta[free[j]]) : theta[free[j]];
  }
  s->options = MakeLmSolverOptions(options.lm);
  if (paper) {
    auto* functor = new PaperResiduals{fit, free, theta};
    ceres::NumericDiffOptions nd;
    nd.relative_step_size = options.fd_relative_step;
    auto* cost = new ceres::DynamicNumericDiffCostFunction<PaperResiduals, ceres::FORWARD>(
        functor, ceres::TAKE_OWNERSHIP, nd);
    cost->AddParameterBlock(nf);
    cost->SetNumResiduals(fit->num_rows());
    s->problem.AddResidualBlock(cost, nullptr, x.data());
    const long eval_budget = static_cast<long>(options.max_evaluations_per_parameter) * nf;
    s->budget = std::make_unique<BudgetCallback>(
        fit, fit->evaluations() + eval_budget, nf + 2);
    s->options.callbacks.push_back(s->budget.get());
  } else {
    s->problem.AddResidualBlock(new ExactCost(fit, theta, free), nullptr,
                                x.data());
  }
  for (int j = 0; j < nf; ++j) {
    double lo, hi;
    BoundsOf(layout, free[j], options, paper, &lo, &hi);
    x[j] = std::clamp(x[j], lo, hi);
    s->problem.SetParameterLowerBound(x.data(), j, lo);
    s->problem.SetParameterUpperBound(x.data(), j, hi);
  }
}

// Stage 6. Solves, writes the solution back into theta and the fit's
// residuals at it, and fills the summary (all but the initial cost, the
// counts and the time).
void Solve(Fit* fit, const std::vector<int>& free, SolverSetup* setup,
           std::vector<double>* theta, std::vector<double>* residuals,
           CalibrationSummary* s) {
  const int nf = static_cast<int>(free.size());
  const std::vector<double>& x = setup->x;
  const long evals_before = fit->evaluations();
  ceres::Solver::Summary summary;
  if (nf > 0) ceres::Solve(setup->options, &setup->problem, &summary);

  for (int j = 0; j < nf; ++j) {
    (*theta)[free[j]] =
        (setup->paper && fit->layout().IsLog(free[j])) ? std::log(x[j]) : x[j];
  }
  fit->Evaluate(theta->data(), residuals->data(), nullptr);
  s->final_cost = fit->DataCost(*residuals);
  s->iterations += nf > 0 ? static_cast<int>(summary.iterations.size()) - 1 : 0;
  s->evaluations += static_cast<int>(fit->evaluations() - evals_before - 1);
  s->termination =
      nf > 0 ? ceres::TerminationTypeToString(summary.termination_type)
             : "NO_FREE_PARAMETERS";
  s->message = nf > 0 ? summary.message : "nothing to fit";
  bool finite = std::isfinite(s->final_cost);
  for (double t : *theta) finite = finite && std::isfinite(t);
  s->usable = finite && (nf == 0 || summary.IsSolutionUsable()) &&
              s->final_cost <= s->initial_cost * (1 + 1e-12);
  if (!finite) s->message = "non-finite parameters or cost";
}

// Stage 8. Ceres covariance (dense SVD, pseudo-inverse) of the free
// parameters, scaled by s^2 = sum r^2 / (m - n) (r and m include the grade
// shrinkage's prior rows: s^2 is sigma^2 at its fixed point) and mapped to the reported
// gauge; sets model->covariance and the standard errors of the identified
// parameters. Leaves both untouched when Ceres cannot compute it.
void EstimateCovariance(const Fit& fit, const std::vector<int>& free,
                        SolverSetup* setup,
                        const std::vector<double>& residuals,
                        const Eigen::MatrixXd& transform, WearModel* model,
                        CalibrationResult* result) {
  const Layout& layout = fit.layout();
  const int nf = static_cast<int>(free.size());
  const std::vector<double>& x = setup->x;
  ceres::Covariance::Options co;
  co.algorithm_type = ceres::DENSE_SVD;
  co.null_space_rank = -1;
  co.min_reciprocal_condition_number = 1e-12;
  ceres::Covariance covariance(co);
  std::vector<std::pair<const double*, const double*>> blocks = {
      {x.data(), x.data()}};
  Eigen::MatrixXd cx(nf, nf);
  if (!covariance.Compute(blocks, &setup->problem) ||
      !covariance.GetCovarianceBlock(x.data(), x.data(), cx.data())) {
    return;
  }
  // Ceres returns row-major; the block is symmetric so layout is moot.
  double rss = 0;
  for (double r : residuals) rss += r * r;
  const double s2 = rss / std::max(1, fit.num_rows() - nf);
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(layout.n_full, nf);
  for (int j = 0; j < nf; ++j) {
    // Paper mode works in k; d(log k) = dk / k.
    a(free[j], j) = (setup->paper && layout.IsLog(free[j])) ? 1.0 / x[j] : 1.0;
  }
  const Eigen::MatrixXd ta = transform * a;
  model->covariance = s2 * ta * cx * ta.transpose();
  for (int i = 0; i < static_cast<int>(transform.rows()); ++i) {
    if (result->identified[i]) {
      result->std_error[i] = std::sqrt(model->covariance(i, i));
    }
  }
}

// The robust loss (calibration.h): IRLS steps with Huber weights from the
// robust noise model of the current training residuals, each re-solved from
// the previous optimum; the last step's problem is left in *solver for the
// covariance. Returns the final weights (empty when a step fails, leaving
// the least-squares solution).
std::vector<double> RobustSteps(Fit* fit, const std::vector<int>& free,
                                const CalibrationOptions& options,
                                std::unique_ptr<SolverSetup>* solver,
                                std::vector<double>* theta,
                                std::vector<double>* residuals,
                                CalibrationSummary* s) {
  constexpr int kIrlsSteps = 2;  // the LS fit's scale, iterated once
  std::vector<double> pred, err, weight;
  // What a failed step returns to: the least-squares solution, its
  // problem (for the covariance) and its summary.
  const std::vector<double> ls_theta = *theta;
  const CalibrationSummary ls_summary = *s;
  std::unique_ptr<SolverSetup> ls_solver;
  for (int step = 0; step < kIrlsSteps; ++step) {
    fit->DataErrors(*residuals, &pred, &err);
    weight = FitRobustNoise(pred, err).weight;
    fit->SetRobustWeights(weight);
    auto next = std::make_unique<SolverSetup>();
    SetUpSolver(fit, *theta, free, options, next.get());
    CalibrationSummary step_summary = *s;
    Solve(fit, free, next.get(), theta, residuals, &step_summary);
    if (!step_summary.usable) {  // keep least squares
      fit->SetRobustWeights(std::vector<double>(weight.size(), 1.0));
      *theta = ls_theta;
      fit->Evaluate(theta->data(), residuals->data(), nullptr);
      if (ls_solver) *solver = std::move(ls_solver);
      *s = ls_summary;
      return {};
    }
    *s = step_summary;
    if (!ls_solver) ls_solver = std::move(*solver);
    *solver = std::move(next);
  }
  fit->DataErrors(*residuals, &pred, &err);
  return FitRobustNoise(pred, err).weight;
}

// Stage 6b. The grade shrinkage (calibration.h): evidence updates of sigma
// and tau, each followed by a solve from the previous optimum, until tau
// moves under 1 %; the last solve's problem is left in *solver.
GradeShrinkage ShrinkGrades(Fit* fit, const std::vector<int>& free,
                            const CalibrationOptions& options,
                            std::unique_ptr<SolverSetup>* solver,
                            std::vector<double>* theta,
                            std::vector<double>* residuals,
                            CalibrationSummary* s) {
  GradeShrinkage g;
  g.levels = static_cast<int>(fit->shrunk_grades().size());
  double tau = 0;
  for (int round = 0; round < kMaxShrinkageRounds && s->usable; ++round) {
    const EvidenceUpdate up = UpdateGradeEvidence(fit, free, *theta);
    if (!up.ok) break;  // keeps the last solve and its figures
    g.applied = true;
    ++g.rounds;
    g.sigma = up.sigma;
    g.effective_parameters = up.gamma;
    g.converged = tau > 0 && std::abs(std::log(up.tau / tau)) < 0.01;
    tau = g.tau = up.tau;
    if (g.converged) break;
    // The next solve from this optimum; a failed one leaves this round's
    // solution, problem and summary in place.
    const double previous_scale = fit->grade_scale();
    const std::vector<double> previous_theta = *theta;
    const CalibrationSummary previous_summary = *s;
    fit->set_grade_scale(up.sigma / up.tau);
    auto next = std::make_unique<SolverSetup>();
    SetUpSolver(fit, *theta, free, options, next.get());
    Solve(fit, free, next.get(), theta, residuals, s);
    if (!s->usable) {
      fit->set_grade_scale(previous_scale);
      *theta = previous_theta;
      fit->Evaluate(theta->data(), residuals->data(), nullptr);
      *s = previous_summary;
      break;
    }
    *solver = std::move(next);
  }
  return g;
}

}  // namespace
}  // namespace calibration_internal

StatusOr<CalibrationResult> Calibrate(const WearStatistics& stats,
                                      const std::vector<int>& train,
                                      const CalibrationOptions& options) {
  namespace ci = calibration_internal;
  const auto start_time = std::chrono::steady_clock::now();
  ROLLWEAR_RETURN_IF_ERROR(ci::ValidateInputs(stats, train, options));
  ROLLWEAR_ASSIGN_OR_RETURN(
      KStructure ks, KStructure::ForOption(options.option, stats.positions,
                                           stats.roll_types, stats.grades));
  ci::Fit fit(stats, train, options, std::move(ks));
  std::optional<CalibrationResult> prefit;
  if (options.option == 2) {
    ROLLWEAR_ASSIGN_OR_RETURN(prefit,
                              ci::Option2Prefit(stats, train, options, &fit));
  }
  std::vector<double> theta =
      ci::InitialTheta(stats, train, options, fit, prefit ? &*prefit : nullptr);
  const std::vector<int> free = ci::FreeParameters(fit, options);
  const int nf = static_cast<int>(free.size());

  std::vector<double> residuals(fit.num_rows());
  fit.Evaluate(theta.data(), residuals.data(), nullptr);
  CalibrationResult result;
  CalibrationSummary& s = result.summary;
  s.initial_cost = fit.DataCost(residuals);
  s.num_free_parameters = nf;
  s.num_observations = static_cast<int>(train.size());
  const bool shrink = !fit.shrunk_grades().empty() && nf > 0;
  if (shrink) {  // a weak start: tau = 3 on log kS, sigma of the start
    constexpr double kStartTau = 3;
    fit.set_grade_scale(std::sqrt(s.initial_cost / fit.num_data_rows()) /
                        kStartTau);
  }

  auto solver = std::make_unique<ci::SolverSetup>();
  ci::SetUpSolver(&fit, theta, free, options, solver.get());
  ci::Solve(&fit, free, solver.get(), &theta, &residuals, &s);
  if (shrink && s.usable) {
    result.grade_shrinkage = ci::ShrinkGrades(&fit, free, options, &solver,
                                              &theta, &residuals, &s);
  }
  if (options.robust && s.usable && nf > 0 &&
      options.derivatives == DerivativeMode::kExact) {
    result.robust_weight =
        ci::RobustSteps(&fit, free, options, &solver, &theta, &residuals, &s);
  }

  const Eigen::MatrixXd transform = ci::GaugeTransform(fit);
  WearModel model = ci::ReportedModel(fit, transform, theta);
  const int n_rep = model.num_parameters();
  result.at_bound = ci::AtBound(fit.layout(), free, *solver, options, n_rep);
  const std::vector<double>& load = fit.coef_load();
  result.identified.assign(n_rep, true);
  for (int i = 0; i < fit.layout().n_coef; ++i)
    result.identified[i] = load[i] > 0;
  result.std_error.assign(n_rep, std::numeric_limits<double>::quiet_NaN());
  if (options.compute_covariance && nf > 0 && s.usable) {
    ci::EstimateCovariance(fit, free, solver.get(), residuals, transform,
                           &model, &result);
  }
  ci::FitTrainingNoise(stats, train, options.robust, &model);
  result.model = std::move(model);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time)
                  .count();
  return result;
}

}  // namespace rollwear
