// The data a term fit reads (TermData): each measured roll's passes with
// their base loads and every covariate of the catalog, evaluated pass by
// pass and load-weighted per reading; see term_fit.h.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/fit/term_fit.h"
#include "core/model/aggregation.h"
#include "core/model/covariates.h"
#include "core/model/wear_law.h"

namespace rollwear {

int TermData::CovariateIndex(const std::string& name) const {
  for (size_t i = 0; i < catalog.size(); ++i) {
    if (catalog[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

StatusOr<TermData> BuildTermData(const Dataset& data, WearLaw law) {
  const DatasetIndex index(data);
  TermData td;
  td.law = law;
  td.roll_types = data.roll_types;
  td.grades = data.grades;
  td.catalog = CovariateCatalog(data);
  td.positions = PositionLevelNames(index);
  const UnixSeconds origin = 0;  // started_at in days since 1970 (covariates.h)
  td.z.resize(td.catalog.size());
  td.obs_z.resize(td.catalog.size());
  const std::vector<int> service = RollCampaignsBefore(data);
  const std::vector<unsigned char> after_stop = PassesAfterStop(data);
  for (const MountedRoll& roll : MountedRolls(data, index)) {
    if (roll.measurement < 0) continue;
    const Mount& mount = data.mounts[roll.mount];
    TermObservation o;
    static_cast<MountedRoll&>(o) = roll;
    o.pass_begin = static_cast<int>(td.load.size());
    PassContext ctx;
    ctx.mount = &mount;
    ctx.mount_row = roll.mount;
    ctx.roll_campaigns_before = service[roll.mount];
    ctx.campaign = &data.campaigns[roll.campaign];
    ctx.campaign_row = roll.campaign;
    ctx.measurement_row = roll.measurement;
    for (int pi : index.PassesOf(roll.campaign, mount.stand)) {
      const Pass& pass = data.passes[pi];
      ctx.pass = &pass;
      ctx.pass_row = pi;
      ctx.after_stop = after_stop[pi];
      const double load = BaseLoad(law, MakeLoadInput(pass, mount));
      if (!std::isfinite(load) || load < 0) {
        return Status::InvalidArgument("coil " + data.coil_ids[pass.coil] +
                                       ": wear load is not finite");
      }
      td.load.push_back(load);
      td.grade.push_back(pass.grade);
      for (size_t k = 0; k < td.catalog.size(); ++k) {
        td.z[k].push_back(CovariateValue(td.catalog[k], data, ctx, origin));
      }
      ctx.length_before_m += pass.length_m;
      ctx.coils_before += 1;
    }
    o.pass_end = static_cast<int>(td.load.size());
    for (size_t k = 0; k < td.catalog.size(); ++k) {
      double num = 0, den = 0, first = std::numeric_limits<double>::quiet_NaN();
      for (int i = o.pass_begin; i < o.pass_end; ++i) {
        const double v = td.z[k][i];
        if (std::isnan(v)) continue;
        if (std::isnan(first)) first = v;
        num += td.load[i] * v;
        den += td.load[i];
      }
      double agg = first;
      if (td.catalog[k].level == CovariateLevel::kPass && den > 0)
        agg = num / den;
      td.obs_z[k].push_back(agg);
    }
    td.obs.push_back(o);
  }
  return td;
}

}  // namespace rollwear
