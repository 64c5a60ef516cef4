// Tests of the term-family registry (core/model/term_family.h): every form
// has its family under its stored name, each family's derivatives are
// those of its multiplier or offset, a wear-rate family never offsets a
// reading (nor a measurement family the wear rate), and the families' own
// rules on stored terms.
#include "core/model/term_family.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/model/covariates.h"

namespace rollwear {
namespace {

constexpr TermForm kEveryForm[] = {
    TermForm::kLogLinear,    TermForm::kPower,          TermForm::kSaturating,
    TermForm::kDecaying,     TermForm::kFlag,           TermForm::kBinned,
    TermForm::kPerLevel,     TermForm::kCell,           TermForm::kOffsetDecay,
    TermForm::kOffsetLinear, TermForm::kOffsetPerLevel, TermForm::kOffsetBinned,
    TermForm::kRollEffect,   TermForm::kPerCoil,        TermForm::kHinge,
};

// A term of form `f` with parameters away from zero, so that every
// derivative is non-trivial.
ModelTerm TermOf(TermForm f) {
  ModelTerm t;
  t.form = f;
  t.covariate = f == TermForm::kRollEffect ? kRollIdName
                : f == TermForm::kPerCoil  ? "campaign_coils_before"
                                           : "z";
  t.center = 2.0;
  t.scale = 1.5;
  t.edges = {1.0, 2.5, 4.0};
  t.num_levels = 4;
  t.reference_level = f == TermForm::kOffsetPerLevel ? 2 : 0;
  if (f == TermForm::kRollEffect) t.levels = {"R1", "R2", "R3", "R4"};
  t.params.assign(t.NumParams(), 0.0);
  for (size_t j = 0; j < t.params.size(); ++j) t.params[j] = 0.3 - 0.17 * j;
  if (f == TermForm::kSaturating || f == TermForm::kDecaying ||
      f == TermForm::kOffsetDecay) {
    t.params = {0.4, std::log(3.0)};
    if (f == TermForm::kOffsetDecay) t.params[0] = -12.0;
  }
  return t;
}

double Value(const ModelTerm& t, double z, double* grad) {
  if (t.IsAdditiveTerm()) return TermAddend(t, z, grad);
  return t.IsMeasurementTerm() ? TermOffset(t, z, grad)
                               : TermMultiplier(t, z, grad);
}

// The value of a term that leaves everything as it is: a multiplier of 1,
// an offset or added wear of 0.
double Neutral(const ModelTerm& t) {
  return t.IsMeasurementTerm() || t.IsAdditiveTerm() ? 0.0 : 1.0;
}

TEST(TermFamilyTest, EveryFormHasItsFamilyUnderItsStoredName) {
  std::set<std::string> names;
  ASSERT_EQ(AllTermFamilies().size(), std::size(kEveryForm));
  for (TermForm f : kEveryForm) {
    const TermFamily& family = FamilyOf(f);
    EXPECT_EQ(family.form(), f);
    EXPECT_TRUE(names.insert(family.name()).second) << family.name();
    TermForm back = TermForm::kCell;
    ASSERT_TRUE(ParseTermForm(TermFormName(f), &back)) << TermFormName(f);
    EXPECT_EQ(back, f);
    EXPECT_EQ(FamilyNamed(family.name()), &family);
  }
  EXPECT_EQ(FamilyNamed("quadratic"), nullptr);
  TermForm untouched = TermForm::kFlag;
  EXPECT_FALSE(ParseTermForm("quadratic", &untouched));
  EXPECT_EQ(untouched, TermForm::kFlag);
  // The four measurement families and no other.
  int measurement = 0;
  for (const TermFamily* f : AllTermFamilies()) measurement += f->measurement();
  EXPECT_EQ(measurement, 4);
  // One additive family (wear per coil), not on the reading's side.
  int additive = 0;
  for (const TermFamily* f : AllTermFamilies()) {
    additive += f->additive();
    EXPECT_FALSE(f->additive() && f->measurement()) << f->name();
  }
  EXPECT_EQ(additive, 1);
}

TEST(TermFamilyTest, DerivativesAreThoseOfTheValue) {
  for (TermForm f : kEveryForm) {
    const ModelTerm t = TermOf(f);
    const int n = t.NumParams();
    ASSERT_GT(n, 0) << TermFormName(f);
    // Points inside bins and levels (away from the edges, where the binned
    // forms jump).
    for (double z : {0.0, 1.0, 2.0, 3.0, 4.7}) {
      std::vector<double> grad(n, 99.0);
      Value(t, z, grad.data());
      for (int j = 0; j < n; ++j) {
        const double h = 1e-6;
        ModelTerm up = t, down = t;
        up.params[j] += h;
        down.params[j] -= h;
        const double numeric =
            (Value(up, z, nullptr) - Value(down, z, nullptr)) / (2 * h);
        EXPECT_NEAR(grad[j], numeric, 1e-6 * (1 + std::abs(numeric)))
            << TermFormName(f) << " z=" << z << " param " << j;
      }
    }
  }
}

TEST(TermFamilyTest, ATermActsOnlyOnItsSideAndAMissingValueLeavesAllAsIs) {
  for (TermForm f : kEveryForm) {
    const ModelTerm t = TermOf(f);
    std::vector<double> grad(t.NumParams(), 5.0);
    // The sides a term does not act on: neutral, with no derivative.
    if (t.IsMeasurementTerm() || t.IsAdditiveTerm()) {
      EXPECT_EQ(TermMultiplier(t, 3.0, grad.data()), 1.0) << TermFormName(f);
      for (double g : grad) EXPECT_EQ(g, 0.0) << TermFormName(f);
    }
    if (!t.IsMeasurementTerm()) {
      grad.assign(t.NumParams(), 5.0);
      EXPECT_EQ(TermOffset(t, 3.0, grad.data()), 0.0) << TermFormName(f);
      for (double g : grad) EXPECT_EQ(g, 0.0) << TermFormName(f);
    }
    if (!t.IsAdditiveTerm()) {
      grad.assign(t.NumParams(), 5.0);
      EXPECT_EQ(TermAddend(t, 3.0, grad.data()), 0.0) << TermFormName(f);
      for (double g : grad) EXPECT_EQ(g, 0.0) << TermFormName(f);
    }
    grad.assign(t.NumParams(), 5.0);
    EXPECT_EQ(Value(t, std::nan(""), grad.data()), Neutral(t));
    for (double g : grad) EXPECT_EQ(g, 0.0) << TermFormName(f);
  }
  // Wear per coil: a on every pass, whatever the coil count before it.
  EXPECT_EQ(TermAddend(TermOf(TermForm::kPerCoil), 0.0, nullptr), 0.3);
  EXPECT_EQ(TermAddend(TermOf(TermForm::kPerCoil), 140.0, nullptr), 0.3);
  // The values of a few forms at hand-computed points.
  EXPECT_NEAR(TermMultiplier(TermOf(TermForm::kLogLinear), 3.5, nullptr),
              std::exp(0.3 * (3.5 - 2.0) / 1.5), 1e-15);
  EXPECT_NEAR(TermMultiplier(TermOf(TermForm::kPower), 4.0, nullptr),
              std::pow(4.0 / 2.0, 0.3), 1e-15);
  EXPECT_NEAR(TermMultiplier(TermOf(TermForm::kSaturating), 6.0, nullptr),
              1 + 0.4 * (1 - std::exp(-2.0)), 1e-15);
  // Offset by level, reference 2: level 3 is the third parameter.
  EXPECT_NEAR(TermOffset(TermOf(TermForm::kOffsetPerLevel), 3.0, nullptr),
              0.3 - 0.17 * 2, 1e-15);
  EXPECT_EQ(TermOffset(TermOf(TermForm::kOffsetPerLevel), 2.0, nullptr), 0.0);
}

// The term fits compute u(z) once per pass for the exponential families
// and then only exp(b u): the same bits as the family's own multiplier.
TEST(TermFamilyTest, AnExponentialFamilyIsExpOfItsExponent) {
  std::set<TermForm> exponential;
  for (TermForm f : kEveryForm) {
    const TermFamily& family = FamilyOf(f);
    if (!family.exponential()) continue;
    exponential.insert(f);
    const ModelTerm t = TermOf(f);
    ASSERT_EQ(t.NumParams(), 1) << family.name();
    for (double z : {0.0, 0.5, 1.0, 3.0, 7.5}) {
      EXPECT_EQ(TermMultiplier(t, z, nullptr),
                std::exp(t.params[0] * family.Exponent(t, z)))
          << family.name() << " z=" << z;
    }
  }
  EXPECT_EQ(exponential,
            (std::set<TermForm>{TermForm::kLogLinear, TermForm::kPower,
                                TermForm::kFlag}));
}

TEST(TermFamilyTest, EachFamilyKeepsItsOwnStoredRules) {
  for (TermForm f : kEveryForm) {
    EXPECT_FALSE(FamilyOf(f).CheckStored(TermOf(f)).has_value())
        << TermFormName(f);
  }
  struct Case {
    TermForm form;
    void (*edit)(ModelTerm*);
    const char* field;
  };
  const Case cases[] = {
      {TermForm::kPower, [](ModelTerm* t) { t->center = 0; }, "center"},
      {TermForm::kRollEffect, [](ModelTerm* t) { t->covariate = "z"; }, "form"},
      {TermForm::kLogLinear, [](ModelTerm* t) { t->covariate = kRollIdName; },
       "form"},
      {TermForm::kRollEffect, [](ModelTerm* t) { t->levels = {"R1"}; },
       "levels"},
      {TermForm::kCell, [](ModelTerm* t) { t->level_sd = {0.1}; }, "level_sd"},
      {TermForm::kFlag, [](ModelTerm* t) { t->reference_level = 1; },
       "reference_level"},
      {TermForm::kOffsetPerLevel, [](ModelTerm* t) { t->reference_level = 4; },
       "reference_level"},
      {TermForm::kOffsetPerLevel, [](ModelTerm* t) { t->level_readings = {1}; },
       "level_sd"},
      {TermForm::kPerCoil, [](ModelTerm* t) { t->params = {-0.1}; }, "params"},
      {TermForm::kHinge, [](ModelTerm* t) { t->scale = 0; }, "scale"},
      {TermForm::kPerCoil,
       [](ModelTerm* t) { t->covariate = "campaign_length_before_m"; },
       "covariate"},
  };
  for (const Case& c : cases) {
    ModelTerm t = TermOf(c.form);
    c.edit(&t);
    const std::optional<TermFieldError> e = FamilyOf(c.form).CheckStored(t);
    ASSERT_TRUE(e.has_value()) << TermFormName(c.form) << " " << c.field;
    EXPECT_EQ(e->field, c.field) << e->message;
  }
}

// A family words a finding of its term: the levels it names are those more
// than 2 standard errors from the reference, every level without them.
TEST(TermFamilyTest, AFamilyWordsItsFindingAndNamesOnlyClearLevels) {
  ModelTerm t = TermOf(TermForm::kPerLevel);  // params 0.3, 0.13, -0.04
  t.levels = {"A", "B", "C", "D"};
  const std::map<std::string, double> se = {
      {"param0", 0.05}, {"param1", 0.1}, {"param2", 0.01}};
  TermWordingInput in;
  in.readable = [](double v) { return WordFormat("%.1f u", v); };
  in.std_errors = &se;
  TermWording w;
  FamilyOf(TermForm::kPerLevel).Word(t, in, &w);
  EXPECT_EQ(w.shape, "per_level");
  ASSERT_TRUE(w.levels.has_value());
  EXPECT_EQ(*w.levels, (std::vector<std::string>{"B", "D"}));
  EXPECT_NEAR(w.parameters.at("level1_multiplier"), std::exp(0.3), 1e-15);
  EXPECT_EQ(w.fitted, "wear-rate multipliers 1.350 (B) 1.139 (C) 0.961 (D)");
  TermWordingInput bare = in;
  bare.std_errors = nullptr;  // no standard errors: every level is named
  FamilyOf(TermForm::kPerLevel).Word(t, bare, &w);
  EXPECT_EQ(w.levels->size(), 3u);

  ModelTerm o = TermOf(TermForm::kOffsetPerLevel);  // reference level 2
  o.covariate = "grinder";
  o.levels = {"G1", "G2", "G3", "G4"};
  o.params = {-15.2, 0.4, 9.0};
  const std::map<std::string, double> ose = {
      {"param0", 2.0}, {"param1", 2.0}, {"param2", 2.0}};
  in.std_errors = &ose;
  TermWording ow;
  FamilyOf(TermForm::kOffsetPerLevel).Word(o, in, &ow);
  EXPECT_FALSE(ow.up);
  EXPECT_EQ(*ow.levels, (std::vector<std::string>{"G1", "G4"}));
  EXPECT_EQ(ow.fitted,
            "the reading of grinder=G1 is offset by -15.2 µm; the reading of "
            "grinder=G4 is offset by +9.0 µm (reference grinder=G3)");

  ModelTerm l = TermOf(TermForm::kOffsetLinear);
  l.params = {-4.0};
  TermWording lw;
  FamilyOf(TermForm::kOffsetLinear).Word(l, in, &lw);
  EXPECT_EQ(lw.shape, "decreasing");
  EXPECT_FALSE(lw.up);
  EXPECT_FALSE(lw.levels.has_value());
  // The roll-effect family is worded by the diagnosis's per-roll stage.
  TermWording rw;
  FamilyOf(TermForm::kRollEffect).Word(TermOf(TermForm::kRollEffect), in, &rw);
  EXPECT_TRUE(rw.shape.empty());
  EXPECT_TRUE(rw.fitted.empty());
  EXPECT_TRUE(rw.mechanism.empty());
  // Wear per coil names its own physics, not its covariate's.
  const std::map<std::string, double> pse = {{"param0", 0.04}};
  in.std_errors = &pse;
  TermWording pw;
  FamilyOf(TermForm::kPerCoil).Word(TermOf(TermForm::kPerCoil), in, &pw);
  EXPECT_EQ(pw.mechanism, "wear_per_coil");
  EXPECT_NE(pw.mechanism_text.find("number of coils"), std::string::npos);
  EXPECT_EQ(pw.parameters.at("um_per_coil"), 0.3);
  EXPECT_EQ(pw.fitted,
            "0.3 µm of wear per coil (standard error 0.04) on each roll it "
            "covers, whatever the coil's length and load");
  EXPECT_TRUE(FamilyOf(TermForm::kPerCoil).names_mechanism());
  EXPECT_FALSE(FamilyOf(TermForm::kSaturating).names_mechanism());
}

// The forms the families propose over a covariate, in the registry's order.
std::vector<TermForm> ProposedForms(const CovariateSummary& c) {
  std::vector<TermForm> forms;
  for (const TermFamily* f : AllTermFamilies()) {
    std::vector<TermProposal> p;
    f->Propose(c, &p);
    for (const TermProposal& one : p) {
      EXPECT_EQ(one.term.form, f->form());
      EXPECT_EQ(one.term.covariate, c.spec->name);
      EXPECT_EQ(static_cast<int>(one.term.params.size()), one.term.NumParams())
          << f->name();
      EXPECT_EQ(one.lower.size(), one.term.params.size()) << f->name();
      for (size_t j = 0; j < one.lower.size(); ++j) {
        EXPECT_LE(one.lower[j], one.term.params[j]) << f->name();
        EXPECT_GE(one.upper[j], one.term.params[j]) << f->name();
      }
      forms.push_back(one.term.form);
    }
  }
  return forms;
}

TEST(TermFamilyTest, EachFamilyProposesOnlyOverTheCovariatesItFits) {
  CovariateSpec length{"campaign_length_before_m",
                       CovariateSource::kLengthBefore, CovariateLevel::kPass,
                       CovariateKind::kNumeric};
  length.accumulates = true;
  CovariateSummary c;
  c.spec = &length;
  c.p01 = 200;
  c.p05 = 1000;
  c.p50 = 40000;
  c.p95 = 90000;
  c.mean = 42000;
  c.sd = 25000;
  c.max = 110000;
  c.edges = {10000, 30000, 60000};
  using F = TermForm;
  EXPECT_EQ(ProposedForms(c),
            (std::vector<F>{F::kLogLinear, F::kPower, F::kBinned,
                            F::kSaturating, F::kDecaying}));
  // The coil count: the same forms and wear per coil, from a = 0.
  CovariateSpec coils{"campaign_coils_before", CovariateSource::kCoilsBefore,
                      CovariateLevel::kPass, CovariateKind::kNumeric};
  coils.accumulates = true;
  CovariateSummary n = c;
  n.spec = &coils;
  EXPECT_EQ(ProposedForms(n),
            (std::vector<F>{F::kLogLinear, F::kPower, F::kBinned,
                            F::kSaturating, F::kDecaying, F::kPerCoil}));
  std::vector<TermProposal> per_coil;
  FamilyOf(F::kPerCoil).Propose(n, &per_coil);
  ASSERT_EQ(per_coil.size(), 1u);
  EXPECT_EQ(per_coil[0].term.params, std::vector<double>{0.0});
  EXPECT_EQ(per_coil[0].lower, std::vector<double>{0.0});
  // From zero (no power form), not accumulating (no growth or run-in, but
  // a knee above and one below which the rate changes), its bins' last
  // edge at its largest value (no binned form).
  length.accumulates = false;
  c.p01 = 0;
  c.edges = {10000, 110000};
  EXPECT_EQ(ProposedForms(c),
            (std::vector<F>{F::kLogLinear, F::kHinge, F::kHinge}));
  std::vector<TermProposal> hinges;
  FamilyOf(F::kHinge).Propose(c, &hinges);
  ASSERT_EQ(hinges.size(), 2u);
  EXPECT_GT(hinges[0].term.scale, 0);  // above the knee
  EXPECT_LT(hinges[1].term.scale, 0);  // below it
  EXPECT_EQ(hinges[0].lower[1], c.p05);
  EXPECT_EQ(hinges[0].upper[1], c.p95);
  // On the reading's side.
  CovariateSpec cooling{"cooling_h", CovariateSource::kCoolingHours,
                        CovariateLevel::kMeasurement, CovariateKind::kNumeric};
  c.spec = &cooling;
  c.edges = {10, 20, 30};
  c.p50 = 15;
  EXPECT_EQ(
      ProposedForms(c),
      (std::vector<F>{F::kOffsetLinear, F::kOffsetBinned, F::kOffsetDecay}));
  // A grinder column: one offset candidate per level with readings, each
  // with that level as the reference.
  CovariateSpec grinder{"grinder", CovariateSource::kMeasurementExtraFactor,
                        CovariateLevel::kMeasurement, CovariateKind::kFactor};
  grinder.levels = {"G1", "G2", "G3"};
  CovariateSummary g;
  g.spec = &grinder;
  g.levels = 3;
  g.level_weight = {10, 0, 7};
  std::vector<TermProposal> p;
  FamilyOf(F::kOffsetPerLevel).Propose(g, &p);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[0].term.reference_level, 0);
  EXPECT_EQ(p[1].term.reference_level, 2);
  EXPECT_EQ(p[1].term.levels, grinder.levels);
  EXPECT_EQ(ProposedForms(g),
            (std::vector<F>{F::kOffsetPerLevel, F::kOffsetPerLevel}));
  grinder.level = CovariateLevel::kRoll;  // a factor of the roll: per-level
  EXPECT_EQ(ProposedForms(g), (std::vector<F>{F::kPerLevel}));
  CovariateSpec lube{"lubrication", CovariateSource::kLubrication,
                     CovariateLevel::kPass, CovariateKind::kFlag};
  CovariateSummary l;
  l.spec = &lube;
  EXPECT_EQ(ProposedForms(l), (std::vector<F>{F::kFlag}));
}

// Which bounds of the diagnosis's box are limits of a family's shape (a fit
// there is still the family's) and which are brackets (at_box_bound): the
// families with a parameter per level or bin are not checked; every other
// family has a bracket the check reads, and its shape's own limits.
TEST(TermFamilyTest, ABoundIsALimitOnlyWhereTheShapeGoesOn) {
  const std::set<TermForm> per_level = {
      TermForm::kBinned, TermForm::kPerLevel, TermForm::kOffsetBinned,
      TermForm::kOffsetPerLevel, TermForm::kRollEffect};
  for (TermForm f : kEveryForm) {
    const TermFamily& family = FamilyOf(f);
    const ModelTerm t = TermOf(f);
    int brackets = 0;
    for (int j = 0; j < std::min(t.NumParams(), 2); ++j) {
      for (bool upper : {false, true})
        brackets += family.BoundIsALimit(j, upper) ? 0 : 1;
    }
    if (per_level.count(f) > 0 || f == TermForm::kSaturating) {
      EXPECT_EQ(brackets, 0) << family.name();
    } else {
      EXPECT_GT(brackets, 0) << family.name();
    }
  }
  // Decaying: b = 10 is a bracket; m >= 0.1 and the length scale are not.
  EXPECT_FALSE(FamilyOf(TermForm::kDecaying).BoundIsALimit(0, true));
  EXPECT_TRUE(FamilyOf(TermForm::kDecaying).BoundIsALimit(0, false));
  EXPECT_TRUE(FamilyOf(TermForm::kDecaying).BoundIsALimit(1, true));
  // The offset-decay's shortest time constant is a step; its longest a
  // constant offset on every reading.
  EXPECT_TRUE(FamilyOf(TermForm::kOffsetDecay).BoundIsALimit(1, false));
  EXPECT_FALSE(FamilyOf(TermForm::kOffsetDecay).BoundIsALimit(1, true));
  EXPECT_TRUE(FamilyOf(TermForm::kPerCoil).BoundIsALimit(0, false));
  EXPECT_FALSE(FamilyOf(TermForm::kPerCoil).BoundIsALimit(0, true));
}

// A fit stopped at a bracket of its box is reported with the parameter as
// the family's formula names it (AtBoxBound's reason): every parameter
// that has a bracket is named, and one fitted on a log scale is shown as
// the formula's quantity, the one at which the formula takes its value.
TEST(TermFamilyTest, AParameterIsShownOnItsFormulasScale) {
  for (TermForm f : kEveryForm) {
    const TermFamily& family = FamilyOf(f);
    const ModelTerm t = TermOf(f);
    for (int j = 0; j < std::min(t.NumParams(), 2); ++j) {
      if (family.BoundIsALimit(j, false) && family.BoundIsALimit(j, true)) {
        continue;
      }
      EXPECT_NE(family.Param(j, 0.1).name.rfind("parameter ", 0), 0u)
          << family.name() << " " << j;
    }
  }
  // The time constants: at z = lam (tau) the formula is at 1 - e^-1 (e^-1)
  // of its amplitude.
  for (TermForm f :
       {TermForm::kSaturating, TermForm::kDecaying, TermForm::kOffsetDecay}) {
    const ModelTerm t = TermOf(f);  // amplitude params[0], scale 3
    const TermParamView scale = FamilyOf(f).Param(1, t.params[1]);
    EXPECT_NEAR(scale.value, 3.0, 1e-12) << FamilyOf(f).name();
    const double fraction =
        f == TermForm::kSaturating ? 1 - std::exp(-1.0) : std::exp(-1.0);
    const double base = f == TermForm::kOffsetDecay ? 0.0 : 1.0;
    EXPECT_NEAR(Value(t, scale.value, nullptr), base + t.params[0] * fraction,
                1e-12)
        << FamilyOf(f).name();
  }
  // A flag's and a cell's multiplier is the wear-rate ratio itself.
  ModelTerm flag = TermOf(TermForm::kFlag);
  flag.params = {std::log(1.3)};
  EXPECT_NEAR(FamilyOf(TermForm::kFlag).Param(0, flag.params[0]).value, 1.3,
              1e-12);
  EXPECT_NEAR(Value(flag, 1.0, nullptr), 1.3, 1e-12);
  EXPECT_NEAR(FamilyOf(TermForm::kCell).Param(0, std::log(0.8)).value, 0.8,
              1e-12);
}

TEST(TermFamilyTest, RefitBoxesHoldTheAdoptedParameters) {
  for (TermForm f : kEveryForm) {
    const ModelTerm t = TermOf(f);
    std::vector<double> lo, hi;
    FamilyOf(f).RefitBounds(t, &lo, &hi);
    ASSERT_EQ(static_cast<int>(lo.size()), t.NumParams()) << TermFormName(f);
    ASSERT_EQ(hi.size(), lo.size());
    for (size_t j = 0; j < lo.size(); ++j) {
      EXPECT_LT(lo[j], t.params[j]) << TermFormName(f) << " " << j;
      EXPECT_GT(hi[j], t.params[j]) << TermFormName(f) << " " << j;
    }
  }
  // A length scale moves within a factor 20 of the adopted one.
  std::vector<double> lo, hi;
  FamilyOf(TermForm::kSaturating)
      .RefitBounds(TermOf(TermForm::kSaturating), &lo, &hi);
  EXPECT_NEAR(std::exp(hi[1]) / 3.0, 20.0, 1e-9);
  EXPECT_NEAR(3.0 / std::exp(lo[1]), 20.0, 1e-9);
  EXPECT_EQ(FamilyOf(TermForm::kCell).PriorSd(TermOf(TermForm::kCell)),
            kCellPriorSd);
  EXPECT_EQ(
      FamilyOf(TermForm::kRollEffect).PriorSd(TermOf(TermForm::kRollEffect)),
      1.5);
  EXPECT_EQ(
      FamilyOf(TermForm::kLogLinear).PriorSd(TermOf(TermForm::kLogLinear)),
      0.0);
}

}  // namespace
}  // namespace rollwear
