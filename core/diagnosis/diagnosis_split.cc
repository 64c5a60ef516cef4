// The proxy guard's consistency test across the levels of pass-level
// factors (docs/diagnosis.md, "The proxy guard", consistency): the grade,
// the lubrication flag and every text column of coils.csv. A reading sums
// passes of several levels, so the readings cannot be grouped by level as
// the guard groups them by stand; instead each reading's term contribution
// D and prediction P are split by the level of their passes,
//   D_i = sum_l D_il,  P_i = sum_l P_il,
// and one weighted least-squares fit over the training readings
//   e_i ~ sum_l a_l P_il + sum_l b_l D_il        (w_i = 1 / sd_i^2)
// gives the scale b_l of the effect's shape on level l's passes (the a_l
// take up what a change of the level's K would). A term that holds on every
// level has b_l equal (about 1); the Wald statistic of b_1 = ... = b_L,
//   W = (C b)' (C V C')^-1 (C b) ~ chi2(L - 1),   V = phi (X'WX)^-1_bb
// (C the successive differences; Wald 1943, Trans. AMS 54:426) is the
// linearised test of a term x level interaction, as Cochran's Q is for the
// groups of readings. Example: a temperature effect on the passes rolled
// without lubrication only (or those of one shift crew), which an unscoped
// temperature term fits with p = 1e-60: b_off about 2, b_on about 0.
// Levels with less than kMinLevelShare of the term's |D| or in fewer than
// 10 readings are pooled as "other" (fitted, not tested).
// Thread-safety: reentrant (reads its arguments only).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "core/base/distributions.h"
#include "core/diagnosis/diagnosis_stages_internal.h"

namespace rollwear::diag {
namespace {

constexpr double kMinLevelShare = 0.02;
constexpr int kMinLevelReadings = 10;

// A pass-level factor: each pass's level (-1: none) and the level labels.
struct PassFactor {
  std::string name;
  std::vector<int> level;  // per pass (TermData::load indexing)
  std::vector<std::string> labels;
};

// The pass-level factors the term `cov` is not itself about.
std::vector<PassFactor> PassFactors(const TermData& td, const std::string& cov) {
  std::vector<PassFactor> out;
  if (cov != "grade") out.push_back({"grade", td.grade, td.grades});
  for (int k = 0; k < static_cast<int>(td.catalog.size()); ++k) {
    const CovariateSpec& c = td.catalog[k];
    if (c.level != CovariateLevel::kPass || c.name == cov) continue;
    PassFactor f;
    if (c.kind == CovariateKind::kFlag) {
      f.labels = {"off", "on"};
    } else if (c.kind == CovariateKind::kFactor) {
      f.labels = c.levels;
    } else {
      continue;
    }
    f.name = c.name;
    f.level.resize(td.z[k].size());
    for (size_t i = 0; i < f.level.size(); ++i) {
      const double z = td.z[k][i];
      f.level[i] = std::isnan(z) ? -1 : static_cast<int>(std::lround(z));
    }
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace

std::vector<SplitHeterogeneity> SplitByPassFactors(const DiagnosisState& st,
                                                   const Fitted& with_term,
                                                   const std::vector<double>& w,
                                                   const std::vector<double>& before,
                                                   double phi) {
  const TermData& td = st.td;
  std::vector<TermSpec> without = with_term.terms;
  without.pop_back();
  const std::vector<double> c1 = PredictPassWear(td, st.train, with_term.log_k, with_term.terms);
  const std::vector<double> c0 = PredictPassWear(td, st.train, with_term.log_k, without);
  // e_i: the residual without the term (measurement terms included).
  const std::vector<double> p0 = PredictTerms(td, st.train, with_term.log_k, without);
  const size_t n = st.train.size();
  std::vector<SplitHeterogeneity> out;
  for (const PassFactor& f : PassFactors(td, with_term.terms.back().term.covariate)) {
    const int num_levels = static_cast<int>(f.labels.size());
    // Per level: |D| and the readings it reaches.
    std::vector<double> abs_d(num_levels + 1, 0.0);
    std::vector<int> reach(num_levels + 1, 0);
    double total = 0;
    for (size_t i = 0; i < n; ++i) {
      const TermObservation& ob = td.obs[st.train[i]];
      std::vector<char> seen(num_levels + 1, 0);
      for (int p = ob.pass_begin; p < ob.pass_end; ++p) {
        const int l = f.level[p] < 0 || f.level[p] >= num_levels ? num_levels : f.level[p];
        const double d = std::abs(c1[p] - c0[p]);
        abs_d[l] += d;
        total += d;
        if (d > 0 && !seen[l]) {
          seen[l] = 1;
          ++reach[l];
        }
      }
    }
    if (!(total > 0)) continue;
    // Tested levels get a column each; the rest is pooled (last column).
    std::vector<int> column(num_levels + 1, -1);
    std::vector<std::string> tested;
    for (int l = 0; l < num_levels; ++l) {
      if (abs_d[l] >= kMinLevelShare * total && reach[l] >= kMinLevelReadings) {
        column[l] = static_cast<int>(tested.size());
        tested.push_back(f.labels[l]);
      }
    }
    const int k = static_cast<int>(tested.size());
    if (k < 2) continue;
    const int cols = k + 1;  // + "other"
    for (int l = 0; l <= num_levels; ++l) {
      if (column[l] < 0) column[l] = k;
    }
    Eigen::MatrixXd x = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), 2 * cols);
    Eigen::VectorXd y(static_cast<Eigen::Index>(n));
    for (size_t i = 0; i < n; ++i) {
      const TermObservation& ob = td.obs[st.train[i]];
      const double sw = std::sqrt(w[i]);
      for (int p = ob.pass_begin; p < ob.pass_end; ++p) {
        const int l = f.level[p] < 0 || f.level[p] >= num_levels ? num_levels : f.level[p];
        const int c = column[l];
        x(static_cast<Eigen::Index>(i), c) += sw * c0[p];
        x(static_cast<Eigen::Index>(i), cols + c) += sw * (c1[p] - c0[p]);
      }
      y(static_cast<Eigen::Index>(i)) = sw * (ob.measured_um - p0[i]);
    }
    // Drop empty columns (an "other" with no passes), then require full rank.
    std::vector<int> keep;
    for (int j = 0; j < 2 * cols; ++j) {
      if (x.col(j).squaredNorm() > 0) keep.push_back(j);
    }
    Eigen::MatrixXd xk(x.rows(), static_cast<Eigen::Index>(keep.size()));
    for (size_t j = 0; j < keep.size(); ++j) xk.col(static_cast<Eigen::Index>(j)) = x.col(keep[j]);
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(xk);
    qr.setThreshold(1e-10);
    if (qr.rank() < xk.cols()) continue;
    const Eigen::VectorXd beta = qr.solve(y);
    const Eigen::MatrixXd inv = (xk.transpose() * xk).inverse();
    // Positions of the tested levels' D columns in `keep`.
    std::vector<Eigen::Index> at(k, -1);
    for (size_t j = 0; j < keep.size(); ++j) {
      if (keep[j] >= cols && keep[j] < cols + k) at[keep[j] - cols] = static_cast<Eigen::Index>(j);
    }
    if (std::any_of(at.begin(), at.end(), [](Eigen::Index a) { return a < 0; })) continue;
    Eigen::VectorXd b(k);
    Eigen::MatrixXd v(k, k);
    for (int r = 0; r < k; ++r) {
      b(r) = beta(at[r]);
      for (int c = 0; c < k; ++c) v(r, c) = phi * inv(at[r], at[c]);
    }
    Eigen::MatrixXd contrast = Eigen::MatrixXd::Zero(k - 1, k);
    for (int r = 0; r + 1 < k; ++r) {
      contrast(r, r) = 1;
      contrast(r, r + 1) = -1;
    }
    const Eigen::VectorXd cb = contrast * b;
    const Eigen::MatrixXd cvc = contrast * v * contrast.transpose();
    const double wald = cb.dot(cvc.ldlt().solve(cb));
    if (!std::isfinite(wald)) continue;
    SplitHeterogeneity h;
    h.factor = f.name;
    h.levels = k;
    h.wald = wald;
    h.p = ChiSquareSurvival(std::max(0.0, wald), k - 1);
    double sum_wb = 0, sum_w = 0;
    for (int r = 0; r < k; ++r) {
      sum_wb += b(r) / v(r, r);
      sum_w += 1 / v(r, r);
    }
    const double b_bar = sum_wb / sum_w;
    int largest = 0;
    for (int r = 0; r < k; ++r) {
      h.max_dev = std::max(h.max_dev, std::abs(b(r) - b_bar));
      if (std::abs(b(r)) > std::abs(b(largest))) largest = r;
    }
    h.level = tested[largest];
    h.scale = b(largest);
    // The level's mean residual before the round, over the readings its
    // passes carry, weighted by their share of the term's contribution.
    double num = 0, den = 0;
    for (size_t i = 0; i < n; ++i) {
      const TermObservation& ob = td.obs[st.train[i]];
      double share = 0, all = 0;
      for (int p = ob.pass_begin; p < ob.pass_end; ++p) {
        const double d = std::abs(c1[p] - c0[p]);
        all += d;
        const int l = f.level[p] < 0 || f.level[p] >= num_levels ? num_levels : f.level[p];
        if (column[l] == largest) share += d;
      }
      if (all > 0) {
        num += share / all * before[i];
        den += share / all;
      }
    }
    h.level_mean_um = den > 0 ? num / den : 0;
    out.push_back(h);
  }
  return out;
}

}  // namespace rollwear::diag
