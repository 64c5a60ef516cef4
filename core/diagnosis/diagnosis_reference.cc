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
// the round's LR test, diagnosis_stages.cc, with the round's robust sd
// weights held fixed) is compared with chi2_1 at 1 % (Wilks 1938, Ann.
// Math. Stat. 9:60). RSS_best stands in for the unrestricted fit's RSS,
// which it bounds from above, so Delta_r is never larger than the true
// statistic and a reference is kept as possible whenever the data cannot
// reject it. The best reference itself is not tested against the
// all-levels model: when every level reads off by a common constant, the
// data say only which levels differ (docs/diagnosis.md, Limits).
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

#include "core/dataset/dataset.h"
#include "core/diagnosis/diagnosis_stages_internal.h"

namespace rollwear::diag {
namespace {

// Training readings per level of the term's covariate inside its scope.
std::vector<int> ReadingsPerLevel(const DiagnosisState& st,
                                  const ModelTerm& t) {
  std::vector<int> count(t.num_levels, 0);
  const int k = st.td.CovariateIndex(t.covariate);
  if (k < 0) return count;
  for (int o : st.train) {
    const TermObservation& ob = st.td.obs[o];
    const std::string rt =
        ob.roll_type >= 0 ? st.td.roll_types[ob.roll_type] : "";
    if (!t.scope.CoversRoll(SlotStand(ob.slot),
                            static_cast<int>(SlotPosition(ob.slot)), rt)) {
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
  return l < static_cast<int>(t.levels.size()) ? t.levels[l]
                                               : std::to_string(l);
}

}  // namespace

Fitted ChooseOffsetReference(const DiagnosisState& st,
                             const std::vector<double>& sd,
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
    std::fill(terms.back().term.params.begin(), terms.back().term.params.end(),
              0.0);
    fits[r] = Fit(st.td, st.train, sd, winner.log_k, terms);
  }
  int best = -1;
  for (int r = 0; r < t.num_levels; ++r) {
    if (fits[r].usable && (best < 0 || fits[r].rss < fits[best].rss)) best = r;
  }
  if (best < 0) return winner;
  const double n = static_cast<double>(st.train.size());
  choice->critical = st.thresholds.reference_chi2_critical;
  for (int r = 0; r < t.num_levels; ++r) {
    if (count[r] == 0 || r == best) continue;
    // A level whose refit failed is not rejected: it stays possible.
    const double delta = fits[r].usable
                             ? n * std::log(fits[r].rss / fits[best].rss)
                             : std::nan("");
    if (!(delta >= st.thresholds.reference_chi2_critical)) {
      choice->possible.push_back({LevelLabel(t, r), delta});
    }
  }
  choice->reference = LevelLabel(t, best);
  return fits[best];
}

void StateReferenceIdentification(const ReferenceChoice& choice, Finding* f) {
  if (f->form != "offset_per_level" || choice.possible.empty()) return;
  // The levels named as reading off that the data cannot reject as the true
  // reading are not named.
  std::vector<std::string> dropped;
  std::string deltas;
  for (const ReferenceChoice::Possible& p : choice.possible) {
    auto it = std::find(f->levels.begin(), f->levels.end(), p.level);
    if (it == f->levels.end()) continue;
    f->levels.erase(it);
    const std::string label = f->covariate + "=" + p.level;
    char buf[160];
    if (std::isnan(p.delta)) {
      std::snprintf(buf, sizeof(buf), "%s: its refit failed", label.c_str());
    } else {
      std::snprintf(buf, sizeof(buf), "%s: %.2f", label.c_str(), p.delta);
    }
    deltas += (deltas.empty() ? "" : ", ") + std::string(buf);
    dropped.push_back(label);
  }
  if (dropped.empty()) return;
  std::string list;
  for (const std::string& d : dropped) list += (list.empty() ? "" : ", ") + d;
  const bool one = dropped.size() == 1;
  char crit[64];
  std::snprintf(crit, sizeof(crit), "under %.2f, chi2_1 at 1 %%",
                choice.critical);
  f->explanation += " Which of " + f->covariate + "=" + choice.reference +
                    " and " + list +
                    " reads true is not identified by these data: with "
                    "either as the true reading the fit is as good "
                    "(likelihood-ratio difference " +
                    deltas + ", " + crit + "), so " + list +
                    (one ? " is" : " are") + " not named as reading off";
  if (f->levels.empty()) {
    f->shape = "offset_between_levels";
    f->explanation += "; the offset is stated between the levels.";
    return;
  }
  std::string named;
  for (const std::string& l : f->levels) {
    named += (named.empty() ? "" : ", ") + f->covariate + "=" + l;
  }
  f->explanation += "; " + named +
                    (f->levels.size() == 1 ? " reads" : " read") +
                    " off whichever of them is true.";
}

}  // namespace rollwear::diag
