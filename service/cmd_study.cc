// `rollwear study --data DIR [--out DIR] [--figures DIR] [--split-seed N]
// [--seed N]`: the study's Tables 1-3 on a dataset, as Markdown (stdout and
// OUT/study.md) and JSON (OUT/study.json); with --figures, the study's
// measured-vs-calculated figures as SVG (core/report/study_figures.h).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "api/json_number.h"
#include "core/dataset/dataset_io.h"
#include "core/fit/study.h"
#include "core/report/study_figures.h"
#include "service/commands.h"
#include "service/data_quality_cli.h"

namespace rollwear::cli {
namespace {

nlohmann::json RowJson(const StudyRow& r) {
  return {{"law", r.law},
          {"option", r.option},
          {"start", r.initial_set},
          {"derivatives", r.derivatives},
          {"num_parameters", r.num_parameters},
          {"initial_cost", JsonNumber(r.initial_cost)},
          {"cost", JsonNumber(r.cost)},
          {"gap_train_um", JsonNumber(r.gap_train_um)},
          {"gap_val_um", JsonNumber(r.gap_val_um)},
          {"bias_above_300_um", JsonNumber(r.bias_above_300_um)},
          {"n_above_300", r.n_above_300},
          {"profile_gap_val_um", JsonNumber(r.profile_gap_val_um)},
          {"profile_edge_val_um", JsonNumber(r.profile_edge_val_um)},
          {"iterations", r.iterations},
          {"evaluations", r.evaluations},
          {"seconds", r.seconds},
          {"usable", r.usable},
          {"termination", r.termination}};
}

}  // namespace

int RunStudy(const StudyArgs& args) {
  StudyOptions options = args.options;
  CheckedDataset checked;
  if (int code = ReadCheckedDataset("study", args.data, args.strict, &checked)) {
    return code;
  }
  if (int code = ApplySplitFile("study", args.split, &checked,
                                &options.given_split)) {
    return code;
  }
  const Dataset* data = &checked.fit;
  StatusOr<StudyReport> report = rollwear::RunStudy(*data, options);
  if (!report.ok()) {
    std::fprintf(stderr, "rollwear study: %s\n", report.status().message().c_str());
    return 1;
  }
  const std::string md = StudyMarkdown(*report);
  std::fputs(md.c_str(), stdout);
  if (!args.out.empty()) {
    const std::filesystem::path out = args.out;
    std::error_code ec;
    std::filesystem::create_directories(out, ec);
    nlohmann::json j;
    j["n_campaigns"] = report->n_campaigns;
    j["n_coils"] = report->n_coils;
    j["n_train"] = report->n_train;
    j["n_val"] = report->n_val;
    j["split_seed"] = report->split_seed;
    j["notes"] = report->notes;
    j["data_quality"] = DataQualityJson(checked.quality);
    for (const char* name : {"table1", "table2", "table3"}) j[name] = nlohmann::json::array();
    for (const StudyRow& r : report->table1) j["table1"].push_back(RowJson(r));
    for (const StudyRow& r : report->table2) j["table2"].push_back(RowJson(r));
    for (const StudyRow& r : report->table3) j["table3"].push_back(RowJson(r));
    std::ofstream(out / "study.md") << md;
    std::ofstream json_out(out / "study.json");
    json_out << j.dump(2) << "\n";
    if (!json_out) {
      std::fprintf(stderr, "rollwear study: cannot write %s\n",
                   (out / "study.json").c_str());
      return 1;
    }
    std::printf("wrote %s and %s\n", (out / "study.md").c_str(),
                (out / "study.json").c_str());
  }
  if (!args.figures.empty()) {
    StatusOr<std::vector<SvgFigure>> figures = StudyFigures(*data, options);
    Status written = figures.ok() ? WriteFigures(args.figures, *figures)
                                  : figures.status();
    if (!written.ok()) {
      std::fprintf(stderr, "rollwear study: %s\n", written.message().c_str());
      return 1;
    }
    for (const SvgFigure& f : *figures) {
      std::printf("wrote %s/%s\n", args.figures.c_str(), f.file_name.c_str());
    }
  }
  return 0;
}

}  // namespace rollwear::cli
