// PassInput: what one pass of a coil brings to the roll it wears, besides
// the roll itself (the coil row of data-format.md without the stand). The
// one pass struct that every incremental predictor takes: the classical
// predictor (predictor.h, with adopted terms) and the recurrent network
// (ann_model.h).
//
// Thread-safety: plain value.
#ifndef ROLLWEAR_CORE_DATASET_PASS_INPUT_H_
#define ROLLWEAR_CORE_DATASET_PASS_INPUT_H_

#include <string>
#include <utility>

#include "core/dataset/dataset.h"
#include "core/dataset/extra_fields.h"

namespace rollwear {

struct PassInput {
  std::string grade;
  double force_kn = 0;
  double width_mm = 0;
  double length_m = 0;
  double entry_thickness_mm = 0;
  double exit_thickness_mm = 0;
  UnixSeconds rolled_at = 0;
  double temperature_c = 0;
  double speed_mps = 0;
  bool lubrication = false;
  double shift_mm = 0;
  // The pass's extra fields (its coil's and its own): the values of terms
  // adopted on extra pass columns (predictor.h).
  ExtraFields extra;
};

// The pass input of any row type with the coil row's fields (a dataset
// Pass, storage's stored pass) for a coil of `grade`.
template <typename Row>
PassInput PassInputFromRow(std::string grade, const Row& p) {
  PassInput in;
  in.grade = std::move(grade);
  in.force_kn = p.force_kn;
  in.width_mm = p.width_mm;
  in.length_m = p.length_m;
  in.entry_thickness_mm = p.entry_thickness_mm;
  in.exit_thickness_mm = p.exit_thickness_mm;
  in.rolled_at = p.rolled_at;
  in.temperature_c = p.temperature_c;
  in.speed_mps = p.speed_mps;
  in.lubrication = p.lubrication;
  in.shift_mm = p.shift_mm;
  return in;
}

// The pass `pass` (an element of data.passes) of a dataset, with its row's
// extra columns.
PassInput PassInputOf(const Dataset& data, const Pass& pass);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_DATASET_PASS_INPUT_H_
