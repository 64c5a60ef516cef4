// K structures: how the wear coefficient K of a pass is built from factors
// that depend on the roll position (stand/top-bottom), the roll type or
// supplier, and the strip grade. A structure is data, not a code path:
// a list of factor groups, each keyed by one attribute of the pass, and
//   K(position p, roll type r, grade s) = prod_g k_g[level_g(p, r, s)].
//
//   option 1: kF[p] * kR[r] * kS[s]   (P + R + S coefficients; study: 21)
//   option 2: kF[p] * kRS[r, s]       (P + R*S;                study: 76)
//   option 3: kF[p] * kR[r]           (P + R;                  study: 12)
//
// Gauge. A product of G groups is invariant under multiplying one group by
// c and another by 1/c, so only G-1 scale factors are not identifiable.
// rollwear reports every group after the first in the geometric-mean gauge
// (prod over levels with data of k = 1) and lets the position factor kF
// carry the scale; the products K(p, r, s) are gauge-invariant and are the
// identifiable quantities.
//
// Thread-safety: immutable after construction; safe to share.
#ifndef ROLLWEAR_CORE_MODEL_K_STRUCTURE_H_
#define ROLLWEAR_CORE_MODEL_K_STRUCTURE_H_

#include <string>
#include <unordered_map>
#include <vector>

#include "core/base/status.h"

namespace rollwear {

enum class FactorKey { kRollPosition, kRollType, kGrade, kRollTypeGrade };

struct FactorGroup {
  std::string name;  // "kF", "kR", "kS", "kRS"
  FactorKey key;
  int offset = 0;    // index of the group's first coefficient
  int size = 0;      // number of levels (coefficients)
};

class KStructure {
 public:
  KStructure() = default;
  // Option 1, 2 or 3 over the given level labels (positions like "F6/top").
  // Roll types and grades may be empty (a prior model before any data):
  // unknown levels then count as 1.
  static StatusOr<KStructure> ForOption(int option,
                                        std::vector<std::string> positions,
                                        std::vector<std::string> roll_types,
                                        std::vector<std::string> grades);

  int option() const { return option_; }
  const std::vector<FactorGroup>& groups() const { return groups_; }
  int num_coefficients() const { return num_coefficients_; }
  // "kF[F6/top]", "kR[ICDP-S3]", "kS[DP600]", "kRS[ICDP-S3|DP600]".
  const std::string& CoefficientName(int i) const { return names_[i]; }
  int CoefficientIndex(const std::string& name) const;  // -1 if unknown

  const std::vector<std::string>& positions() const { return positions_; }
  const std::vector<std::string>& roll_types() const { return roll_types_; }
  const std::vector<std::string>& grades() const { return grades_; }
  // Level index of a label, or -1 when the structure has never seen it.
  int PositionLevel(const std::string& label) const;
  int RollTypeLevel(const std::string& label) const;
  int GradeLevel(const std::string& label) const;

  // Coefficient index of group g for the cell (p, r, s) of level indices;
  // -1 when a needed level is unknown (-1), in which case the factor is
  // taken as its gauge value 1.
  int CoefficientOf(int group, int p, int r, int s) const;

  // K(p, r, s) for natural (positive) coefficients `k`.
  double K(const std::vector<double>& k, int p, int r, int s) const;

 private:
  int option_ = 0;
  std::vector<FactorGroup> groups_;
  int num_coefficients_ = 0;
  std::vector<std::string> names_;
  std::unordered_map<std::string, int> name_index_;
  std::vector<std::string> positions_, roll_types_, grades_;
  std::unordered_map<std::string, int> position_index_, roll_type_index_,
      grade_index_;
};

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_K_STRUCTURE_H_
