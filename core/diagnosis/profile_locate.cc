#include "core/diagnosis/profile_locate.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include "core/base/distributions.h"
#include "core/fit/profile_fit.h"

namespace rollwear {
namespace {

// Zone sums of one roll: operator edge, operator body, drive body, drive
// edge (index as in BarrelLocate).
struct RollZones {
  int stand = 0;
  double sum[4] = {0, 0, 0, 0};
  int n[4] = {0, 0, 0, 0};

  // Mean residual over the zones in `mask` (bit z = zone z); NaN if none.
  double Mean(unsigned mask) const {
    double s = 0;
    int k = 0;
    for (int z = 0; z < 4; ++z) {
      if (mask & (1u << z)) {
        s += sum[z];
        k += n[z];
      }
    }
    return k > 0 ? s / k : std::nan("");
  }
};

constexpr unsigned kEdges = 0b1001, kBody = 0b0110;
constexpr unsigned kOperator = 0b0011, kDrive = 0b1100;

// One-sample t test of the per-roll contrasts Mean(first) - Mean(second)
// over the rolls `keep` accepts.
template <typename Keep>
BarrelContrast Contrast(std::string dimension, std::string where,
                        const std::vector<RollZones>& rolls, unsigned first,
                        unsigned second, Keep keep) {
  BarrelContrast c;
  c.dimension = std::move(dimension);
  c.where = std::move(where);
  std::vector<double> d;
  for (const RollZones& r : rolls) {
    if (!keep(r)) continue;
    const double v = r.Mean(first) - r.Mean(second);
    if (std::isfinite(v)) d.push_back(v);
  }
  c.n_rolls = static_cast<int>(d.size());
  if (d.size() < 3) return c;
  double mean = 0;
  for (double v : d) mean += v;
  mean /= static_cast<double>(d.size());
  double ss = 0;
  for (double v : d) ss += (v - mean) * (v - mean);
  c.mean_um = mean;
  c.sd_um = std::sqrt(ss / static_cast<double>(d.size() - 1));
  if (c.sd_um <= 0) return c;
  c.t = mean / (c.sd_um / std::sqrt(static_cast<double>(d.size())));
  c.p_value = StudentTTwoSided(c.t, static_cast<double>(d.size() - 1));
  return c;
}

}  // namespace

bool BarrelLocate::any_significant() const {
  return std::any_of(contrasts.begin(), contrasts.end(),
                     [](const BarrelContrast& c) { return c.significant; });
}

StatusOr<BarrelLocate> LocateAlongBarrel(
    const WearModel& model, const Dataset& data, const DatasetIndex& index,
    const CampaignSplit& split, double alpha,
    const DiagnosisThresholds& thresholds) {
  ROLLWEAR_ASSIGN_OR_RETURN(const ProfileFit fit,
                            FitProfileShape(model, data, index, split));
  std::vector<int> all = split.train;
  all.insert(all.end(), split.validation.begin(), split.validation.end());
  std::sort(all.begin(), all.end());
  // Each roll's own scale first: its profile's least-squares factor
  // a_r = sum m p / sum p^2 over its zone points takes out the roll's
  // multiplicative scatter (its own K), which would otherwise swamp the
  // contrasts; what is left is the profile's shape against the model's.
  std::map<std::pair<int, int>, std::vector<ProfileResidual>> points;
  for (ProfileResidual& r : ProfileResiduals(model, fit.shape, data, index, all)) {
    if (r.edge || r.body) points[{r.campaign, r.slot}].push_back(r);
  }
  BarrelLocate out;
  std::map<std::pair<int, int>, RollZones> by_roll;
  double ss = 0;
  double zone_sum[4] = {0, 0, 0, 0};
  int zone_n[4] = {0, 0, 0, 0};
  for (const auto& [key, roll_points] : points) {
    double mp = 0, pp = 0;
    for (const ProfileResidual& r : roll_points) {
      mp += r.measured_um * r.predicted_um;
      pp += r.predicted_um * r.predicted_um;
    }
    const double scale = pp > 0 ? mp / pp : 1;
    RollZones& roll = by_roll[key];
    roll.stand = SlotStand(key.second);
    for (const ProfileResidual& r : roll_points) {
      const bool drive = r.x_mm > 0;
      const int z = r.edge ? (drive ? 3 : 0) : (drive ? 2 : 1);
      const double e = r.measured_um - scale * r.predicted_um;
      roll.sum[z] += e;
      ++roll.n[z];
      zone_sum[z] += e;
      ++zone_n[z];
      ss += e * e;
      ++out.n_points;
    }
  }
  std::vector<RollZones> rolls;
  std::set<int> stands;
  for (const auto& [key, roll] : by_roll) {
    rolls.push_back(roll);
    stands.insert(roll.stand);
  }
  out.n_rolls = static_cast<int>(rolls.size());
  double* means[4] = {&out.edge_operator_um, &out.body_operator_um,
                      &out.body_drive_um, &out.edge_drive_um};
  for (int z = 0; z < 4; ++z) {
    *means[z] = zone_n[z] > 0 ? zone_sum[z] / zone_n[z] : std::nan("");
  }
  const auto every = [](const RollZones&) { return true; };
  out.contrasts.push_back(
      Contrast("barrel_zone", "strip-edge zones", rolls, kEdges, kBody, every));
  out.contrasts.push_back(Contrast("body_side", "drive-side body", rolls,
                                   kDrive & kBody, kOperator & kBody, every));
  out.contrasts.push_back(Contrast("edge_side", "drive-side edge", rolls,
                                   0b1000, 0b0001, every));
  if (stands.size() > 1) {
    for (int s : stands) {
      const std::string name = "F" + std::to_string(s);
      out.contrasts.push_back(
          Contrast("barrel_zone@" + name, "strip-edge zones at " + name, rolls,
                   kEdges, kBody, [s](const RollZones& r) { return r.stand == s; }));
    }
  }
  // A side contrast names the side that reads more than predicted.
  for (BarrelContrast& c : out.contrasts) {
    if (c.mean_um < 0 && c.dimension == "body_side") {
      c.where = "operator-side body";
    }
    if (c.mean_um < 0 && c.dimension == "edge_side") {
      c.where = "operator-side edge";
    }
  }
  out.point_sd_um = out.n_points > 0 ? std::sqrt(ss / out.n_points) : 0;
  const double level = alpha / static_cast<double>(out.contrasts.size());
  for (BarrelContrast& c : out.contrasts) {
    c.significant =
        c.p_value < level && c.sd_um > 0 &&
        std::abs(c.mean_um) >= thresholds.barrel_min_effect * c.sd_um &&
        std::abs(c.mean_um) >= thresholds.barrel_material * out.point_sd_um;
  }
  std::stable_sort(out.contrasts.begin(), out.contrasts.end(),
                   [](const BarrelContrast& a, const BarrelContrast& b) {
                     return a.p_value < b.p_value;
                   });
  return out;
}

}  // namespace rollwear
