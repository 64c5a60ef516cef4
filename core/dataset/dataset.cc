#include "core/dataset/dataset.h"

#include <algorithm>
#include <cmath>

namespace rollwear {

std::string RollPositionName(int stand, Position p) {
  std::string out = "F";
  out += std::to_string(stand);
  out += '/';
  out += PositionName(p);
  return out;
}

const char* PositionName(Position p) {
  return p == Position::kTop ? "top" : "bottom";
}

// Appended piecewise: GCC 12 warns falsely (-Wrestrict) on
// "F" + std::to_string().
std::string StandName(int stand) {
  std::string s = "F";
  s += std::to_string(stand);
  return s;
}

int ParseStand(const std::string& text) {
  if (text.size() == 2 && text[0] == 'F' && text[1] >= '0' + kMinStand &&
      text[1] <= '0' + kMaxStand) {
    return text[1] - '0';
  }
  return 0;
}

bool ParsePosition(const std::string& text, Position* out) {
  if (text == "top") {
    *out = Position::kTop;
    return true;
  }
  if (text == "bottom") {
    *out = Position::kBottom;
    return true;
  }
  return false;
}

// Linear search: meant for the small label tables (grades, roll types). Bulk
// loaders with many labels (coil ids) keep their own hash map.
int Dataset::Intern(std::vector<std::string>* table, const std::string& label) {
  auto it = std::find(table->begin(), table->end(), label);
  if (it != table->end()) return static_cast<int>(it - table->begin());
  table->push_back(label);
  return static_cast<int>(table->size()) - 1;
}

DatasetIndex::DatasetIndex(const Dataset& data) {
  const int num_campaigns = static_cast<int>(data.campaigns.size());
  mount_.assign(static_cast<size_t>(num_campaigns) * kNumRollPositionSlots, -1);
  measurement_.assign(mount_.size(), -1);
  passes_.resize(static_cast<size_t>(num_campaigns) * (kMaxStand + 1));

  auto valid = [num_campaigns](int campaign, int stand) {
    return campaign >= 0 && campaign < num_campaigns && stand >= kMinStand &&
           stand <= kMaxStand;
  };

  bool slot_used[kNumRollPositionSlots] = {};
  for (size_t i = 0; i < data.mounts.size(); ++i) {
    const Mount& m = data.mounts[i];
    if (!valid(m.campaign, m.stand)) continue;
    const int slot = RollPositionSlot(m.stand, m.position);
    int& entry = mount_[m.campaign * kNumRollPositionSlots + slot];
    if (entry < 0) entry = static_cast<int>(i);
    slot_used[slot] = true;
  }
  for (int s = 0; s < kNumRollPositionSlots; ++s) {
    if (slot_used[s]) slots_.push_back(s);
  }
  for (size_t i = 0; i < data.measurements.size(); ++i) {
    const Measurement& m = data.measurements[i];
    if (!valid(m.campaign, m.stand)) continue;
    int& entry = measurement_[m.campaign * kNumRollPositionSlots +
                              RollPositionSlot(m.stand, m.position)];
    if (entry < 0) entry = static_cast<int>(i);
  }
  for (size_t i = 0; i < data.passes.size(); ++i) {
    const Pass& p = data.passes[i];
    if (!valid(p.campaign, p.stand)) continue;
    passes_[p.campaign * (kMaxStand + 1) + p.stand].push_back(
        static_cast<int>(i));
  }
  // Rows usually arrive in seq order already; sort only when they do not.
  // Stable, so equal seq keeps file order.
  const std::vector<Pass>& passes = data.passes;
  auto by_seq = [&passes](int a, int b) {
    return passes[a].seq < passes[b].seq;
  };
  for (std::vector<int>& list : passes_) {
    if (!std::is_sorted(list.begin(), list.end(), by_seq)) {
      std::stable_sort(list.begin(), list.end(), by_seq);
    }
  }
}

double SpecificForce(const PassMeasures& p) { return p.force_kn / p.width_mm; }

double PassLoad(const PassMeasures& p) { return SpecificForce(p) * p.length_m; }

double ContactLength(const Pass& p, double diameter_mm) {
  return std::sqrt(diameter_mm / 2.0 *
                   (p.entry_thickness_mm - p.exit_thickness_mm));
}

double Reduction(const Pass& p) {
  return (p.entry_thickness_mm - p.exit_thickness_mm) / p.entry_thickness_mm;
}

}  // namespace rollwear
