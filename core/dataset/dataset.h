// Dataset: the in-memory form of a mill dataset folder (campaigns.csv,
// mounts.csv, coils.csv, measurements.csv and the optional profiles.csv;
// see docs/data-format.md) and the
// index that groups its rows the way the wear models aggregate them.
//
// Text labels (grades, roll types, coil ids) are interned into per-dataset
// tables and rows refer to them by index. Extra columns found in a file are
// kept as numeric covariates (every value parses as a number) or factors.
//
// Thread-safety: plain values; a const Dataset may be read from any thread.
#ifndef ROLLWEAR_CORE_DATASET_DATASET_H_
#define ROLLWEAR_CORE_DATASET_DATASET_H_

#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace rollwear {

// Seconds since 1970-01-01T00:00:00Z.
using UnixSeconds = int64_t;

enum class Position : uint8_t { kTop = 0, kBottom = 1 };

constexpr int kMinStand = 1;
constexpr int kMaxStand = 7;
// A roll position is a (stand, position) pair; index 0..13 = (stand-1)*2+pos.
constexpr int kNumRollPositionSlots = 14;
inline int RollPositionSlot(int stand, Position p) {
  return (stand - 1) * 2 + static_cast<int>(p);
}
inline int SlotStand(int slot) { return slot / 2 + 1; }
inline Position SlotPosition(int slot) {
  return static_cast<Position>(slot % 2);
}
// "F6/top".
std::string RollPositionName(int stand, Position p);
const char* PositionName(Position p);  // "top" / "bottom"
// "F6": the stand's name in the data format and the API.
std::string StandName(int stand);
// Parses "F1".."F7"; returns 0 when invalid.
int ParseStand(const std::string& text);
// Parses "top"/"bottom"; returns false when invalid.
bool ParsePosition(const std::string& text, Position* out);

// Columns of a file that the format does not define: numeric covariates
// (every non-empty value parsed as a number) or text factors.
struct ExtraColumns {
  std::vector<std::string> numeric_names;
  std::vector<std::vector<double>> numeric;  // [column][row]; NaN if empty
  std::vector<std::string> factor_names;
  std::vector<std::vector<int>> factor;  // [column][row] -> level index
  std::vector<std::vector<std::string>> factor_levels;  // [column][level]
};

struct Campaign {
  std::string id;
  UnixSeconds started_at = 0;
  UnixSeconds ended_at = 0;
};

// The roll-type label of a roll whose type a real mill export does not
// record (mounts.csv roll_type empty or "unknown": data-format.md).
inline constexpr const char* kUnknownRollType = "unknown";

struct Mount {
  int campaign = -1;  // index into Dataset::campaigns
  int stand = 0;      // 1..7
  Position position = Position::kTop;
  std::string roll_id;
  int roll_type = -1;  // index into Dataset::roll_types
  double diameter_mm = 0;
  double hardness_hb = 0;  // NaN: not recorded (only Nikitenko needs it)
};

// What one coil brings to one stand: the measured quantities of a
// coils.csv row, without its keys, time and grade (the pass of an API coil
// body is this plus its extra fields: storage::PassIn).
struct PassMeasures {
  int stand = 0;
  double force_kn = 0;
  double width_mm = 0;
  double length_m = 0;
  double entry_thickness_mm = 0;
  double exit_thickness_mm = 0;
  double temperature_c = 0;
  double speed_mps = 0;
  bool lubrication = false;
  double shift_mm = 0;
  bool operator==(const PassMeasures&) const = default;
};

// One row of coils.csv: one coil passing one stand.
struct Pass : PassMeasures {
  int campaign = -1;  // index into Dataset::campaigns
  int coil = -1;      // index into Dataset::coil_ids
  int seq = 0;
  UnixSeconds rolled_at = 0;
  int grade = -1;  // index into Dataset::grades
};

struct Measurement {
  int campaign = -1;
  int stand = 0;
  Position position = Position::kTop;
  std::string roll_id;
  UnixSeconds measured_at = 0;
  double wear_center_um = 0;
};

// One point of a grinder's wear profile across the barrel (profiles.csv,
// optional): wear at barrel coordinate x_mm (mm from the barrel centre,
// positive towards the drive side) of the roll measured after its campaign.
struct ProfilePoint {
  int campaign = -1;
  int stand = 0;
  Position position = Position::kTop;
  std::string roll_id;
  UnixSeconds measured_at = 0;
  double x_mm = 0;
  double wear_um = 0;
};

struct Dataset {
  std::vector<Campaign> campaigns;
  std::vector<Mount> mounts;
  std::vector<Pass> passes;  // rows of coils.csv in file order
  std::vector<Measurement> measurements;
  std::vector<ProfilePoint> profile_points;  // empty without profiles.csv

  std::vector<std::string> grades;      // grade labels, first-seen order
  std::vector<std::string> roll_types;  // roll type labels, first-seen order
  std::vector<std::string> coil_ids;

  ExtraColumns campaign_extra;
  ExtraColumns mount_extra;
  ExtraColumns pass_extra;
  ExtraColumns measurement_extra;

  // Interns a label, returning its index (adds it when new).
  static int Intern(std::vector<std::string>* table, const std::string& label);
};

// Groups the rows of a Dataset by campaign and roll position. Built once in
// O(rows); all indices refer to the Dataset it was built from.
class DatasetIndex {
 public:
  explicit DatasetIndex(const Dataset& data);

  // Mount index for (campaign, slot) or -1.
  int MountOf(int campaign, int slot) const {
    return mount_[campaign * kNumRollPositionSlots + slot];
  }
  // Measurement index for (campaign, slot) or -1.
  int MeasurementOf(int campaign, int slot) const {
    return measurement_[campaign * kNumRollPositionSlots + slot];
  }
  // Pass indices of (campaign, stand), ordered by seq.
  const std::vector<int>& PassesOf(int campaign, int stand) const {
    return passes_[campaign * (kMaxStand + 1) + stand];
  }
  // Slots (roll positions) that appear in any mount, ascending.
  const std::vector<int>& slots() const { return slots_; }

 private:
  std::vector<int> mount_;
  std::vector<int> measurement_;
  std::vector<std::vector<int>> passes_;
  std::vector<int> slots_;
};

// Canonical derived quantities of data-format.md for one pass as seen by the
// roll in `mount`. `length_before_m` and `coils_before` are the campaign
// state before this pass at the same stand.
double SpecificForce(const PassMeasures& p);  // kN/mm
// Wang's load of a pass, F / w * L (kN/mm * m): what the reading checks
// sum per roll position (core/dataset/data_quality.h; the daemon's catalog
// keeps the sums, storage/store_state.h).
double PassLoad(const PassMeasures& p);
double ContactLength(const Pass& p, double diameter_mm);  // mm
double Reduction(const Pass& p);                          // 1

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_DATASET_DATASET_H_
