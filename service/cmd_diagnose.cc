// `rollwear diagnose --data DIR [--json FILE] [--html FILE] [--split-seed N]`:
// locate model-vs-measurement mismatch, name and fit the missing physics,
// show the gain on held-out campaigns (core/diagnosis/diagnosis.h).
#include <cmath>
#include <cstdio>
#include <fstream>

#include "api/diagnosis_json.h"
#include "core/dataset/dataset_io.h"
#include "core/diagnosis/diagnosis.h"
#include "core/report/diagnosis_report.h"
#include "service/commands.h"
#include "service/data_quality_cli.h"

namespace rollwear::cli {

int RunDiagnose(const DiagnoseArgs& args) {
  DiagnosisOptions options = args.options;
  if (!ParseWearLaw(args.model, &options.law)) {
    std::fprintf(stderr, "rollwear diagnose: --model must be wang, nikitenko or cao\n");
    return 2;
  }
  CheckedDataset checked;
  if (int code = ReadCheckedDataset("diagnose", args.data, args.strict, &checked)) {
    return code;
  }
  if (int code = ApplySplitFile("diagnose", args.split, &checked,
                                &options.given_split)) {
    return code;
  }
  StatusOr<DiagnosisReport> report = Diagnose(checked.fit, options);
  if (!report.ok()) {
    std::fprintf(stderr, "rollwear diagnose: %s\n", report.status().message().c_str());
    return 1;
  }
  const DiagnosisReport& r = *report;
  std::printf("verdict: %s\n", r.verdict.c_str());
  std::printf("baseline (%s, option 1): gap training %.1f µm, validation %.1f µm\n",
              r.law.c_str(), r.baseline_gap_train_um, r.baseline_gap_val_um);
  std::printf("baseline grades: %s\n", r.baseline_grades.c_str());
  for (size_t i = 0; i < r.findings.size(); ++i) {
    const Finding& f = r.findings[i];
    std::printf("finding %zu: %s — %s, %s (%s term), p = %.2g, validation gap %.1f -> %.1f µm\n",
                i + 1, f.mechanism.c_str(), f.covariate.c_str(), f.shape.c_str(),
                f.form.c_str(), f.p_adjusted, f.gap_val_before_um, f.gap_val_after_um);
    std::printf("  %s\n", f.explanation.c_str());
  }
  for (const Unexplained& u : r.unexplained) {
    // The size: a mean residual, the rms of the campaign means (time-order
    // checks) or the mean |residual| (spread checks); docs/diagnosis.md.
    const bool rms = u.test == "lag1_autocorrelation" || u.test == "runs";
    // Collinear rivals (encompassing_lr): the rms of the winner's term.
    const bool rivals = u.test == "encompassing_lr";
    const char* size = rms      ? "campaign means %.1f µm rms"
                       : rivals ? "term effect %.1f µm rms"
                       : u.test == "brown_forsythe" ? "mean |residual| %.1f µm"
                                                    : "%+.1f µm";
    char buf[64];
    std::snprintf(buf, sizeof(buf), size, u.mean_residual_um);
    std::printf(
        "mismatch at %s: %s, p = %.2g (%s); %s\n", u.where.c_str(), buf,
        u.p_adjusted, u.dimension.c_str(),
        rivals
            ? "several recorded quantities describe it alike, so none is named"
            : "no recorded quantity explains it");
  }
  for (const RunnerUp& u : r.runners_up) {
    std::printf("not adopted: %s (%s term), p = %.2g: %s\n", u.covariate.c_str(),
                u.form.c_str(), u.p_adjusted, u.reason.c_str());
  }
  std::printf("with adopted terms: gap training %.1f µm, validation %.1f µm (%.1f s)\n",
              r.final_gap_train_um, r.final_gap_val_um, r.seconds);
  PrintSuspectedOutliers(r.suspected_outliers);
  if (!args.json.empty()) {
    std::ofstream out(args.json);
    out << api::DiagnosisJsonText(r, 2, &checked.quality) << "\n";
    if (!out) {
      std::fprintf(stderr, "rollwear diagnose: cannot write %s\n", args.json.c_str());
      return 1;
    }
  }
  if (!args.html.empty()) {
    std::ofstream out(args.html);
    out << DiagnosisHtml(r);
    if (!out) {
      std::fprintf(stderr, "rollwear diagnose: cannot write %s\n", args.html.c_str());
      return 1;
    }
  }
  return 0;
}

}  // namespace rollwear::cli
