// TermModel: the wear model with its terms evaluated observation by
// observation for the term fits (term_fit.cc) and the score screen: the
// prediction of a reading and its Jacobian in log K and the terms'
// parameters. Internal to core/fit.
//
// Wear of observation o (Archard-type law, docs/model.md):
//   w_o = sum over its passes i of k_g(i) * load_i * prod_t m_t(z_t,i),
//   k_g = exp(log kF_position + log kR_roll_type + log kS_grade),
// plus the additive terms' wear on each pass they cover (a_t(z_t,i), wear
// per coil) times the roll's own factor (the roll-effect term, which scales
// all of a roll's wear), and the measurement terms' reading offsets.
//
// Thread-safety: a TermModel keeps per-call scratch and a cache of the
// last multiplier per term; use one per thread. The TermData it reads
// must outlive it and not change. Its terms' forms, centers and scales are
// fixed at construction (the exponents u(z) are computed from them at the
// first Predict); only their parameters change, through SetParams.
#ifndef ROLLWEAR_CORE_FIT_TERM_MODEL_INTERNAL_H_
#define ROLLWEAR_CORE_FIT_TERM_MODEL_INTERNAL_H_

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/dataset/dataset.h"
#include "core/fit/term_fit.h"
#include "core/model/model_terms.h"
#include "core/model/term_family.h"

namespace rollwear::fit_internal {

// Evaluates predictions and their Jacobian for log_k (n_coef) and the term
// parameters (concatenated after log_k).
class TermModel {
 public:
  TermModel(const TermData& data, const std::vector<TermSpec>& terms)
      : data_(data), terms_(terms) {
    p_ = static_cast<int>(data.positions.size());
    r_ = static_cast<int>(data.roll_types.size());
    s_ = static_cast<int>(data.grades.size());
    n_coef_ = p_ + r_ + s_;
    n_ = n_coef_;
    for (const TermSpec& t : terms_) {
      offsets_.push_back(n_);
      n_ += t.term.NumParams();
      num_params_.push_back(t.term.NumParams());
      measurement_.push_back(t.term.IsMeasurementTerm() ? 1 : 0);
      additive_.push_back(t.term.IsAdditiveTerm() ? 1 : 0);
      scales_added_.push_back(FamilyOf(t.term.form).scales_added_wear() ? 1
                                                                        : 0);
      scopes_.push_back(Resolve(t.term.scope));
    }
    k_.resize(s_);
    k_ok_.resize(s_);
    t_.resize(s_);
    last_z_.resize(terms_.size());
    cached_.resize(terms_.size());
  }

  int num_coef() const { return n_coef_; }
  int num_params() const { return n_; }
  int r_offset() const { return p_; }
  int s_offset() const { return p_ + r_; }
  const std::vector<TermSpec>& terms() const { return terms_; }
  // Whether term t applies to observation `o` (its roll) and, for a wear
  // term, to pass i of grade g.
  bool CoversRoll(int t, const TermObservation& o) const {
    return scopes_[t].CoversRoll(o);
  }
  // Whether wear term t applies to pass i of grade g (its grade and gate).
  bool CoversPass(int t, int g, int i) const {
    return scopes_[t].CoversPass(g, i);
  }
  // With `out` (indexed by pass, sized to every pass), Predict also writes
  // each pass's wear contribution k_g * load * (product of the wear terms),
  // with the additive terms' wear on the pass when `with_added` (the pass's
  // whole wear) or without (the part a multiplier scales).
  void set_pass_contributions(std::vector<double>* out, bool with_added) {
    pass_out_ = out;
    pass_out_with_added_ = with_added;
  }

  // Whether a term's multiplier is exp(b u(z)) with one parameter b, and
  // u(z) of such a term t: its family's (core/model/term_family.h).
  static bool IsExpForm(const ModelTerm& term) {
    return term.NumParams() == 1 && FamilyOf(term.form).exponential();
  }
  double ExponentOf(size_t t, double z) const {
    const ModelTerm& term = terms_[t].term;
    return FamilyOf(term.form).Exponent(term, z);
  }

  // Writes params into the terms.
  void SetParams(const double* params) {
    for (size_t t = 0; t < terms_.size(); ++t) {
      std::copy(params + offsets_[t],
                params + offsets_[t] + terms_[t].term.NumParams(),
                terms_[t].term.params.begin());
    }
  }

  // Prediction of observation o; with `grad` (size num_params, zeroed by
  // the caller) also d(prediction)/d(params).
  double Predict(const double* params, int o, double* grad,
                 bool wear_only = false) {
    const TermObservation& obs = data_.obs[o];
    const size_t nt = terms_.size();
    if (u_.size() != nt) PrecomputeExponents();  // once, at the first call
    roll_in_.resize(nt);
    for (size_t t = 0; t < nt; ++t) roll_in_[t] = scopes_[t].CoversRoll(obs);
    const double base = params[obs.position] +
                        (obs.roll_type >= 0 ? params[p_ + obs.roll_type] : 0.0);
    // k of a grade only where the observation has a pass of that grade
    // (the others add exactly 0 to the prediction and its derivatives).
    std::fill(t_.begin(), t_.end(), 0.0);
    std::fill(k_ok_.begin(), k_ok_.end(), 0);
    double wear = 0;
    scratch_.resize(8);
    mt_.resize(nt);
    if (grad != nullptr) dm_.resize(static_cast<size_t>(n_));
    // m_t and dm_t of the last pass a term was evaluated on, reused while
    // its covariate repeats bit for bit (campaign- and roll-level
    // covariates repeat on every pass): TermMultiplier is a function of
    // (params, z) alone, so the reuse is exact.
    std::fill(cached_.begin(), cached_.end(), 0);
    zp_.resize(nt);
    for (size_t t = 0; t < nt; ++t)
      zp_[t] = data_.z[terms_[t].covariate].data();
    // The wear terms that cover this observation's roll; the others' m is
    // 1 on every pass (a factor of exactly 1: leaving it out is exact).
    active_.clear();
    added_.clear();
    for (size_t t = 0; t < nt; ++t) {
      if (measurement_[t] || !roll_in_[t]) continue;
      (additive_[t] ? added_ : active_).push_back(t);
    }
    for (int i = obs.pass_begin; i < obs.pass_end; ++i) {
      const int g = data_.grade[i];
      if (!k_ok_[g]) {
        k_[g] = std::exp(base + params[p_ + r_ + g]);
        k_ok_[g] = 1;
      }
      double m = 1;
      double roll = 1;  // the factors that scale the added wear too
      for (const size_t t : active_) {
        if (!scopes_[t].CoversPass(g, i)) {
          mt_[t] = 1.0;  // outside the scope: m = 1, no derivative
          cached_[t] = 0;
          continue;
        }
        const uint64_t z_bits = std::bit_cast<uint64_t>(zp_[t][i]);
        if (!cached_[t] || z_bits != last_z_[t]) {
          double* dm = grad != nullptr ? dm_.data() + offsets_[t] : nullptr;
          mt_[t] = u_[t].empty()
                       ? TermMultiplier(terms_[t].term,
                                        std::bit_cast<double>(z_bits), dm)
                       : ExpMultiplier(t, i, std::bit_cast<double>(z_bits), dm);
          last_z_[t] = z_bits;
          cached_[t] = 1;
        }
        m *= mt_[t];
        if (scales_added_[t]) roll *= mt_[t];
      }
      const double c = k_[g] * data_.load[i] * m;
      wear += c;
      t_[g] += c;
      const double added = added_.empty() ? 0.0 : AddedWear(i, g, roll, grad);
      wear += added;
      if (pass_out_ != nullptr)
        (*pass_out_)[i] = pass_out_with_added_ ? c + added : c;
      if (grad == nullptr) continue;
      for (const size_t t : active_) {
        if (!scopes_[t].CoversPass(g, i)) continue;
        // d(c)/d(param) = c / m_t * dm_t/d(param), and the added wear's
        // for a factor that scales it.
        const double scaled = scales_added_[t] ? c + added : c;
        const double f = mt_[t] != 0 ? scaled / mt_[t] : 0.0;
        const double* dm = dm_.data() + offsets_[t];
        double* gt = grad + offsets_[t];
        for (int j = 0; j < num_params_[t]; ++j) gt[j] += f * dm[j];
      }
    }
    double y = wear;
    if (grad != nullptr) {
      double total = 0;
      for (int s = 0; s < s_; ++s) {
        grad[p_ + r_ + s] += t_[s];
        total += t_[s];
      }
      grad[obs.position] += total;
      if (obs.roll_type >= 0) grad[p_ + obs.roll_type] += total;
    }
    if (wear_only) return y;
    for (size_t t = 0; t < terms_.size(); ++t) {
      const ModelTerm& term = terms_[t].term;
      if (!term.IsMeasurementTerm() || !roll_in_[t]) continue;
      const int np = term.NumParams();
      if (static_cast<int>(scratch_.size()) < np) scratch_.resize(np);
      const double z = data_.obs_z[terms_[t].covariate][o];
      y += TermOffset(term, z, scratch_.data());
      if (grad != nullptr) {
        for (int j = 0; j < np; ++j) grad[offsets_[t] + j] += scratch_[j];
      }
    }
    return y;
  }

 private:
  // The additive terms' wear on pass i of grade g (added_: those covering
  // the observation's roll) times `roll` (the roll's own factor), their
  // derivatives added into grad.
  double AddedWear(int i, int g, double roll, double* grad) {
    double sum = 0;
    for (const size_t t : added_) {
      if (!scopes_[t].CoversPass(g, i)) continue;
      const int np = num_params_[t];
      if (static_cast<int>(scratch_.size()) < np) scratch_.resize(np);
      const double z = zp_[t][i];
      sum += roll * TermAddend(terms_[t].term, z, scratch_.data());
      if (grad == nullptr) continue;
      for (int j = 0; j < np; ++j) grad[offsets_[t] + j] += roll * scratch_[j];
    }
    return sum;
  }

  // A TermScope resolved to the data's level indices (-1: any level, -2: a
  // label the data does not have, which nothing matches) and its gate to the
  // gate covariate's values by pass (a gate over a covariate the data does
  // not have matches nothing).
  struct ResolvedScope {
    int stand = 0, position = -1, roll_type = -1, grade = -1;
    const double* gate = nullptr;  // the gate covariate by pass
    double gate_at = 0;
    bool gate_above = true, gate_missing = false;
    bool CoversRoll(const TermObservation& o) const {
      return (stand == 0 || stand == SlotStand(o.slot)) &&
             (position < 0 ||
              position == static_cast<int>(SlotPosition(o.slot))) &&
             (roll_type == -1 || roll_type == o.roll_type);
    }
    bool CoversPass(int g, int i) const {
      if (grade != -1 && grade != g) return false;
      if (gate == nullptr) return !gate_missing;
      // NaN (no value) is on neither side.
      return gate_above ? gate[i] >= gate_at : gate[i] < gate_at;
    }
  };
  ResolvedScope Resolve(const TermScope& s) const {
    auto level = [](const std::vector<std::string>& labels,
                    const std::string& l) {
      if (l.empty()) return -1;
      const auto it = std::find(labels.begin(), labels.end(), l);
      return it == labels.end() ? -2 : static_cast<int>(it - labels.begin());
    };
    ResolvedScope r{s.stand, s.position, level(data_.roll_types, s.roll_type),
                    level(data_.grades, s.grade)};
    if (!s.gate.empty()) {
      r.gate_at = s.gate_at;
      r.gate_above = s.gate_above;
      const int k = data_.CovariateIndex(s.gate);
      if (k >= 0) {
        r.gate = data_.z[k].data();
      } else {
        r.gate_missing = true;
      }
    }
    return r;
  }

  // The families whose multiplier is m = exp(b u(z)) with u fixed by the
  // term's center and scale (log_linear u = (z - c) / s, power
  // u = ln(max(z, 1e-12) / c), flag u = z; term_family.h): u of every
  // pass is computed once per fit (at the first Predict), by the same
  // expression as TermMultiplier, so the fit's iterations evaluate only exp
  // (the same bits; a profile of a diagnosis had the per-pass log at 15 %
  // of its time).
  void PrecomputeExponents() {
    u_.resize(terms_.size());
    for (size_t t = 0; t < terms_.size(); ++t) {
      if (terms_[t].term.IsMeasurementTerm() || !IsExpForm(terms_[t].term))
        continue;
      const std::vector<double>& z = data_.z[terms_[t].covariate];
      std::vector<double>& u = u_[t];
      u.resize(z.size());
      for (size_t i = 0; i < z.size(); ++i) u[i] = ExponentOf(t, z[i]);
    }
  }
  // TermMultiplier of a term with u_ (one parameter), at pass i.
  double ExpMultiplier(size_t t, int i, double z, double* grad) const {
    if (std::isnan(z)) {
      if (grad != nullptr) grad[0] = 0.0;
      return 1.0;
    }
    const double u = u_[t][i];
    const double m = std::exp(terms_[t].term.params[0] * u);
    if (grad != nullptr) grad[0] = m * u;
    return m;
  }

  const TermData& data_;
  std::vector<TermSpec> terms_;
  std::vector<std::vector<double>> u_;  // per term, per pass (or empty)
  std::vector<ResolvedScope> scopes_;
  std::vector<char> roll_in_;
  std::vector<int> offsets_, num_params_;
  std::vector<char> measurement_;  // per term: a reading offset
  std::vector<char> additive_;     // per term: wear added per pass
  std::vector<char> scales_added_;  // per term: scales the added wear too
  std::vector<uint64_t> last_z_;   // per term: z (bits) of the cached m_t, dm_t
  std::vector<char> cached_;       // per term: last_z_ is valid
  std::vector<char> k_ok_;  // per grade: k_ computed for this observation
  int p_ = 0, r_ = 0, s_ = 0, n_coef_ = 0, n_ = 0;
  std::vector<double> k_, t_, scratch_, mt_, dm_;
  std::vector<size_t> active_;     // per observation: its roll's wear terms
  std::vector<size_t> added_;      // ... and its roll's additive terms
  std::vector<const double*> zp_;  // per term: its covariate's values by pass
  std::vector<double>* pass_out_ = nullptr;
  bool pass_out_with_added_ = false;
};

}  // namespace rollwear::fit_internal

#endif  // ROLLWEAR_CORE_FIT_TERM_MODEL_INTERNAL_H_
