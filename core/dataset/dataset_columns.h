// Internal to core's dataset reader/writer (dataset_io.cc,
// dataset_write.cc): the four file names and the columns the format defines
// for each, in canonical order (the order WriteDataset writes them).
//
// Thread-safety: constants.
#ifndef ROLLWEAR_CORE_DATASET_DATASET_COLUMNS_H_
#define ROLLWEAR_CORE_DATASET_DATASET_COLUMNS_H_

#include <span>
#include <string_view>

#include "core/dataset/dataset.h"
#include "core/dataset/timestamp.h"  // ParseTimestampView

namespace rollwear {

enum DatasetFile {
  kCampaignsFile = 0,
  kMountsFile,
  kCoilsFile,
  kMeasurementsFile,
  kNumDatasetFiles
};

inline constexpr const char* kDatasetFileNames[kNumDatasetFiles] = {
    "campaigns.csv", "mounts.csv", "coils.csv", "measurements.csv"};

namespace campaign_col {
enum { kId, kStartedAt, kEndedAt };
}  // namespace campaign_col
inline constexpr const char* kCampaignColumns[] = {"campaign_id", "started_at",
                                                   "ended_at"};

namespace mount_col {
enum { kCampaign, kStand, kPosition, kRollId, kRollType, kDiameter, kHardness };
}  // namespace mount_col
inline constexpr const char* kMountColumns[] = {
    "campaign_id", "stand",       "position",   "roll_id",
    "roll_type",   "diameter_mm", "hardness_hb"};

namespace coil_col {
enum {
  kCampaign,
  kCoil,
  kSeq,
  kRolledAt,
  kGrade,
  kStand,
  kForce,
  kWidth,
  kLength,
  kEntry,
  kExit,
  kTemperature,
  kSpeed,
  kLubrication,
  kShift
};
}  // namespace coil_col
inline constexpr const char* kCoilColumns[] = {"campaign_id",
                                               "coil_id",
                                               "seq",
                                               "rolled_at",
                                               "grade",
                                               "stand",
                                               "force_kn",
                                               "width_mm",
                                               "length_m",
                                               "entry_thickness_mm",
                                               "exit_thickness_mm",
                                               "temperature_c",
                                               "speed_mps",
                                               "lubrication",
                                               "shift_mm"};

namespace measurement_col {
enum { kCampaign, kStand, kPosition, kRollId, kMeasuredAt, kWear };
}  // namespace measurement_col
inline constexpr const char* kMeasurementColumns[] = {
    "campaign_id", "stand",       "position",
    "roll_id",     "measured_at", "wear_center_um"};

// profiles.csv is optional: read when present, written when non-empty.
inline constexpr const char* kProfilesFileName = "profiles.csv";
namespace profile_col {
enum { kCampaign, kStand, kPosition, kRollId, kMeasuredAt, kX, kWear };
}  // namespace profile_col
inline constexpr const char* kProfileColumns[] = {
    "campaign_id", "stand",       "position", "roll_id",
    "measured_at", "x_mm",        "wear_um"};

using ColumnList = std::span<const char* const>;
inline constexpr ColumnList kDatasetColumns[kNumDatasetFiles] = {
    kCampaignColumns, kMountColumns, kCoilColumns, kMeasurementColumns};

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_DATASET_DATASET_COLUMNS_H_
