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
// Levels with less than min_level_share (2 %) of the term's |D| or in fewer
// than min_level_readings (10) readings (diagnosis_thresholds.h) are pooled
// as "other" (fitted, not tested).
// Thread-safety: reentrant (reads its arguments only).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "core/base/distributions.h"
#include "core/diagnosis/diagnosis_stages_internal.h"
#include "core/model/term_family.h"

namespace rollwear::diag {
namespace {

// A pass-level factor: each pass's level (-1: none) and the level labels.
struct PassFactor {
  std::string name;
  std::vector<int> level;  // per pass (TermData::load indexing)
  std::vector<std::string> labels;
  bool deferred = false;  // SplitHeterogeneity::deferred
  bool inside_gate = false;  // SplitHeterogeneity::inside_gate
};

// The quartiles of numeric pass-level covariate k over the training
// passes (load-weighted) as a factor: a term that claims one multiplier on
// a set of passes (a flag, a level of a text column) must hold at every
// temperature, speed, campaign progress... of those passes: a temperature
// effect on dry passes only otherwise reads as the lubrication flag, since
// in a campaign's mean the temperature's spread is diluted and pass by
// pass it is not
// (DiagnosisProxyTest.AnEffectOnDryPassesIsNotNamedAsTheLubricationFlag).
bool QuartileFactor(const TermData& td, const std::vector<int>& train, int k,
                    PassFactor* f) {
  std::array<double, 3> edges;
  const WeightedValues values = Collect(td, train, k);  // sorted once
  for (int q = 0; q < 3; ++q) edges[q] = Quantile(values, 0.25 * (q + 1));
  if (!std::isfinite(edges[0]) || !std::isfinite(edges[2]) ||
      !(edges[2] > edges[0])) {
    return false;
  }
  f->labels.clear();
  for (int q = 0; q < 4; ++q) f->labels.push_back(QuartileLabel(q, edges));
  f->name = td.catalog[k].name;
  f->level.resize(td.z[k].size());
  for (size_t i = 0; i < f->level.size(); ++i) {
    const double z = td.z[k][i];
    f->level[i] = std::isnan(z) ? -1 : QuartileOf(z, edges);
  }
  return true;
}

// A gated term's passes inside its gate, split in two at the load-weighted
// median of the gate covariate over those it acts on (the passes outside
// pooled): a
// gate claims one effect on every pass beyond its threshold, so the term's
// scale must not differ between the near and the far half (a slope along
// the gate covariate on the lubricated passes otherwise reads as a gated
// flag). SplitHeterogeneity::inside_gate marks it for the guard
// (diagnosis_guard.cc, ConstantInsideGate).
bool InsideGateHalves(const TermData& td, const std::vector<int>& train,
                      const ModelTerm& term, PassFactor* f) {
  const TermScope& scope = term.scope;
  const int k = scope.gate.empty() ? -1 : td.CovariateIndex(scope.gate);
  const int own = td.CovariateIndex(term.covariate);
  if (k < 0 || own < 0) return false;
  // The median over the passes where the term acts (a flag: those on),
  // load-weighted, so that both halves hold its effect.
  WeightedValues inside;
  for (int o : train) {
    const TermObservation& ob = td.obs[o];
    for (int i = ob.pass_begin; i < ob.pass_end; ++i) {
      const double z = td.z[k][i], x = td.z[own][i];
      if (!scope.CoversGateValue(z) || std::isnan(x) || x == 0) continue;
      inside.v.emplace_back(z, td.load[i]);
      inside.total += td.load[i];
    }
  }
  std::sort(inside.v.begin(), inside.v.end());
  const double median = Quantile(inside, 0.5);
  if (!std::isfinite(median)) return false;
  f->name = scope.gate;
  f->inside_gate = true;
  f->labels = {"inside the gate, < " + WordFormat("%.4g", median),
               "inside the gate, >= " + WordFormat("%.4g", median)};
  f->level.resize(td.z[k].size());
  for (size_t i = 0; i < f->level.size(); ++i) {
    const double z = td.z[k][i];
    f->level[i] = !scope.CoversGateValue(z) ? -1 : (z < median ? 0 : 1);
  }
  return true;
}

// The pass-level factors the last term of `terms` is not itself about, and
// the quartiles of the numeric pass-level covariates other than its own
// (not for a cell, whose inside LookInsideCell checks): a flag or a text
// level must hold on all of its passes, and a slope along one covariate
// must hold at every value of another: a temperature x speed interaction
// without main effects otherwise reads as contact length or speed at one
// stand (DiagnosisProxyTest.AnInteractionIsRefusedAcrossThePassQuartiles).
std::vector<PassFactor> PassFactors(const TermData& td,
                                    const std::vector<int>& train,
                                    const ModelTerm& term) {
  const std::string& cov = term.covariate;
  const bool quartiles = term.form != TermForm::kCell;
  const bool constant_on_passes =
      term.form == TermForm::kFlag || term.form == TermForm::kPerLevel;
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
      if (quartiles && c.source != CovariateSource::kCell &&
          QuartileFactor(td, train, k, &f)) {
        f.deferred = !constant_on_passes;
        out.push_back(std::move(f));
      }
      continue;
    }
    f.name = c.name;
    f.level.resize(td.z[k].size());
    for (size_t i = 0; i < f.level.size(); ++i)
      f.level[i] = LevelIndex(td.z[k][i]);
    out.push_back(std::move(f));
  }
  PassFactor inside;
  if (InsideGateHalves(td, train, term, &inside))
    out.push_back(std::move(inside));
  return out;
}

// Level l of pass p, or num_levels (pooled) for a pass without one.
int LevelOf(const PassFactor& f, int p) {
  const int n = static_cast<int>(f.labels.size());
  return f.level[p] < 0 || f.level[p] >= n ? n : f.level[p];
}

// The term's per-pass contribution d = c1 - c0 and prediction c0 (per pass).
struct PassSplit {
  const std::vector<double>& c0;
  const std::vector<double>& c1;
};

// Each level's column (-1: pooled) and the tested levels' labels: a level
// is tested when it carries >= thresholds.min_level_share of the term's |D|
// in >= thresholds.min_level_readings readings.
std::vector<int> TestedColumns(const TermData& td,
                               const std::vector<int>& train,
                               const DiagnosisThresholds& thresholds,
                               const PassFactor& f, const PassSplit& c,
                               std::vector<std::string>* tested) {
  const int num_levels = static_cast<int>(f.labels.size());
  std::vector<double> abs_d(num_levels + 1, 0.0);
  std::vector<int> reach(num_levels + 1, 0);
  double total = 0;
  for (int o : train) {
    const TermObservation& ob = td.obs[o];
    std::vector<char> seen(num_levels + 1, 0);
    for (int p = ob.pass_begin; p < ob.pass_end; ++p) {
      const int l = LevelOf(f, p);
      const double d = std::abs(c.c1[p] - c.c0[p]);
      abs_d[l] += d;
      total += d;
      if (d > 0 && !seen[l]) {
        seen[l] = 1;
        ++reach[l];
      }
    }
  }
  std::vector<int> column(num_levels + 1, -1);
  if (!(total > 0)) return column;
  for (int l = 0; l < num_levels; ++l) {
    if (abs_d[l] >= thresholds.min_level_share * total &&
        reach[l] >= thresholds.min_level_readings) {
      column[l] = static_cast<int>(tested->size());
      tested->push_back(f.labels[l]);
    }
  }
  return column;
}

// The Wald test of equal b over the tested levels: W, p, the largest
// |b_l - b_bar| and the level with the largest |b_l|.
void WaldEqual(const Eigen::VectorXd& b, const Eigen::MatrixXd& v,
               const std::vector<std::string>& tested, SplitHeterogeneity* h) {
  const Eigen::Index k = b.size();
  Eigen::MatrixXd contrast = Eigen::MatrixXd::Zero(k - 1, k);
  for (Eigen::Index r = 0; r + 1 < k; ++r) {
    contrast(r, r) = 1;
    contrast(r, r + 1) = -1;
  }
  const Eigen::VectorXd cb = contrast * b;
  const Eigen::MatrixXd cvc = contrast * v * contrast.transpose();
  h->wald = cb.dot(cvc.ldlt().solve(cb));
  h->levels = static_cast<int>(k);
  h->p = ChiSquareSurvival(std::max(0.0, h->wald), static_cast<double>(k - 1));
  double sum_wb = 0, sum_w = 0;
  for (Eigen::Index r = 0; r < k; ++r) {
    sum_wb += b(r) / v(r, r);
    sum_w += 1 / v(r, r);
  }
  const double b_bar = sum_wb / sum_w;
  Eigen::Index largest = 0;
  for (Eigen::Index r = 0; r < k; ++r) {
    h->max_dev = std::max(h->max_dev, std::abs(b(r) - b_bar));
    if (std::abs(b(r)) > std::abs(b(largest))) largest = r;
  }
  h->level = tested[largest];
  h->scale = b(largest);
}

// The WLS fit e ~ sum_l a_l P_l + sum_l b_l D_l over the training readings
// (columns: P of each tested level and the pool, then D likewise) and the
// Wald test of its tested b_l; false when the design is not of full rank.
bool FitLevelScales(const DiagnosisState& st, const PassFactor& f,
                    const PassSplit& c, const std::vector<int>& column,
                    const std::vector<std::string>& tested,
                    const std::vector<double>& e, const std::vector<double>& w,
                    double phi, SplitHeterogeneity* h) {
  const TermData& td = st.td;
  const auto n = static_cast<Eigen::Index>(st.train.size());
  const int k = static_cast<int>(tested.size());
  const int cols = k + 1;  // + the pool
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(n, 2 * cols);
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const TermObservation& ob = td.obs[st.train[i]];
    const double sw = std::sqrt(w[i]);
    for (int p = ob.pass_begin; p < ob.pass_end; ++p) {
      const int l = column[LevelOf(f, p)];
      const int j = l < 0 ? k : l;
      x(i, j) += sw * c.c0[p];
      x(i, cols + j) += sw * (c.c1[p] - c.c0[p]);
    }
    y(i) = sw * e[i];
  }
  // Empty columns (a pool without passes) out, then full rank required.
  std::vector<int> keep;
  for (int j = 0; j < 2 * cols; ++j) {
    if (x.col(j).squaredNorm() > 0) keep.push_back(j);
  }
  Eigen::MatrixXd xk(n, static_cast<Eigen::Index>(keep.size()));
  std::vector<Eigen::Index> at(k, -1);  // tested levels' D columns in xk
  for (size_t j = 0; j < keep.size(); ++j) {
    xk.col(static_cast<Eigen::Index>(j)) = x.col(keep[j]);
    if (keep[j] >= cols && keep[j] < cols + k)
      at[keep[j] - cols] = static_cast<Eigen::Index>(j);
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(xk);
  qr.setThreshold(1e-10);
  if (qr.rank() < xk.cols() ||
      std::any_of(at.begin(), at.end(), [](Eigen::Index a) { return a < 0; })) {
    return false;
  }
  const Eigen::VectorXd beta = qr.solve(y);
  const Eigen::MatrixXd inv = (xk.transpose() * xk).inverse();
  Eigen::VectorXd b(k);
  Eigen::MatrixXd v(k, k);
  for (int r = 0; r < k; ++r) {
    b(r) = beta(at[r]);
    for (int q = 0; q < k; ++q) v(r, q) = phi * inv(at[r], at[q]);
  }
  WaldEqual(b, v, tested, h);
  return std::isfinite(h->wald);
}

// The size of the effect on a level's passes: the root mean square of
// b_l * D_il over the readings its passes reach (the shape is what differs
// between the levels, so a mean residual would say little), with the sign
// of its mean.
double LevelEffectSize(const DiagnosisState& st, const PassFactor& f,
                       const PassSplit& c, const std::vector<int>& column,
                       int tested_level, double scale) {
  double sum = 0, sum2 = 0;
  int n = 0;
  for (int o : st.train) {
    const TermObservation& ob = st.td.obs[o];
    double d = 0;
    for (int p = ob.pass_begin; p < ob.pass_end; ++p) {
      if (column[LevelOf(f, p)] == tested_level)
        d += scale * (c.c1[p] - c.c0[p]);
    }
    if (d == 0) continue;
    sum += d;
    sum2 += d * d;
    ++n;
  }
  if (n == 0) return 0;
  return std::copysign(std::sqrt(sum2 / n), sum);
}

}  // namespace

std::vector<SplitHeterogeneity> SplitByPassFactors(const DiagnosisState& st,
                                                   const Fitted& with_term,
                                                   const std::vector<double>& e,
                                                   const std::vector<double>& w,
                                                   double phi) {
  const TermData& td = st.td;
  std::vector<TermSpec> without = with_term.terms;
  without.pop_back();
  const std::vector<double> c1 =
      PredictPassWear(td, st.train, with_term.log_k, with_term.terms);
  const std::vector<double> c0 =
      PredictPassWear(td, st.train, with_term.log_k, without);
  const PassSplit c{c0, c1};
  std::vector<SplitHeterogeneity> out;
  for (const PassFactor& f :
       PassFactors(td, st.train, with_term.terms.back().term)) {
    std::vector<std::string> tested;
    const std::vector<int> column =
        TestedColumns(td, st.train, st.thresholds, f, c, &tested);
    if (tested.size() < 2) continue;
    SplitHeterogeneity h;
    h.factor = f.name;
    h.deferred = f.deferred;
    h.inside_gate = f.inside_gate;
    if (!FitLevelScales(st, f, c, column, tested, e, w, phi, &h)) continue;
    const int largest = static_cast<int>(
        std::find(tested.begin(), tested.end(), h.level) - tested.begin());
    h.level_size_um = LevelEffectSize(st, f, c, column, largest, h.scale);
    out.push_back(h);
  }
  return out;
}

}  // namespace rollwear::diag
