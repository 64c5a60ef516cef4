#include "service/data_quality_cli.h"

#include <cstdio>

#include "core/dataset/dataset_io.h"

namespace rollwear::cli {

int ReadCheckedDataset(const char* tool, const std::string& dir, bool strict,
                       CheckedDataset* out) {
  DatasetLines& lines = out->lines;
  StatusOr<Dataset> data = ReadDataset(dir, &lines);
  if (!data.ok()) {
    std::fprintf(stderr, "rollwear %s: %s\n", tool,
                 data.status().message().c_str());
    return 1;
  }
  out->quality = AssessDataQuality(*data, &lines);
  std::printf("%s", DataQualitySummary(out->quality).c_str());
  std::fflush(stdout);
  if (strict && !out->quality.issues.empty()) {
    const DataQualityIssue& first = out->quality.issues.front();
    std::fprintf(stderr,
                 "rollwear %s: --strict: %zu data-quality warning(s), first "
                 "%s %s: %s\n",
                 tool, out->quality.issues.size(), first.Location().c_str(),
                 first.where.c_str(), first.reason.c_str());
    return 1;
  }
  out->fit = WithoutSuspects(*data, out->quality);
  out->all = *std::move(data);
  return 0;
}

nlohmann::json DataQualityJson(const DataQuality& q) {
  nlohmann::json counts = nlohmann::json::object();
  for (int k = 0; k < kNumDataQualityKinds; ++k) {
    const auto kind = static_cast<DataQualityKind>(k);
    counts[DataQualityKindName(kind)] = q.Count(kind);
  }
  nlohmann::json issues = nlohmann::json::array();
  for (const DataQualityIssue& i : q.issues) {
    nlohmann::json j = {{"kind", DataQualityKindName(i.kind)},
                        {"file", i.file},
                        {"line", i.line > 0 ? nlohmann::json(i.line)
                                            : nlohmann::json(nullptr)},
                        {"where", i.where},
                        {"reason", i.reason}};
    j["value_um"] = i.measurement >= 0 ? nlohmann::json(i.value_um)
                                       : nlohmann::json(nullptr);
    issues.push_back(std::move(j));
  }
  return {{"warnings", q.issues.size()},
          {"suspect_measurements", q.NumSuspect()},
          {"counts", counts},
          {"thresholds",
           {{"noise_sd_um", q.noise_sd_um},
            {"negative_limit_um", -kSuspectNoiseSigmas * q.noise_sd_um},
            {"excess_factor", q.excess_factor}}},
          {"issues", issues}};
}

bool SpoilsCalibration(const DataQuality& quality) {
  return quality.Count(DataQualityKind::kNoPasses) > 0;
}

}  // namespace rollwear::cli
