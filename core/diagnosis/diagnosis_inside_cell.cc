// Cells in the proxy guard: a winning cell stated as the place of its twin
// pair that wears more (OrientTwinCell), and the look inside a cell
// (docs/diagnosis.md, "The proxy guard", "Inside a cell"): a cell term
// claims one constant multiplier on the passes of its place (a stand or
// roll position x a roll type or grade). An effect that lives on that
// place but varies with a wear-rate quantity is taken by the cell as its
// mean: width acting on roll type X at
// F7 only, (1000/w)^1.2, is fitted as "X at F7 x 0.78", or as its twin "X
// at F6 x 1.28", with p = 1e-37, and the width is never seen, since an
// unscoped or single-scoped width term is inconsistent across the other
// factor and refused. Here each numeric wear-rate covariate (of the pass,
// the roll or the campaign; not a locate-only one) gets a
// log-linear term m = exp(b (z - c) / s) (c, s: the training mean and sd)
// restricted to the cell's place, and to its twin's (TwinCell, which
// describes the same data), on top of the model that holds the cell. The
// nested likelihood-ratio test LR = n ln(RSS / RSS_inside) ~ chi2(1)
// (Wilks 1938, Ann. Math. Stat. 9:60), Bonferroni over places x
// covariates, at thresholds.alternative_alpha (AnyOf,
// diagnosis_alternatives.h: the burden of proof is on the cell's "constant"),
// asks whether the cell's effect varies with the covariate there. A slope
// inside the cell can also come from another structure the model still lacks: a
// grade wearing F7 more, whose coils are wider, makes width matter inside every
// F7 cell. So the slope must also add given each other cell the candidates
// offer, one at a time (EachOf, unadjusted: each is a rival explanation of a
// slope already significant over the family). A wider slope (everywhere, at the
// stand, on the roll type) is no such rival: it holds the cell's place too, and
// the cell's multiplier would still vary there. When it adds, the cell is
// refused and the place is located along the covariate: the vocabulary has no
// covariate scoped to two factors at once, so the mismatch is located, not
// named. An alternative whose fit fails is no explanation (the slope
// counts as adding given it).
// Thread-safety: reentrant (reads its arguments only).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/base/distributions.h"
#include "core/diagnosis/diagnosis_alternatives.h"
#include "core/diagnosis/diagnosis_stages_internal.h"

namespace rollwear::diag {
namespace {

// A log-linear term in covariate k over `scope`, centred and scaled by the
// covariate's training mean and sd.
struct Slope {
  int k = -1;
  double mean = 0, spread = 1;
  TermScope place;
  double lr = 0, p = 1, b = 0;
};

TermSpec SlopeSpec(const DiagnosisState& st, const Slope& s,
                   const TermScope& scope, double start) {
  TermSpec t;
  t.covariate = s.k;
  t.term.covariate = st.td.catalog[s.k].name;
  t.term.form = TermForm::kLogLinear;
  t.term.params = {start};
  t.term.center = s.mean;
  t.term.scale = s.spread;
  t.term.scope = scope;
  t.lower = {-2.0};
  t.upper = {2.0};
  return t;
}

// The alternatives a slope inside the cell must add to: every other offered
// cell (a grade wearing F7 more, whose coils are wider, makes width matter
// inside every F7 roll-type cell). A wider slope (everywhere, at the stand,
// on the roll type) is not one: it holds the cell's place too, so the
// cell's multiplier would still vary with the covariate there.
std::vector<TermSpec> Alternatives(const DiagnosisState& st,
                                   const std::vector<TermScope>& cells,
                                   const std::vector<TermScope>& skip) {
  std::vector<TermSpec> out;
  for (const TermScope& c : cells) {
    if (std::find(skip.begin(), skip.end(), c) == skip.end())
      out.push_back(CellTermSpec(st.td, c));
  }
  return out;
}

// Whether slope `s` adds to `with_term` plus each alternative (EachOf,
// unadjusted): the slope is already significant over the family (the plain
// test), and each alternative here is a rival explanation of it, which
// explains it when the slope no longer adds at that level.
bool AddsToEveryAlternative(const DiagnosisState& st,
                            const std::vector<double>& sd,
                            const Fitted& with_term, const Slope& s,
                            const std::vector<TermSpec>& alternatives) {
  const Multiplicity each = EachOf(st.thresholds);
  for (const TermSpec& alt : alternatives) {
    const Fitted base = FitWith(st, sd, with_term, alt);
    if (!base.usable) continue;
    const Encompassing e =
        Encompass(st, sd, base, SlopeSpec(st, s, s.place, s.b));
    if (!e.with.usable) continue;
    if (!each.Rejects(e.p)) return false;
  }
  return true;
}

// The significant, material slopes inside `places`, strongest first: any
// one refutes the cell's "constant", so Bonferroni over places x
// covariates (*family).
std::vector<Slope> SignificantSlopes(const DiagnosisState& st,
                                     const std::vector<double>& sd,
                                     const Fitted& with_term,
                                     const std::vector<TermScope>& places,
                                     Multiplicity* family) {
  std::vector<int> covariates;
  for (int k = 0; k < static_cast<int>(st.td.catalog.size()); ++k) {
    const CovariateSpec& c = st.td.catalog[k];
    if (c.level != CovariateLevel::kMeasurement &&
        c.kind == CovariateKind::kNumeric &&
        c.source != CovariateSource::kCell && !c.locate_only) {
      covariates.push_back(k);
    }
  }
  *family = AnyOf(st.thresholds,
                  static_cast<double>(places.size() * covariates.size()));
  std::vector<Slope> out;
  for (int k : covariates) {
    Slope s;
    s.k = k;
    const WeightedValues w = Collect(st.td, st.train, k);
    if (!(w.total > 0)) continue;
    MeanSd(w, &s.mean, &s.spread);
    if (!(s.spread > 0)) continue;
    for (const TermScope& place : places) {
      s.place = place;
      const Encompassing inside =
          Encompass(st, sd, with_term, SlopeSpec(st, s, place, 0.0));
      if (!inside.usable()) continue;
      s.b = inside.with.terms.back().term.params[0];
      s.lr = inside.lr;
      s.p = inside.p;
      if (std::abs(s.b) >= st.thresholds.material_slope &&
          family->Rejects(s.p)) {
        out.push_back(s);
      }
    }
  }
  std::sort(out.begin(), out.end(),
            [](const Slope& a, const Slope& b) { return a.p < b.p; });
  return out;
}

}  // namespace

GuardResult LookInsideCell(const DiagnosisState& st,
                           const DiagnosisOptions& options,
                           const std::vector<double>& sd,
                           const Fitted& with_term) {
  GuardResult r;
  const TermSpec& cell = with_term.terms.back();
  if (cell.term.form != TermForm::kCell) return r;
  std::vector<TermScope> places = {cell.term.scope};
  TermScope twin;
  if (TwinCell(st.td, st.train, options.thresholds, cell.term.scope, &twin))
    places.push_back(twin);
  Multiplicity family;
  const std::vector<Slope> slopes =
      SignificantSlopes(st, sd, with_term, places, &family);
  if (slopes.empty()) return r;
  // The model's cells (this one among them) and their twins are in it
  // already.
  const std::vector<TermScope> skip = WithTwins(
      st.td, st.train, options.thresholds, ModelCells(with_term.terms));
  const std::vector<TermSpec> alternatives = Alternatives(
      st, OfferedCellScopes(st.td, st.train, options.thresholds), skip);
  const Slope* found = nullptr;
  for (const Slope& s : slopes) {
    if (AddsToEveryAlternative(st, sd, with_term, s, alternatives)) {
      found = &s;
      break;
    }
  }
  if (found == nullptr) return r;
  const std::string& name = st.td.catalog[found->k].name;
  const double p_adjusted = family.Adjusted(found->p);
  char buf[320];
  std::snprintf(buf, sizeof(buf),
                "not constant inside the cell: on %s the effect varies with "
                "%s (%+.0f %% per sd; LR %.1f, p adjusted %.2g), and no "
                "covariate term is scoped to a place and a %s at once",
                found->place.Label().c_str(), name.c_str(),
                100 * (std::exp(found->b) - 1), found->lr, p_adjusted,
                cell.term.scope.roll_type.empty() ? "grade" : "roll type");
  r.pass = false;
  r.reason = buf;
  r.located.dimension = "effect_by_" + name;
  r.located.where = found->place.Label() + ": along " + name;
  r.located.test = "likelihood_ratio";
  r.located.statistic = found->lr;
  r.located.mean_residual_um = MeanResidualIn(st, with_term, found->place);
  r.located.p_value = found->p;
  r.located.p_adjusted = p_adjusted;
  return r;
}

// A cell with a twin (TwinCell) describes the same data as its twin with
// the inverse multiplier; the data cannot tell which place is the
// exception. The finding is stated by one convention, the place that wears
// MORE than the K structure predicts (multiplier >= 1), and says so: when
// the fitted cell wears less, its twin is fitted instead (the roll type's or
// grade's own K factor takes up the rest; the fit is the same up to the
// cell prior) and `note` gets the sentence naming both.
Fitted OrientTwinCell(const DiagnosisState& st, const std::vector<double>& sd,
                      const Fitted& winner, std::string* note) {
  const TermSpec& cell = winner.terms.back();
  TermScope twin;
  if (cell.term.form != TermForm::kCell ||
      !TwinCell(st.td, st.train, st.thresholds, cell.term.scope, &twin)) {
    return winner;
  }
  const double b = cell.term.params[0];
  Fitted out = winner;
  TermScope other = twin;
  if (b < 0) {
    std::vector<TermSpec> terms = winner.terms;
    terms.back().term.scope = twin;
    terms.back().term.params = {-b};
    const Fitted flipped = Fit(st.td, st.train, sd, winner.log_k, terms);
    if (flipped.usable) {
      out = flipped;
      other = cell.term.scope;
    }
  }
  const double m = std::exp(out.terms.back().term.params[0]);
  char buf[320];
  std::snprintf(
      buf, sizeof(buf),
      " The data cannot tell this from rolls of %s wearing %.2f times the "
      "prediction: the %s runs in these two places only and its own K "
      "factor takes up the rest (stated here as the place that wears more).",
      other.Label().c_str(), 1.0 / m,
      cell.term.scope.roll_type.empty() ? "grade" : "roll type");
  *note = buf;
  return out;
}

}  // namespace rollwear::diag
