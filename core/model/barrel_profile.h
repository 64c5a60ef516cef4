// The wear profile across the barrel: the slicing model that spreads each
// pass's wear over the barrel slices the strip covers, with a body part and
// an edge part across the strip width, placed by the shift convention of the
// data format. The centre wear of the study's laws (wear_law.h) is one point
// of it.
//
// The study's laws (Eqs. 1-3) carry f(x), the distribution of the wear over
// the roll width, and set it aside; the profile models of its references
// [12] (John et al., 2006) and [14] (Wang et al., 2007) and the slicing
// models since ("Research on the Prediction of Roll Wear in a Strip Mill",
// Metals 14(10):1180, 2024) give each barrel slice the wear of the strip
// that runs over it. Here a pass p on a roll adds at slice
// centre x_j
//
//   w_j(p) = K_p * Load_p * g(u, b),   u = x_j - c_p,  b = width_mm / 2,
//   g(u, b) = 0                                           for |u| > b,
//   g(u, b) = 1 + beta2 (u/b)^2 + beta4 (u/b)^4
//               + sum_m alpha_m (1 - d / lambda_m)_+^2    for |u| <= b,
//
// with d = b - |u| the distance to the nearer strip edge, c_p the strip
// centreline on the roll (-shift_mm on the top roll, +shift_mm on the
// bottom one: pair shifting, data-format.md), and three fixed edge widths
// lambda_m = 15, 40, 100 mm. The body part (beta2, beta4) lets the worn
// body be flat (box wear) or crowned; the edge part rises towards the
// strip edges, where the strip is colder and its scale harder. Its shape
// is a free combination of three compact ramps rather than
// one exp(-d/lambda) with lambda fitted, so that g is linear in its six
// coefficients: per-campaign sufficient statistics (six sums per slice and
// K group, ProfileStats) then make a fit's cost independent of the number
// of strips, the derivatives are exact, and an edge rise of any width
// between about 10 and 150 mm is represented. g(0, b) = 1 for every shape
// whose ramps end before the strip centre (b > 100 mm, any real strip), so
// with all coefficients 0 (no profile data) every slice the strip covers
// wears exactly what the centre law says: the centre wear is unchanged.
//
// The barrel is sliced at kDefaultSliceMm = 10 mm: the narrowest edge ramp
// (15 mm) spans 1.5 slices, a grinder's profile is measured every 10 to
// 50 mm, and a 2,000 mm barrel is 201 slices - a pass's update is a few
// hundred multiply-adds, microseconds.
//
// Thread-safety: plain values and pure functions.
#ifndef ROLLWEAR_CORE_MODEL_BARREL_PROFILE_H_
#define ROLLWEAR_CORE_MODEL_BARREL_PROFILE_H_

#include <array>
#include <cstddef>
#include <vector>

namespace rollwear {

inline constexpr double kDefaultBarrelMm = 2000;
inline constexpr double kDefaultSliceMm = 10;
inline constexpr int kEdgeRamps = 3;
inline constexpr std::array<double, kEdgeRamps> kEdgeRampMm = {15, 40, 100};
// Coefficients of g: 1 (fixed), beta2, beta4, alpha_1..3.
inline constexpr int kProfileBasis = 3 + kEdgeRamps;

// Slice centres x_j = -half + j * slice, j = 0..n-1, symmetric about the
// barrel centre (x = 0 is a slice centre).
struct ProfileGrid {
  double barrel_mm = kDefaultBarrelMm;
  double slice_mm = kDefaultSliceMm;

  int slices() const;
  double x(int j) const;
  // Linear interpolation of per-slice values at barrel coordinate x
  // (clamped to the outermost slices).
  double Interpolate(const std::vector<double>& values, double x_mm) const;
  // The slice j and weight t in [0, 1] that Interpolate reads x_mm from:
  // value = values[j] (1 - t) + values[j + 1] t (t = 0 at the ends).
  void Bracket(double x_mm, int* j, double* t) const;
};

// The shape coefficients of g (all 0: uniform wear under the strip).
struct ProfileShape {
  double beta2 = 0;
  double beta4 = 0;
  std::array<double, kEdgeRamps> alpha = {0, 0, 0};

  // {1, beta2, beta4, alpha_1, alpha_2, alpha_3}.
  std::array<double, kProfileBasis> Coefficients() const;
};

// The strip centreline on a roll for a pass with `shift_mm`.
double StripCentreMm(bool top_roll, double shift_mm);

// The six basis values of g at offset u from the strip centre for a strip
// of half-width b (all 0 outside the strip).
std::array<double, kProfileBasis> ProfileBasis(double u_mm, double half_width_mm);

// g(u, b) for `shape`.
double Distribution(const ProfileShape& shape, double u_mm, double half_width_mm);

// Adds `wear_um` * g(x_j - centre, b) to every slice of `profile` (sized to
// grid.slices()): the daemon's per-pass update of a mounted roll.
void AddPassProfile(const ProfileGrid& grid, const ProfileShape& shape,
                    double wear_um, double centre_mm, double half_width_mm,
                    std::vector<double>* profile);

// Per-slice sufficient statistics of one group of passes (one roll in one
// campaign, one K group): s_j = sum_p weight_p * basis(x_j - c_p, b_p). The
// profile of the group for any shape is then coefficients . s_j, and its
// derivative with respect to a shape coefficient is that component of s_j.
class ProfileStats {
 public:
  explicit ProfileStats(const ProfileGrid& grid);

  void AddPass(double weight, double centre_mm, double half_width_mm);
  // sum_i coefficient_i * s_j[i] for every slice.
  std::vector<double> Evaluate(const ProfileShape& shape) const;
  const std::array<double, kProfileBasis>& slice(int j) const { return sums_[j]; }
  // The six sums at barrel coordinate x_mm, interpolated between slices as
  // ProfileGrid::Interpolate reads a profile (exact at slice centres).
  std::array<double, kProfileBasis> At(double x_mm) const;
  const ProfileGrid& grid() const { return grid_; }

 private:
  ProfileGrid grid_;
  std::vector<std::array<double, kProfileBasis>> sums_;
};

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_BARREL_PROFILE_H_
