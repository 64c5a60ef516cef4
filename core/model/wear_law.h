// The three Archard-type wear laws at the barrel centre (x = 0), written as
//   wear_um(pass) = K * Load(law, pass, roll)
// so that K is the only coefficient for Wang and Nikitenko; Cao carries the
// stress exponent `a` inside the load.
//
//   Wang:      Load = (F/w) * L                     [kN/mm * km]
//   Nikitenko: Load = P(0) * L / (pi * D * HB),     P(0) = F/w
//                                                   [kN/mm * mm / (mm * HB)]
//   Cao:       Load = L * lc / D * (F / (w * lc))^a [m * 1 * (kN/mm^2)^a]
//              lc = sqrt(D/2 * (h_entry - h_exit))  (contact length, mm)
//
// F force (kN), w strip width (mm), L rolled length, D roll diameter (mm),
// HB surface Brinell hardness. The unit choices (km for Wang, mm for
// Nikitenko, m for Cao) make K of order 0.1..1 for a hot strip finishing
// mill, so the study's "all ones" initial set is a sensible start.
// Sources: the rollwear study (design brief), after Wang et al., Nikitenko
// et al. and Cao et al.; see docs/model.md.
//
// Thread-safety: pure functions.
#ifndef ROLLWEAR_CORE_MODEL_WEAR_LAW_H_
#define ROLLWEAR_CORE_MODEL_WEAR_LAW_H_

#include <cmath>
#include <string>

namespace rollwear {

enum class WearLaw { kWang = 0, kNikitenko = 1, kCao = 2 };

const char* WearLawName(WearLaw law);  // "wang", "nikitenko", "cao"
bool ParseWearLaw(const std::string& name, WearLaw* out);

// What a wear law needs of one pass and the roll it acts on.
struct PassLoadInput {
  double force_kn;
  double width_mm;
  double length_m;
  double entry_thickness_mm;
  double exit_thickness_mm;
  double diameter_mm;
  double hardness_hb;
};

constexpr double kPi = 3.14159265358979323846;

// Parameter-free part of the load. For Wang and Nikitenko this is the whole
// load; for Cao it is L*lc/D and the stress factor is applied by CaoStress.
inline double BaseLoad(WearLaw law, const PassLoadInput& in) {
  const double p0 = in.force_kn / in.width_mm;  // kN/mm
  switch (law) {
    case WearLaw::kWang:
      return p0 * in.length_m * 1e-3;
    case WearLaw::kNikitenko:
      return p0 * in.length_m * 1e3 / (kPi * in.diameter_mm * in.hardness_hb);
    case WearLaw::kCao: {
      const double lc = std::sqrt(in.diameter_mm / 2 *
                                  (in.entry_thickness_mm - in.exit_thickness_mm));
      return in.length_m * lc / in.diameter_mm;
    }
  }
  return 0;
}

// Cao: mean contact stress F/(w*lc) in kN/mm^2 (= GPa); 1 for other laws.
inline double CaoStress(const PassLoadInput& in) {
  const double lc = std::sqrt(in.diameter_mm / 2 *
                              (in.entry_thickness_mm - in.exit_thickness_mm));
  return in.force_kn / (in.width_mm * lc);
}

// Full load for exponent a (a ignored unless law is Cao).
inline double Load(WearLaw law, const PassLoadInput& in, double a) {
  const double base = BaseLoad(law, in);
  if (law != WearLaw::kCao) return base;
  return base * std::pow(CaoStress(in), a);
}

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_WEAR_LAW_H_
