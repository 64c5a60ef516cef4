#include "core/model/k_structure.h"

#include <utility>

namespace rollwear {
namespace {

std::unordered_map<std::string, int> IndexOf(const std::vector<std::string>& v) {
  std::unordered_map<std::string, int> out;
  for (size_t i = 0; i < v.size(); ++i) out.emplace(v[i], static_cast<int>(i));
  return out;
}

int Find(const std::unordered_map<std::string, int>& m, const std::string& k) {
  auto it = m.find(k);
  return it == m.end() ? -1 : it->second;
}

}  // namespace

StatusOr<KStructure> KStructure::ForOption(int option,
                                           std::vector<std::string> positions,
                                           std::vector<std::string> roll_types,
                                           std::vector<std::string> grades) {
  if (option < 1 || option > 3) {
    return Status::InvalidArgument("K structure option must be 1, 2 or 3, got " +
                                   std::to_string(option));
  }
  if (positions.empty()) {
    return Status::InvalidArgument(
        "K structure needs at least one roll position");
  }
  KStructure s;
  s.option_ = option;
  s.positions_ = std::move(positions);
  s.roll_types_ = std::move(roll_types);
  s.grades_ = std::move(grades);
  s.position_index_ = IndexOf(s.positions_);
  s.roll_type_index_ = IndexOf(s.roll_types_);
  s.grade_index_ = IndexOf(s.grades_);

  auto add_group = [&s](const char* name, FactorKey key, int size) {
    FactorGroup g{name, key, s.num_coefficients_, size};
    s.groups_.push_back(g);
    s.num_coefficients_ += size;
  };
  const int p = static_cast<int>(s.positions_.size());
  const int r = static_cast<int>(s.roll_types_.size());
  const int g = static_cast<int>(s.grades_.size());
  add_group("kF", FactorKey::kRollPosition, p);
  if (option == 1) {
    add_group("kR", FactorKey::kRollType, r);
    add_group("kS", FactorKey::kGrade, g);
  } else if (option == 2) {
    add_group("kRS", FactorKey::kRollTypeGrade, r * g);
  } else {
    add_group("kR", FactorKey::kRollType, r);
  }
  for (const FactorGroup& grp : s.groups_) {
    for (int i = 0; i < grp.size; ++i) {
      std::string label;
      switch (grp.key) {
        case FactorKey::kRollPosition: label = s.positions_[i]; break;
        case FactorKey::kRollType: label = s.roll_types_[i]; break;
        case FactorKey::kGrade: label = s.grades_[i]; break;
        case FactorKey::kRollTypeGrade:
          label = s.roll_types_[i / g] + "|" + s.grades_[i % g];
          break;
      }
      s.names_.push_back(grp.name + "[" + label + "]");
    }
  }
  s.name_index_ = IndexOf(s.names_);
  return s;
}

int KStructure::CoefficientIndex(const std::string& name) const {
  return Find(name_index_, name);
}
int KStructure::PositionLevel(const std::string& l) const {
  return Find(position_index_, l);
}
int KStructure::RollTypeLevel(const std::string& l) const {
  return Find(roll_type_index_, l);
}
int KStructure::GradeLevel(const std::string& l) const {
  return Find(grade_index_, l);
}

int KStructure::CoefficientOf(int group, int p, int r, int s) const {
  const FactorGroup& g = groups_[group];
  switch (g.key) {
    case FactorKey::kRollPosition: return p < 0 ? -1 : g.offset + p;
    case FactorKey::kRollType: return r < 0 ? -1 : g.offset + r;
    case FactorKey::kGrade: return s < 0 ? -1 : g.offset + s;
    case FactorKey::kRollTypeGrade:
      return (r < 0 || s < 0)
                 ? -1
                 : g.offset + r * static_cast<int>(grades_.size()) + s;
  }
  return -1;
}

double KStructure::K(const std::vector<double>& k, int p, int r, int s) const {
  double out = 1.0;
  for (size_t g = 0; g < groups_.size(); ++g) {
    const int c = CoefficientOf(static_cast<int>(g), p, r, s);
    if (c >= 0) out *= k[c];
  }
  return out;
}

}  // namespace rollwear
