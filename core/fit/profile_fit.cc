#include "core/fit/profile_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "core/dataset/pass_input.h"
#include "core/model/model_eval.h"
#include "core/model/predictor.h"

namespace rollwear {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

enum class PointZone { kEdge, kBody, kOutside };

// One grinder point with the six basis sums of its roll at its x.
struct PointRow {
  double measured_um = 0;
  std::array<double, kProfileBasis> sums{};
  PointZone zone = PointZone::kBody;
  int roll = 0;  // index of its profile among the rows' profiles
};

// The points of the profiles of `campaigns`, with their sums under `model`.
struct ProfileRows {
  std::vector<PointRow> rows;
  int n_profiles = 0;
};

// The roll's campaign as its profile sees it: the basis sums of every pass,
// and the band the strips covered.
struct RollSums {
  ProfileStats stats;
  double band_lo = std::numeric_limits<double>::infinity();
  double band_hi = -std::numeric_limits<double>::infinity();
};

RollSums SumRoll(const WearModel& model, const Dataset& data,
                 const DatasetIndex& index, int campaign, int slot,
                 const ProfileFitOptions& options) {
  RollSums roll{ProfileStats(options.grid)};
  const int mi = index.MountOf(campaign, slot);
  const Mount& mount = data.mounts[mi];
  const bool top = mount.position == Position::kTop;
  RollWearState state = MountedRollState(model, data, campaign, mi);
  for (int pi : index.PassesOf(campaign, mount.stand)) {
    const Pass& pass = data.passes[pi];
    const double wear = AddPass(model, PassInputOf(data, pass), &state);
    const double c = StripCentreMm(top, pass.shift_mm);
    const double b = pass.width_mm / 2;
    roll.stats.AddPass(wear, c, b);
    roll.band_lo = std::min(roll.band_lo, c - b);
    roll.band_hi = std::max(roll.band_hi, c + b);
  }
  return roll;
}

// The zone of a point at x on `roll` (see the header).
PointZone ZoneOf(const RollSums& roll, double x_mm, double edge_zone_mm) {
  const double to_end =
      std::min(std::abs(x_mm - roll.band_lo), std::abs(x_mm - roll.band_hi));
  if (to_end <= edge_zone_mm) return PointZone::kEdge;
  if (x_mm > roll.band_lo && x_mm < roll.band_hi) return PointZone::kBody;
  return PointZone::kOutside;
}

ProfileRows RowsOf(const WearModel& model, const Dataset& data,
                   const DatasetIndex& index,
                   const std::map<std::pair<int, int>, std::vector<int>>& rolls,
                   const std::vector<int>& campaigns,
                   const ProfileFitOptions& options) {
  ProfileRows out;
  for (const auto& [key, points] : rolls) {
    const auto [campaign, slot] = key;
    if (!std::binary_search(campaigns.begin(), campaigns.end(), campaign)) {
      continue;
    }
    if (index.MountOf(campaign, slot) < 0) continue;  // checked on input
    const RollSums roll = SumRoll(model, data, index, campaign, slot, options);
    ++out.n_profiles;
    for (int i : points) {
      const ProfilePoint& p = data.profile_points[i];
      PointRow row;
      row.measured_um = p.wear_um;
      row.sums = roll.stats.At(p.x_mm);
      row.zone = ZoneOf(roll, p.x_mm, options.edge_zone_mm);
      row.roll = out.n_profiles - 1;
      out.rows.push_back(row);
    }
  }
  return out;
}

double Predict(const ProfileShape& shape, const PointRow& row) {
  const auto coef = shape.Coefficients();
  double w = 0;
  for (int i = 0; i < kProfileBasis; ++i) w += coef[i] * row.sums[i];
  return w;
}

ProfileGap GapOf(const ProfileShape& shape, const ProfileRows& rows) {
  ProfileGap gap;
  gap.n_profiles = rows.n_profiles;
  double all = 0, edge = 0, body = 0;
  for (const PointRow& row : rows.rows) {
    const double e = std::abs(row.measured_um - Predict(shape, row));
    all += e;
    if (row.zone == PointZone::kEdge) {
      edge += e;
      ++gap.n_edge;
    } else if (row.zone == PointZone::kBody) {
      body += e;
      ++gap.n_body;
    }
  }
  gap.n_points = static_cast<int>(rows.rows.size());
  gap.gap_um = gap.n_points > 0 ? all / gap.n_points : kNaN;
  gap.edge_um = gap.n_edge > 0 ? edge / gap.n_edge : kNaN;
  gap.body_um = gap.n_body > 0 ? body / gap.n_body : kNaN;
  return gap;
}

// The roll-clustered (sandwich) covariance of the least-squares shape
//   cov = B M B,  B = (S'S)^-1,  M = G/(G-1) sum_r (S_r' e_r)(S_r' e_r)'
// over the G rolls r (Liang & Zeger, 1986, Biometrika 73(1):13-22): the
// points of one roll share its scatter, so they are not counted as
// independent evidence (sigma^2 (S'S)^-1 would be).
Eigen::MatrixXd ClusteredCovariance(const Eigen::MatrixXd& s,
                                    const Eigen::VectorXd& e,
                                    const ProfileRows& rows) {
  const int k = static_cast<int>(s.cols());
  Eigen::MatrixXd score = Eigen::MatrixXd::Zero(k, rows.n_profiles);
  for (int r = 0; r < static_cast<int>(rows.rows.size()); ++r) {
    score.col(rows.rows[r].roll) += s.row(r).transpose() * e(r);
  }
  const double g = std::max(2.0, static_cast<double>(rows.n_profiles));
  const Eigen::MatrixXd meat = score * score.transpose() * (g / (g - 1));
  const Eigen::MatrixXd bread =
      (s.transpose() * s).ldlt().solve(Eigen::MatrixXd::Identity(k, k));
  return bread * meat * bread;
}

// The residual sd within rolls: sqrt(sum_r sum (e - mean_r e)^2 / (n - G)),
// the one-way ANOVA's within-cluster mean square (the point-to-point part,
// without the roll's shared scatter).
double WithinRollSd(const Eigen::VectorXd& e, const ProfileRows& rows) {
  std::vector<double> sum(rows.n_profiles, 0.0);
  std::vector<int> count(rows.n_profiles, 0);
  for (int r = 0; r < static_cast<int>(rows.rows.size()); ++r) {
    sum[rows.rows[r].roll] += e(r);
    ++count[rows.rows[r].roll];
  }
  double ss = 0;
  for (int r = 0; r < static_cast<int>(rows.rows.size()); ++r) {
    const int g = rows.rows[r].roll;
    ss += std::pow(e(r) - sum[g] / count[g], 2);
  }
  const double dof = static_cast<double>(rows.rows.size()) - rows.n_profiles;
  return dof > 0 ? std::sqrt(ss / dof) : kNaN;
}

// Least squares of y - s_0 on s_1..s_5 over `rows` into `fit`.
Status SolveShape(const ProfileRows& rows, ProfileFit* fit) {
  constexpr int kP = kProfileShapeParameters;
  const int n = static_cast<int>(rows.rows.size());
  if (n < 2 * kP) {
    return Status::FailedPrecondition(
        "profile fit: " + std::to_string(n) +
        " profile points in the training campaigns, at least " +
        std::to_string(2 * kP) + " needed");
  }
  Eigen::MatrixXd s(n, kP);
  Eigen::VectorXd y(n);
  for (int r = 0; r < n; ++r) {
    const PointRow& row = rows.rows[r];
    y(r) = row.measured_um - row.sums[0];
    for (int i = 0; i < kP; ++i) s(r, i) = row.sums[1 + i];
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(s);
  if (qr.rank() < kP) {
    return Status::FailedPrecondition(
        "profile fit: the training profiles do not identify the shape (rank " +
        std::to_string(qr.rank()) + " of " + std::to_string(kP) +
        "): too few distinct strip widths or points near the strip edges");
  }
  const Eigen::VectorXd theta = qr.solve(y);
  const Eigen::VectorXd e = y - s * theta;
  const double sigma2 = e.squaredNorm() / (n - kP);
  const Eigen::MatrixXd cov = ClusteredCovariance(s, e, rows);
  fit->shape.beta2 = theta(0);
  fit->shape.beta4 = theta(1);
  for (int m = 0; m < kEdgeRamps; ++m) fit->shape.alpha[m] = theta(2 + m);
  for (int i = 0; i < kP; ++i) {
    fit->std_error[i] = std::sqrt(cov(i, i));
    for (int j = 0; j < kP; ++j) fit->covariance[i][j] = cov(i, j);
  }
  fit->within_roll_sd_um = WithinRollSd(e, rows);
  fit->residual_sd_um = std::sqrt(sigma2);
  return Status::Ok();
}

}  // namespace

std::map<std::pair<int, int>, std::vector<int>> ProfilePointsByRoll(
    const Dataset& data) {
  std::map<std::pair<int, int>, std::vector<int>> out;
  for (size_t i = 0; i < data.profile_points.size(); ++i) {
    const ProfilePoint& p = data.profile_points[i];
    out[{p.campaign, RollPositionSlot(p.stand, p.position)}].push_back(
        static_cast<int>(i));
  }
  return out;
}

StatusOr<ProfileFit> FitProfileShape(const WearModel& model,
                                     const Dataset& data,
                                     const DatasetIndex& index,
                                     const CampaignSplit& split,
                                     const ProfileFitOptions& options) {
  const auto rolls = ProfilePointsByRoll(data);
  std::vector<int> train = split.train, val = split.validation;
  std::sort(train.begin(), train.end());
  std::sort(val.begin(), val.end());
  const ProfileRows train_rows =
      RowsOf(model, data, index, rolls, train, options);
  ProfileFit fit;
  ROLLWEAR_RETURN_IF_ERROR(SolveShape(train_rows, &fit));
  fit.train = GapOf(fit.shape, train_rows);
  fit.validation =
      GapOf(fit.shape, RowsOf(model, data, index, rolls, val, options));
  return fit;
}

ProfileGap ProfileGapOf(const WearModel& model, const ProfileShape& shape,
                        const Dataset& data, const DatasetIndex& index,
                        const std::vector<int>& campaigns,
                        const ProfileFitOptions& options) {
  return GapOf(shape, RowsOf(model, data, index, ProfilePointsByRoll(data),
                             campaigns, options));
}

std::vector<double> PredictRollProfile(const WearModel& model,
                                       const ProfileShape& shape,
                                       const Dataset& data,
                                       const DatasetIndex& index, int campaign,
                                       int slot,
                                       const ProfileFitOptions& options) {
  if (index.MountOf(campaign, slot) < 0) return {};
  return SumRoll(model, data, index, campaign, slot, options)
      .stats.Evaluate(shape);
}

std::vector<ProfileResidual> ProfileResiduals(
    const WearModel& model, const ProfileShape& shape, const Dataset& data,
    const DatasetIndex& index, const std::vector<int>& campaigns,
    const ProfileFitOptions& options) {
  std::vector<ProfileResidual> out;
  for (const auto& [key, points] : ProfilePointsByRoll(data)) {
    const auto [campaign, slot] = key;
    if (!std::binary_search(campaigns.begin(), campaigns.end(), campaign) ||
        index.MountOf(campaign, slot) < 0) {
      continue;
    }
    const RollSums roll = SumRoll(model, data, index, campaign, slot, options);
    const std::vector<double> profile = roll.stats.Evaluate(shape);
    for (int i : points) {
      const ProfilePoint& p = data.profile_points[i];
      const PointZone zone = ZoneOf(roll, p.x_mm, options.edge_zone_mm);
      out.push_back({campaign, slot, p.x_mm, p.wear_um,
                     options.grid.Interpolate(profile, p.x_mm),
                     zone == PointZone::kEdge, zone == PointZone::kBody});
    }
  }
  return out;
}

}  // namespace rollwear
