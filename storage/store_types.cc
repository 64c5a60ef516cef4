#include "storage/store_types.h"

#include <cmath>

namespace rollwear::storage {

std::vector<MountRecord> MountRecords(const std::vector<MountedRollIn>& rolls) {
  std::vector<MountRecord> out;
  out.reserve(rolls.size());
  for (const MountedRollIn& r : rolls) {
    out.push_back(MountRecord{r.stand, r.position, r.roll_id, r.roll_type,
                              r.diameter_mm, r.hardness_hb});
  }
  return out;
}

bool StoreOptions::IsValid(std::string* error) const {
  if (max_batch < 1) {
    *error = "max_batch must be >= 1";
    return false;
  }
  if (default_option < 1 || default_option > 3) {
    *error = "default_option must be 1, 2 or 3";
    return false;
  }
  if (!std::isfinite(initial_k) || !(initial_k > 0)) {
    *error = "initial_k must be a finite number > 0";
    return false;
  }
  return true;
}

const char* CalibrationStatusName(CalibrationStatus s) {
  switch (s) {
    case CalibrationStatus::kQueued:
      return "queued";
    case CalibrationStatus::kRunning:
      return "running";
    case CalibrationStatus::kDone:
      return "done";
    case CalibrationStatus::kFailed:
      return "failed";
  }
  return "unknown";
}

}  // namespace rollwear::storage

namespace rollwear::storage {

std::string ModelSource(const std::string& trigger) {
  if (trigger == "nightly") return "nightly";
  if (trigger.rfind("diagnosis", 0) == 0) return "diagnosis";
  return "calibration";
}

}  // namespace rollwear::storage
