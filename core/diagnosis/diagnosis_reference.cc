// Which level of a measurement-side text column reads true (docs/diagnosis.md,
// "Which gauge reads true"). An offset-per-level term y = K L + d_l (l not
// the reference r) is identified relative to r only because the wear law
// has no intercept: "B reads 15 um low" and "A reads 15 um high" differ by a
// constant on every reading, which K (multiplying the load L) absorbs only
// in part. How well the data tell the references apart is a test: the
// model with reference r is the all-levels model (one offset per level, an
// intercept in effect) restricted to d_r = 0, so
//   Delta_r = n log(RSS_r / RSS_best)
// (the likelihood-ratio statistic of the Gaussian fits, the same form as
// the round's LR test, diagnosis_stages.cc) is compared with chi2_1 at
// kReferenceLevel (Wilks 1938, Ann. Math. Stat. 9:60; RSS_best stands in
// for the unrestricted fit, which it bounds from above, so a reference is
// kept as possible whenever the data cannot reject it).
// A level is named as the one that reads off only when it is not itself a
// possible true reading. Otherwise the finding states the offset between
// the levels and says that the data do not identify which reads true: on
// two levels with few campaigns, "B reads low" and "A reads high" fit
// equally well, and naming either would be a confident guess.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/base/distributions.h"
#include "core/dataset/dataset.h"
#include "core/diagnosis/diagnosis_stages_internal.h"

namespace rollwear::diag {
namespace {

constexpr double kReferenceLevel = 0.01;  // chi2_1 upper quantile: 6.63

// chi2_1's upper `level` quantile, by bisection on ChiSquareSurvival.
double ChiSquare1Quantile(double level) {
  double lo = 0, hi = 100;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (ChiSquareSurvival(mid, 1) > level ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Training readings per level of the term's covariate inside its scope.
std::vector<int> ReadingsPerLevel(const DiagnosisState& st, const ModelTerm& t) {
  std::vector<int> count(t.num_levels, 0);
  const int k = st.td.CovariateIndex(t.covariate);
  if (k < 0) return count;
  for (int o : st.train) {
    const TermObservation& ob = st.td.obs[o];
    const std::string rt = ob.roll_type >= 0 ? st.td.roll_types[ob.roll_type] : "";
    if (!t.scope.CoversRoll(SlotStand(ob.slot), static_cast<int>(SlotPosition(ob.slot)),
                            rt)) {
      continue;
    }
    const double z = st.td.obs_z[k][o];
    if (std::isnan(z)) continue;
    const int l = static_cast<int>(z);
    if (l >= 0 && l < t.num_levels) ++count[l];
  }
  return count;
}

std::string LevelLabel(const ModelTerm& t, int l) {
  return l < static_cast<int>(t.levels.size()) ? t.levels[l] : std::to_string(l);
}

}  // namespace

Fitted ChooseOffsetReference(const DiagnosisState& st, const std::vector<double>& sd,
                             const Fitted& winner, ReferenceChoice* choice) {
  *choice = ReferenceChoice{};
  const ModelTerm& t = winner.terms.back().term;
  if (t.form != TermForm::kOffsetPerLevel || !winner.usable) return winner;
  const std::vector<int> count = ReadingsPerLevel(st, t);
  std::vector<Fitted> fits(t.num_levels);
  for (int r = 0; r < t.num_levels; ++r) {
    if (count[r] == 0) continue;
    if (r == t.reference_level) {
      fits[r] = winner;
      continue;
    }
    std::vector<TermSpec> terms = winner.terms;
    terms.back().term.reference_level = r;
    std::fill(terms.back().term.params.begin(), terms.back().term.params.end(), 0.0);
    fits[r] = Fit(st.td, st.train, sd, winner.log_k, terms);
  }
  int best = t.reference_level;
  for (int r = 0; r < t.num_levels; ++r) {
    if (fits[r].usable && fits[r].rss < fits[best].rss) best = r;
  }
  const double n = static_cast<double>(st.train.size());
  const double critical = ChiSquare1Quantile(kReferenceLevel);
  choice->critical = critical;
  for (int r = 0; r < t.num_levels; ++r) {
    if (!fits[r].usable || r == best) continue;
    const double delta = n * std::log(fits[r].rss / fits[best].rss);
    if (delta < critical) {
      choice->possible_true.push_back(LevelLabel(t, r));
      choice->delta.push_back(delta);
    }
  }
  choice->reference = LevelLabel(t, best);
  return fits[best];
}

void StateReferenceIdentification(const ReferenceChoice& choice, Finding* f) {
  if (f->form != "offset_per_level" || choice.possible_true.empty()) return;
  // The levels named as reading off that the data cannot reject as the true
  // reading are not named.
  std::string dropped, deltas;
  for (size_t i = 0; i < choice.possible_true.size(); ++i) {
    const std::string& level = choice.possible_true[i];
    auto it = std::find(f->levels.begin(), f->levels.end(), level);
    if (it == f->levels.end()) continue;
    f->levels.erase(it);
    char buf[160];
    std::snprintf(buf, sizeof(buf), "%s%s=%s: %.2f", deltas.empty() ? "" : ", ",
                  f->covariate.c_str(), level.c_str(), choice.delta[i]);
    deltas += buf;
    dropped += (dropped.empty() ? "" : ", ") + f->covariate + "=" + level;
  }
  if (dropped.empty()) return;
  char buf[200];
  std::snprintf(buf, sizeof(buf), "under %.2f, chi2_1 at 1 %%", choice.critical);
  f->explanation += " Which of " + f->covariate + "=" + choice.reference + " and " + dropped +
                    " reads true is not identified by these data: with either as the true "
                    "reading the fit is as good (likelihood-ratio difference " +
                    deltas + ", " + buf + "), so " + dropped +
                    " is not named as reading off";
  if (f->levels.empty()) {
    f->shape = "offset_between_levels";
    f->explanation += "; the offset is stated between the levels.";
  } else {
    std::string named;
    for (const std::string& l : f->levels) {
      named += (named.empty() ? "" : ", ") + f->covariate + "=" + l;
    }
    f->explanation += "; " + named + " reads off whichever of them is true.";
  }
}

}  // namespace rollwear::diag
