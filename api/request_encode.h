// Request bodies of the HTTP contract (../shared/api.md) for the events of
// a dataset: the roll change that opens a campaign, a coil with its passes,
// a campaign end, a grinder measurement and a grinder profile. One definition of the request
// shapes for every client this project ships: `rollwear replay`, the load
// bench and the end-to-end tests.
//
// Thread-safety: stateless functions over a const Dataset.
#ifndef ROLLWEAR_API_REQUEST_ENCODE_H_
#define ROLLWEAR_API_REQUEST_ENCODE_H_

#include <string>
#include <vector>

#include "core/dataset/dataset.h"

namespace rollwear::api {

// POST /v1/roll-changes for campaign `campaign`; `mounts` indexes
// data.mounts (the campaign's mounts, in the order to list them).
std::string RollChangeRequest(const Dataset& data, int campaign,
                              const std::vector<int>& mounts);
// POST /v1/coils for one coil; `passes` indexes data.passes (its passes,
// in stand order; not empty).
std::string CoilRequest(const Dataset& data, const std::vector<int>& passes);
// POST /v1/campaigns/{id}/end for campaign `campaign`.
std::string CampaignEndRequest(const Dataset& data, int campaign);
// POST /v1/measurements for data.measurements[measurement].
std::string MeasurementRequest(const Dataset& data, int measurement);
// The grinder profiles of `data`: data.profile_points grouped by
// (campaign, stand, position), each group's point indices in file order,
// the groups in order of their first point.
std::vector<std::vector<int>> ProfileGroups(const Dataset& data);
// POST /v1/profiles for one profile; `points` indexes data.profile_points
// (one group of ProfileGroups; not empty). Its ids and measured_at are the
// first point's.
std::string ProfileRequest(const Dataset& data, const std::vector<int>& points);

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_REQUEST_ENCODE_H_
