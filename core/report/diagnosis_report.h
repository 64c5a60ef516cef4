// The diagnosis report as a self-contained HTML page with inline SVG plots
// (svg_plot.h): verdict, before/after figures, each finding with its
// physics, evidence and plots (residual against the named covariate before
// and after; measured against predicted per stand), where the mismatch
// lives, and the candidates tried. Written for a mill engineer who has not
// read the code: no scripts, no external resources.
//
// Thread-safety: pure function.
#ifndef ROLLWEAR_CORE_REPORT_DIAGNOSIS_REPORT_H_
#define ROLLWEAR_CORE_REPORT_DIAGNOSIS_REPORT_H_

#include <string>

#include "core/diagnosis/diagnosis.h"

namespace rollwear {

std::string DiagnosisHtml(const DiagnosisReport& report);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_REPORT_DIAGNOSIS_REPORT_H_
