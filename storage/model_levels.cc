#include "storage/model_levels.h"

#include <utility>

namespace rollwear::storage {

StatusOr<WearModel> PriorModel(WearLaw law, int option,
                               std::vector<std::string> positions,
                               double initial_k) {
  WearModel m;
  ROLLWEAR_ASSIGN_OR_RETURN(
      m.structure, KStructure::ForOption(option, std::move(positions), {}, {}));
  m.law = law;
  m.k.assign(m.structure.num_coefficients(), 1.0);
  const FactorGroup& kf = m.structure.groups().front();  // kF comes first
  for (int i = 0; i < kf.size; ++i) m.k[kf.offset + i] = initial_k;
  m.cao_exponent = 1.0;
  // Uncalibrated: K is a typical value, not a fit, so the prediction
  // interval must say so. K of hot strip finishing work rolls spans about a
  // factor of two between mills, roll grades and steel grades; a 50 %
  // relative sd (95 % interval about ±100 %) states that honestly.
  m.noise_rel = 0.5;
  return m;
}

StatusOr<WearModel> ModelOverLevels(const WearModel& model,
                                    std::vector<std::string> positions,
                                    std::vector<std::string> roll_types,
                                    std::vector<std::string> grades) {
  if (model.is_ann()) {
    return Status::InvalidArgument(
        "the recurrent network has no K coefficients to re-express over levels");
  }
  WearModel out;
  ROLLWEAR_ASSIGN_OR_RETURN(
      out.structure,
      KStructure::ForOption(model.structure.option(), std::move(positions),
                            std::move(roll_types), std::move(grades)));
  out.law = model.law;
  out.cao_exponent = model.cao_exponent;
  out.noise_sd_um = model.noise_sd_um;
  out.noise_rel = model.noise_rel;
  out.terms = model.terms;
  const int n = out.structure.num_coefficients();
  out.k.assign(n, 1.0);
  bool same = n == model.structure.num_coefficients();
  for (int i = 0; i < n; ++i) {
    const int j =
        model.structure.CoefficientIndex(out.structure.CoefficientName(i));
    if (j >= 0) out.k[i] = model.k[j];
    same = same && j == i;
  }
  if (same) out.covariance = model.covariance;
  return out;
}

}  // namespace rollwear::storage
