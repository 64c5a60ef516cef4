// The joint Levenberg-Marquardt fit of K and the profile shape
// (profile_joint.h): sufficient statistics per roll and grade, the
// weighting, the Ceres problem with exact derivatives, the standard errors.
#include "core/fit/profile_joint.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <ceres/ceres.h>

#include "core/base/intraclass.h"
#include "core/dataset/pass_input.h"
#include "core/fit/lm_setup.h"
#include "core/model/model_eval.h"
#include "core/model/predictor.h"

namespace rollwear {
namespace {

constexpr int kShape = kProfileShapeParameters;
using Sums = std::array<double, kProfileBasis>;

// One roll (campaign, slot) of the training campaigns: its K cells (one per
// grade of its campaign) with their centre sums C_s, and its centre
// reading when it has one.
struct JointRoll {
  std::vector<std::vector<int>> cell_coefficients;  // per grade: k indices
  std::vector<double> centre;                       // C_s per grade
  bool has_reading = false;
  double reading_um = 0;
  double offset_um = 0;  // measurement terms, fixed
  double weight = 0;     // 1 / sd_c^2
};

// A grinder point: the roll it belongs to and S_{s,i}(x) per grade.
struct JointPoint {
  int roll = 0;
  double measured_um = 0;
  double weight = 0;
  std::vector<Sums> sums;
};

struct JointData {
  std::vector<JointRoll> rolls;
  std::vector<JointPoint> points;
  int num_k = 0;
};

// The sufficient statistics of the training rolls (profile_joint.h).
JointData Collect(const WearModel& model, const Dataset& data,
                  const DatasetIndex& index, const std::vector<int>& train,
                  const ProfileFitOptions& options) {
  const std::map<std::pair<int, int>, std::vector<int>> points =
      ProfilePointsByRoll(data);
  std::map<std::pair<int, int>, MeasuredPrediction> readings;
  for (const MeasuredPrediction& m : PredictMeasured(model, data, index, train)) {
    readings[{m.campaign, m.slot}] = m;
  }
  JointData out;
  out.num_k = model.structure.num_coefficients();
  const int groups = static_cast<int>(model.structure.groups().size());
  for (int c : train) {
    for (int slot : index.slots()) {
      const int mi = index.MountOf(c, slot);
      const auto pts = points.find({c, slot});
      const auto reading = readings.find({c, slot});
      if (mi < 0 || (pts == points.end() && reading == readings.end())) {
        continue;
      }
      const Mount& mount = data.mounts[mi];
      JointRoll roll;
      std::map<int, int> cell_of_grade;
      std::vector<ProfileStats> stats;
      RollWearState state = MountedRollState(model, data, c, mi);
      for (int pi : index.PassesOf(c, mount.stand)) {
        const Pass& pass = data.passes[pi];
        const PassInput in = PassInputOf(data, pass);
        const int s = model.structure.GradeLevel(in.grade);
        const double wear = AddPass(model, in, &state);
        // Load_p m_p: the pass's wear without its K.
        const double load = wear / model.K(state.position, state.roll_type, s);
        auto [it, fresh] = cell_of_grade.emplace(s, roll.centre.size());
        if (fresh) {
          std::vector<int> coefficients;
          for (int g = 0; g < groups; ++g) {
            const int j = model.structure.CoefficientOf(g, state.position,
                                                        state.roll_type, s);
            if (j >= 0) coefficients.push_back(j);
          }
          roll.cell_coefficients.push_back(std::move(coefficients));
          roll.centre.push_back(0);
          stats.emplace_back(options.grid);
        }
        roll.centre[it->second] += load;
        stats[it->second].AddPass(
            load, StripCentreMm(mount.position == Position::kTop, pass.shift_mm),
            pass.width_mm / 2);
      }
      if (reading != readings.end()) {
        const MeasuredPrediction& m = reading->second;
        const double sd2 = model.noise_sd_um * model.noise_sd_um +
                           std::pow(model.noise_rel * m.wear_um, 2);
        roll.has_reading = sd2 > 0;
        roll.reading_um = m.measured_um;
        roll.offset_um = m.expected_um - m.wear_um;
        roll.weight = sd2 > 0 ? 1 / sd2 : 0;
      }
      const int r = static_cast<int>(out.rolls.size());
      out.rolls.push_back(std::move(roll));
      if (pts == points.end()) continue;
      for (int i : pts->second) {
        const ProfilePoint& p = data.profile_points[i];
        JointPoint point{r, p.wear_um, 0, {}};
        for (const ProfileStats& st : stats) point.sums.push_back(st.At(p.x_mm));
        out.points.push_back(std::move(point));
      }
    }
  }
  return out;
}

// Full parameters: log k (num_k), then beta2, beta4, alpha_1..3.
double CellK(const std::vector<int>& coefficients, const double* full) {
  double log_k = 0;
  for (int j : coefficients) log_k += full[j];
  return std::exp(log_k);
}

// Prediction of a point under `full`, and if `grad` (size num_k + 5),
// its derivatives.
double PredictPoint(const JointData& d, const JointPoint& p, const double* full,
                    double* grad) {
  const JointRoll& roll = d.rolls[p.roll];
  const double* theta = full + d.num_k;
  double total = 0;
  for (size_t s = 0; s < p.sums.size(); ++s) {
    const Sums& sum = p.sums[s];
    double shaped = sum[0];
    for (int i = 1; i < kProfileBasis; ++i) shaped += theta[i - 1] * sum[i];
    const double k = CellK(roll.cell_coefficients[s], full);
    total += k * shaped;
    if (grad == nullptr) continue;
    for (int j : roll.cell_coefficients[s]) grad[j] += k * shaped;
    for (int i = 1; i < kProfileBasis; ++i) grad[d.num_k + i - 1] += k * sum[i];
  }
  return total;
}

double PredictReading(const JointRoll& roll, const double* full, double* grad) {
  double total = roll.offset_um;
  for (size_t s = 0; s < roll.centre.size(); ++s) {
    const double w = CellK(roll.cell_coefficients[s], full) * roll.centre[s];
    total += w;
    if (grad == nullptr) continue;
    for (int j : roll.cell_coefficients[s]) grad[j] += w;
  }
  return total;
}

// Whitened residuals (centre readings, then points) and their Jacobian in
// the free parameters.
class JointCost : public ceres::CostFunction {
 public:
  JointCost(const JointData* data, std::vector<double> full,
            std::vector<int> free)
      : data_(data), full_(std::move(full)), free_(std::move(free)) {
    for (const JointRoll& r : data_->rolls) readings_ += r.has_reading ? 1 : 0;
    set_num_residuals(readings_ + static_cast<int>(data_->points.size()));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(free_.size()));
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    std::vector<double> full = full_;
    for (size_t j = 0; j < free_.size(); ++j) full[free_[j]] = parameters[0][j];
    std::vector<double> grad(full.size());
    const int n_free = static_cast<int>(free_.size());
    int row = 0;
    auto emit = [&](double measured, double predicted, double weight) {
      const double sw = std::sqrt(weight);
      residuals[row] = sw * (measured - predicted);
      if (jacobians != nullptr && jacobians[0] != nullptr) {
        for (int j = 0; j < n_free; ++j) {
          jacobians[0][row * n_free + j] = -sw * grad[free_[j]];
        }
      }
      ++row;
    };
    const bool want = jacobians != nullptr && jacobians[0] != nullptr;
    for (const JointRoll& r : data_->rolls) {
      if (!r.has_reading) continue;
      std::fill(grad.begin(), grad.end(), 0.0);
      const double y = PredictReading(r, full.data(), want ? grad.data() : nullptr);
      emit(r.reading_um, y, r.weight);
    }
    for (const JointPoint& p : data_->points) {
      std::fill(grad.begin(), grad.end(), 0.0);
      const double y =
          PredictPoint(*data_, p, full.data(), want ? grad.data() : nullptr);
      emit(p.measured_um, y, p.weight);
    }
    return std::all_of(residuals, residuals + row,
                       [](double v) { return std::isfinite(v); });
  }

 private:
  const JointData* data_;
  std::vector<double> full_;
  std::vector<int> free_;
  int readings_ = 0;
};

// Sets each point's weight 1 / (sigma^2 (1 + (n_r - 1) rho)) from the
// residuals under `full` (the first stage); returns rho.
double WeighPoints(const double* full, JointData* d) {
  std::vector<double> residual;
  std::vector<int> roll;
  std::map<int, double> points_of;
  for (const JointPoint& p : d->points) {
    residual.push_back(p.measured_um - PredictPoint(*d, p, full, nullptr));
    roll.push_back(p.roll);
    points_of[p.roll] += 1;
  }
  const Intraclass icc = OneWayIntraclass(residual, roll);
  for (JointPoint& p : d->points) {
    p.weight = 1 / (icc.variance * (1 + (points_of[p.roll] - 1) * icc.rho));
  }
  return icc.rho;
}

// The gauge (as term_fit.cc): coefficients without data are held, and in
// every factor group after the first the level with the most load.
std::vector<int> FreeParameters(const WearModel& model, const JointData& d,
                                std::vector<bool>* has_data) {
  std::vector<double> load(d.num_k, 0.0);
  for (const JointRoll& r : d.rolls) {
    for (size_t s = 0; s < r.centre.size(); ++s) {
      for (int j : r.cell_coefficients[s]) load[j] += r.centre[s];
    }
  }
  std::vector<bool> held(d.num_k + kShape, false);
  has_data->assign(d.num_k, false);
  for (int j = 0; j < d.num_k; ++j) {
    (*has_data)[j] = load[j] > 0;
    held[j] = !(*has_data)[j];
  }
  const auto& groups = model.structure.groups();
  for (size_t g = 1; g < groups.size(); ++g) {
    const int b = groups[g].offset, e = b + groups[g].size;
    held[std::max_element(load.begin() + b, load.begin() + e) - load.begin()] =
        true;
  }
  std::vector<int> free;
  for (int j = 0; j < d.num_k + kShape; ++j) {
    if (!held[j]) free.push_back(j);
  }
  return free;
}

std::string ParameterName(const WearModel& model, int j) {
  const int n = model.structure.num_coefficients();
  return j < n ? model.structure.CoefficientName(j) : ProfileShapeNames()[j - n];
}

// Standard errors of the shape by the cluster-robust (sandwich) covariance
// with the rolls as clusters (Liang & Zeger, 1986, Biometrika 73(1):13-22):
//   cov = B M B,  B = (J'J)^-1,  M = G/(G-1) sum_r (J_r' e_r)(J_r' e_r)'
// over the whitened residuals e and Jacobian J, G rolls. A roll's centre
// reading and its profile points form one cluster, so scatter they share is
// neither counted as independent evidence nor assumed away.
void ShapeErrors(const JointCost& cost, const JointData& d,
                 const std::vector<double>& x, const std::vector<int>& free,
                 JointProfileFit* out) {
  const int m = cost.num_residuals(), n = static_cast<int>(x.size());
  Eigen::VectorXd e(m);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> jac(m, n);
  const double* params[] = {x.data()};
  double* jacs[] = {jac.data()};
  out->profile.std_error.fill(std::nan(""));
  if (!cost.Evaluate(params, e.data(), jacs) || m <= n) return;
  // The cluster of each residual row, in JointCost's order.
  std::vector<int> cluster;
  for (size_t r = 0; r < d.rolls.size(); ++r) {
    if (d.rolls[r].has_reading) cluster.push_back(static_cast<int>(r));
  }
  for (const JointPoint& p : d.points) cluster.push_back(p.roll);
  Eigen::MatrixXd score = Eigen::MatrixXd::Zero(n, d.rolls.size());
  for (int row = 0; row < m; ++row) {
    score.col(cluster[row]) += jac.row(row).transpose() * e(row);
  }
  const double g = static_cast<double>(d.rolls.size());
  const Eigen::MatrixXd meat = score * score.transpose() * (g / (g - 1));
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(
      jac.transpose() * jac);
  const Eigen::MatrixXd bread = cod.pseudoInverse();
  const Eigen::MatrixXd cov = bread * meat * bread;
  for (auto& row : out->profile.covariance) row.fill(0.0);
  for (int j = 0; j < n; ++j) {
    if (free[j] < d.num_k) continue;
    out->profile.std_error[free[j] - d.num_k] = std::sqrt(cov(j, j));
    for (int l = 0; l < n; ++l) {
      if (free[l] >= d.num_k) {
        out->profile.covariance[free[j] - d.num_k][free[l] - d.num_k] = cov(j, l);
      }
    }
  }
}

// The reported gauge (k_structure.h): every group after the first at
// geometric mean 1 over its levels with data, the first carrying the scale.
void ReportGauge(const WearModel& model, const std::vector<bool>& has_data,
                 std::vector<double>* log_k) {
  const auto& groups = model.structure.groups();
  double shift = 0;
  for (size_t g = 1; g < groups.size(); ++g) {
    double sum = 0;
    int count = 0;
    for (int j = groups[g].offset; j < groups[g].offset + groups[g].size; ++j) {
      if (has_data[j]) {
        sum += (*log_k)[j];
        ++count;
      }
    }
    if (count == 0) continue;
    const double mean = sum / count;
    for (int j = groups[g].offset; j < groups[g].offset + groups[g].size; ++j) {
      if (has_data[j]) (*log_k)[j] -= mean;
    }
    shift += mean;
  }
  if (groups.empty()) return;
  for (int j = groups[0].offset; j < groups[0].offset + groups[0].size; ++j) {
    if (has_data[j]) (*log_k)[j] += shift;
  }
}

double CentreGap(const WearModel& model, const Dataset& data,
                 const DatasetIndex& index, const std::vector<int>& campaigns) {
  double sum = 0;
  int n = 0;
  for (const MeasuredPrediction& m : PredictMeasured(model, data, index, campaigns)) {
    sum += std::abs(m.measured_um - m.expected_um);
    ++n;
  }
  return n > 0 ? sum / n : std::nan("");
}

}  // namespace

namespace {

// Why the joint fit cannot take `model`, or nullptr: it needs a wear law,
// and it reads a pass's Load * m as its wear / K (Collect), which wear
// added per pass (a per-coil term) is not: refused rather than fitted
// wrong.
const char* Unsupported(const WearModel& model) {
  if (model.is_ann()) return "the joint profile fit needs a wear law model";
  for (const ModelTerm& t : model.terms) {
    if (t.IsAdditiveTerm()) {
      return "the joint profile fit does not take a model with wear added "
             "per pass (a per_coil term)";
    }
  }
  return nullptr;
}

}  // namespace

StatusOr<JointProfileFit> FitProfileJoint(const WearModel& centre,
                                          const Dataset& data,
                                          const DatasetIndex& index,
                                          const CampaignSplit& split,
                                          const ProfileFit& first,
                                          const ProfileFitOptions& options) {
  if (const char* why = Unsupported(centre))
    return Status::InvalidArgument(why);
  std::vector<int> train = split.train, val = split.validation;
  std::sort(train.begin(), train.end());
  std::sort(val.begin(), val.end());
  JointData d = Collect(centre, data, index, train, options);
  if (d.points.size() < 2 * kShape) {
    return Status::InvalidArgument(
        "the joint profile fit needs profile points on the training campaigns");
  }
  std::vector<double> full(d.num_k + kShape);
  for (int j = 0; j < d.num_k; ++j) full[j] = std::log(centre.k[j]);
  const auto start = ProfileShapeValues(first.shape);
  std::copy(start.begin(), start.end(), full.begin() + d.num_k);
  JointProfileFit out;
  out.intra_roll_correlation = WeighPoints(full.data(), &d);

  std::vector<bool> has_data;
  const std::vector<int> free = FreeParameters(centre, d, &has_data);
  std::vector<double> x;
  for (int j : free) x.push_back(full[j]);
  auto* cost = new JointCost(&d, full, free);
  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, x.data());
  std::vector<std::pair<double, double>> bounds(x.size());
  for (size_t j = 0; j < free.size(); ++j) {
    const int f = free[j];
    bounds[j] = f < d.num_k                ? std::make_pair(x[j] - 5, x[j] + 5)
                : f < d.num_k + 2          ? std::make_pair(-0.45, 10.0)
                                           : std::make_pair(-5.0, 50.0);
    x[j] = std::clamp(x[j], bounds[j].first, bounds[j].second);
    problem.SetParameterLowerBound(x.data(), static_cast<int>(j), bounds[j].first);
    problem.SetParameterUpperBound(x.data(), static_cast<int>(j), bounds[j].second);
  }
  LmOptions lm;
  lm.max_iterations = 100;
  lm.function_tolerance = 1e-12;
  lm.parameter_tolerance = 1e-10;
  ceres::Solver::Summary summary;
  ceres::Solve(MakeLmSolverOptions(lm), &problem, &summary);
  if (!summary.IsSolutionUsable()) {
    return Status::NumericalFailure("the joint profile fit did not converge: " +
                                    summary.message);
  }
  out.iterations = static_cast<int>(summary.iterations.size());
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  for (size_t j = 0; j < free.size(); ++j) {
    full[free[j]] = x[j];
    const double span = bounds[j].second - bounds[j].first;
    if (std::min(x[j] - bounds[j].first, bounds[j].second - x[j]) < 1e-6 * span) {
      out.at_bound.push_back(ParameterName(centre, free[j]));
    }
  }
  ShapeErrors(*cost, d, x, free, &out);

  std::vector<double> log_k(full.begin(), full.begin() + d.num_k);
  ReportGauge(centre, has_data, &log_k);
  out.model = centre;
  for (int j = 0; j < d.num_k; ++j) out.model.k[j] = std::exp(log_k[j]);
  ProfileShape& shape = out.profile.shape;
  const double* theta = full.data() + d.num_k;
  shape.beta2 = theta[0];
  shape.beta4 = theta[1];
  for (int m = 0; m < kEdgeRamps; ++m) shape.alpha[m] = theta[2 + m];
  double rss = 0, wsum = 0;
  std::map<int, std::vector<double>> by_roll;
  for (const JointPoint& p : d.points) {
    const double e = p.measured_um - PredictPoint(d, p, full.data(), nullptr);
    rss += e * e;
    wsum += 1;
    by_roll[p.roll].push_back(e);
  }
  out.profile.residual_sd_um = std::sqrt(rss / std::max(1.0, wsum - kShape));
  // Within rolls (profile_fit.h): about each roll's mean residual.
  double ss_within = 0;
  for (const auto& [roll, e] : by_roll) {
    double mean = 0;
    for (double v : e) mean += v;
    mean /= static_cast<double>(e.size());
    for (double v : e) ss_within += (v - mean) * (v - mean);
  }
  const double dof = wsum - static_cast<double>(by_roll.size());
  out.profile.within_roll_sd_um =
      dof > 0 ? std::sqrt(ss_within / dof) : std::nan("");
  out.profile.train = ProfileGapOf(out.model, shape, data, index, train, options);
  out.profile.validation = ProfileGapOf(out.model, shape, data, index, val, options);
  out.centre_gap_train_um = CentreGap(out.model, data, index, train);
  out.centre_gap_val_um = CentreGap(out.model, data, index, val);
  return out;
}

}  // namespace rollwear
