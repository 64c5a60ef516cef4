// Carriers of one mechanism (docs/diagnosis.md, "Carriers of one
// mechanism"): quantities that move together in every mill because one
// physical process sets them, so that a mismatch along one is, in most
// data, equally well described along the others. When the encompassing
// test (diagnosis_rivals.cc) cannot tell the winner from a rival and both
// carry the same mechanism, the mechanism is what the data show and it is
// named, with its carriers listed; rivals of different mechanisms stay
// "not distinguishable" and nothing is named.
//  - along_campaign: the roll's service within the campaign, as rolled
//    length, coils or hours since mounting (a roll's rolled length and coil
//    count before a pass correlate above 0.99 within a campaign, and the
//    hours with them apart from stoppages);
//  - load: rolling force and specific force (force per unit width);
//  - gauge: entry and exit thickness (the stand's draught is a fraction of
//    the gauge).
// Thread-safety: constants and pure functions.
#include <string>
#include <vector>

#include "core/diagnosis/diagnosis_internal.h"

namespace rollwear::diag {
namespace {

constexpr CarrierGroup kCarrierGroups[] = {
    {"along_campaign",
     {"campaign_length_before_m", "campaign_coils_before", "hours_since_mount"},
     "wear_rate_growth_along_campaign",
     "The wear rate grows along the campaign: the later coils of a campaign "
     "wear the roll more than the first ones, which the wear law, summing "
     "independent strips, leaves out. Either the roll surface degrades with "
     "the rolled amount (fire cracks, banding, loss of the protective oxide "
     "layer) or the roll's thermal load grows with its hours in the stand; "
     "these data do not tell the two apart.",
     "run_in_of_fresh_surface",
     "A freshly mounted roll wears faster at first and then settles (run-in "
     "of the ground surface, the thermal transient of a cold roll); the wear "
     "law treats every strip alike."},
    {"load",
     {"force_kn", "specific_force_kn_per_mm", nullptr},
     "superlinear_load_dependence",
     "Wear grows faster than linearly with the load (pressure exponent above "
     "one in the Archard law).",
     "sublinear_load_dependence",
     "Wear grows slower than linearly with the load."},
    {"gauge",
     {"entry_thickness_mm", "exit_thickness_mm", nullptr},
     "strip_thickness",
     "Thicker strip wears the roll more.",
     "thin_strip",
     "Thinner strip wears the roll more per unit load."},
};

}  // namespace

const CarrierGroup* CarrierGroupOf(const std::string& covariate) {
  for (const CarrierGroup& g : kCarrierGroups) {
    for (const char* c : g.covariates) {
      if (c != nullptr && covariate == c) return &g;
    }
  }
  return nullptr;
}

bool SameCarriedMechanism(const std::string& a, const std::string& b) {
  const CarrierGroup* g = CarrierGroupOf(a);
  return g != nullptr && a != b && g == CarrierGroupOf(b);
}

std::string CarriersSentence(const std::vector<std::string>& carriers) {
  std::string list;
  for (size_t i = 0; i < carriers.size(); ++i) {
    if (i > 0) list += i + 1 == carriers.size() ? " or " : ", ";
    list += carriers[i];
  }
  return " Carried by " + list +
         ": they move together in this data, which does not say which of "
         "them drives the wear (the fitted term is on " +
         carriers.front() + ").";
}

}  // namespace rollwear::diag
