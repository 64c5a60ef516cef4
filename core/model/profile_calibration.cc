#include "core/model/profile_calibration.h"

namespace rollwear {

const std::array<std::string, kProfileShapeParameters>& ProfileShapeNames() {
  static const std::array<std::string, kProfileShapeParameters> names = {
      "beta2", "beta4", "alpha1", "alpha2", "alpha3"};
  return names;
}

std::array<double, kProfileShapeParameters> ProfileShapeValues(
    const ProfileShape& shape) {
  return {shape.beta2, shape.beta4, shape.alpha[0], shape.alpha[1],
          shape.alpha[2]};
}

}  // namespace rollwear
