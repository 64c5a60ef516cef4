// Tail probabilities of the chi-square, Student t and F distributions, for
// the diagnosis engine's likelihood-ratio and breakdown tests.
//
// Computed from the regularised incomplete gamma and beta functions by their
// series and Lentz continued fractions (Press et al., Numerical Recipes,
// 3rd ed., sections 6.2 and 6.4; Abramowitz & Stegun 6.5 and 26.5).
//
// Thread-safety: pure functions.
#ifndef ROLLWEAR_CORE_BASE_DISTRIBUTIONS_H_
#define ROLLWEAR_CORE_BASE_DISTRIBUTIONS_H_

namespace rollwear {

// Q(a, x) = Gamma(a, x) / Gamma(a), upper regularised incomplete gamma.
double RegularizedGammaQ(double a, double x);
// I_x(a, b), regularised incomplete beta.
double RegularizedBeta(double x, double a, double b);

// P(X >= x) for X ~ chi-square with k degrees of freedom.
double ChiSquareSurvival(double x, double k);
// Two-sided P(|T| >= |t|) for T ~ Student t with nu degrees of freedom.
double StudentTTwoSided(double t, double nu);
// P(F >= f) for F ~ F(d1, d2).
double FSurvival(double f, double d1, double d2);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_BASE_DISTRIBUTIONS_H_
