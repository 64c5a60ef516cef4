#include "core/model/barrel_profile.h"

#include <algorithm>
#include <cmath>

namespace rollwear {

int ProfileGrid::slices() const {
  const int half = static_cast<int>(std::floor(barrel_mm / 2 / slice_mm + 1e-9));
  return 2 * half + 1;
}

double ProfileGrid::x(int j) const {
  return (j - (slices() - 1) / 2) * slice_mm;
}

void ProfileGrid::Bracket(double x_mm, int* j, double* t) const {
  const int n = slices();
  const double pos = x_mm / slice_mm + (n - 1) / 2;
  *t = 0;
  if (pos <= 0) {
    *j = 0;
  } else if (pos >= n - 1) {
    *j = n - 1;
  } else {
    *j = static_cast<int>(std::floor(pos));
    *t = pos - *j;
  }
}

double ProfileGrid::Interpolate(const std::vector<double>& values,
                                double x_mm) const {
  int j = 0;
  double t = 0;
  Bracket(x_mm, &j, &t);
  if (t == 0) return values[j];
  return values[j] * (1 - t) + values[j + 1] * t;
}

std::array<double, kProfileBasis> ProfileShape::Coefficients() const {
  return {1, beta2, beta4, alpha[0], alpha[1], alpha[2]};
}

double StripCentreMm(bool top_roll, double shift_mm) {
  return top_roll ? -shift_mm : shift_mm;
}

std::array<double, kProfileBasis> ProfileBasis(double u_mm,
                                               double half_width_mm) {
  std::array<double, kProfileBasis> basis{};
  const double a = std::abs(u_mm);
  if (a > half_width_mm) return basis;
  const double r2 = (u_mm / half_width_mm) * (u_mm / half_width_mm);
  basis[0] = 1;
  basis[1] = r2;
  basis[2] = r2 * r2;
  const double d = half_width_mm - a;  // distance to the nearer edge
  for (int m = 0; m < kEdgeRamps; ++m) {
    const double ramp = 1 - d / kEdgeRampMm[m];
    basis[3 + m] = ramp > 0 ? ramp * ramp : 0;
  }
  return basis;
}

double Distribution(const ProfileShape& shape, double u_mm,
                    double half_width_mm) {
  const auto basis = ProfileBasis(u_mm, half_width_mm);
  const auto coef = shape.Coefficients();
  double g = 0;
  for (int i = 0; i < kProfileBasis; ++i) g += coef[i] * basis[i];
  return g;
}

namespace {

// The slices whose centres lie under the strip: [first, last].
std::pair<int, int> CoveredSlices(const ProfileGrid& grid, double centre_mm,
                                  double half_width_mm) {
  const int n = grid.slices();
  const double offset = (n - 1) / 2;
  const int first = std::max(
      0, static_cast<int>(std::ceil((centre_mm - half_width_mm) / grid.slice_mm +
                                    offset - 1e-12)));
  const int last = std::min(
      n - 1, static_cast<int>(std::floor(
                 (centre_mm + half_width_mm) / grid.slice_mm + offset + 1e-12)));
  return {first, last};
}

}  // namespace

void AddPassProfile(const ProfileGrid& grid, const ProfileShape& shape,
                    double wear_um, double centre_mm, double half_width_mm,
                    std::vector<double>* profile) {
  const auto [first, last] = CoveredSlices(grid, centre_mm, half_width_mm);
  for (int j = first; j <= last; ++j) {
    (*profile)[j] +=
        wear_um * Distribution(shape, grid.x(j) - centre_mm, half_width_mm);
  }
}

ProfileStats::ProfileStats(const ProfileGrid& grid)
    : grid_(grid), sums_(grid.slices()) {}

void ProfileStats::AddPass(double weight, double centre_mm,
                           double half_width_mm) {
  const auto [first, last] = CoveredSlices(grid_, centre_mm, half_width_mm);
  for (int j = first; j <= last; ++j) {
    const auto basis = ProfileBasis(grid_.x(j) - centre_mm, half_width_mm);
    for (int i = 0; i < kProfileBasis; ++i) sums_[j][i] += weight * basis[i];
  }
}

std::array<double, kProfileBasis> ProfileStats::At(double x_mm) const {
  int j = 0;
  double t = 0;
  grid_.Bracket(x_mm, &j, &t);
  if (t == 0) return sums_[j];
  std::array<double, kProfileBasis> out{};
  for (int i = 0; i < kProfileBasis; ++i) {
    out[i] = sums_[j][i] * (1 - t) + sums_[j + 1][i] * t;
  }
  return out;
}

std::vector<double> ProfileStats::Evaluate(const ProfileShape& shape) const {
  const auto coef = shape.Coefficients();
  std::vector<double> out(sums_.size(), 0.0);
  for (size_t j = 0; j < sums_.size(); ++j) {
    for (int i = 0; i < kProfileBasis; ++i) out[j] += coef[i] * sums_[j][i];
  }
  return out;
}

}  // namespace rollwear
