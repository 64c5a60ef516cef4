// `rollwear diagnose --data DIR [--json FILE] [--html FILE] [--split-seed N]`:
// locate model-vs-measurement mismatch, name and fit the missing physics,
// show the gain on held-out campaigns (core/diagnosis.h).
#include <cmath>
#include <cstdio>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/dataset_io.h"
#include "core/diagnosis.h"
#include "core/diagnosis_report.h"
#include "service/commands.h"
#include "service/flags.h"

namespace rollwear::cli {
namespace {

nlohmann::json Num(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

nlohmann::json TermJson(const ModelTerm& t) {
  nlohmann::json j = {{"covariate", t.covariate},
                      {"form", TermFormName(t.form)},
                      {"params", t.params},
                      {"center", t.center},
                      {"scale", t.scale}};
  if (!t.edges.empty()) j["edges"] = t.edges;
  if (t.num_levels > 0) j["num_levels"] = t.num_levels;
  return j;
}

}  // namespace

nlohmann::json DiagnosisJson(const DiagnosisReport& r) {
  nlohmann::json j;
  j["baseline"] = {{"model", r.law},
                   {"option", 1},
                   {"gap_train_um", r.baseline_gap_train_um},
                   {"gap_val_um", r.baseline_gap_val_um}};
  j["final"] = {{"gap_train_um", r.final_gap_train_um}, {"gap_val_um", r.final_gap_val_um}};
  j["n_train"] = r.n_train;
  j["n_val"] = r.n_val;
  j["verdict"] = r.verdict;
  j["findings"] = nlohmann::json::array();
  for (const Finding& f : r.findings) {
    nlohmann::json params = nlohmann::json::object(), se = nlohmann::json::object();
    for (const auto& [k, v] : f.parameters) params[k] = Num(v);
    for (const auto& [k, v] : f.parameter_std_errors) se[k] = Num(v);
    j["findings"].push_back({{"covariate", f.covariate},
                             {"level", f.level},
                             {"mechanism", f.mechanism},
                             {"shape", f.shape},
                             {"form", f.form},
                             {"explanation", f.explanation},
                             {"parameters", params},
                             {"term", TermJson(f.term)},
                             {"term_param_std_errors", se},
                             {"lr_statistic", f.lr},
                             {"df", f.df},
                             {"p_value", Num(f.p_adjusted)},
                             {"p_value_unadjusted", Num(f.p_value)},
                             {"cv_gap_before_um", f.cv_gap_before_um},
                             {"cv_gap_after_um", f.cv_gap_after_um},
                             {"cv_error_ratio", Num(f.cv_mse_ratio)},
                             {"gap_val_before_um", f.gap_val_before_um},
                             {"gap_val_after_um", f.gap_val_after_um},
                             {"alternatives", f.alternatives}});
  }
  j["locate"] = nlohmann::json::array();
  for (const Breakdown& b : r.locate) {
    nlohmann::json groups = nlohmann::json::array();
    for (const Breakdown::Group& g : b.groups) {
      groups.push_back({{"label", g.label},
                        {"n", g.n},
                        {"mean_residual_um", g.mean_residual_um},
                        {"mean_relative_residual", g.mean_relative}});
    }
    j["locate"].push_back({{"dimension", b.dimension},
                           {"test", b.test},
                           {"statistic", Num(b.statistic)},
                           {"p_value", Num(b.p_value)},
                           {"effect_size", Num(b.effect_size)},
                           {"groups", groups}});
  }
  j["candidates_first_round"] = nlohmann::json::array();
  for (const CandidateResult& c : r.first_round) {
    j["candidates_first_round"].push_back({{"covariate", c.covariate},
                                           {"form", c.form},
                                           {"df", c.df},
                                           {"lr_statistic", c.lr},
                                           {"p_value", Num(c.p_adjusted)},
                                           {"cv_error_ratio", Num(c.cv_mse_ratio)},
                                           {"accepted", c.accepted}});
  }
  nlohmann::json coef = nlohmann::json::object();
  for (const auto& [k, v] : r.coefficients) coef[k] = v;
  nlohmann::json terms = nlohmann::json::array();
  for (const ModelTerm& t : r.terms) terms.push_back(TermJson(t));
  j["adopted_model"] = {{"model", r.law}, {"option", 1}, {"coefficients", coef}, {"terms", terms}};
  j["seconds"] = r.seconds;
  return j;
}

int RunDiagnose(const Args& args) {
  Flags flags;
  std::string error;
  if (!flags.Parse(args, {"data", "json", "html", "split-seed", "model", "threads"}, {},
                   &error)) {
    std::fprintf(stderr, "rollwear diagnose: %s\n", error.c_str());
    return 2;
  }
  if (!flags.Has("data")) {
    std::fprintf(stderr, "rollwear diagnose: --data DIR is required\n");
    return 2;
  }
  DiagnosisOptions options;
  long long split_seed = 1, threads = 2;
  if (!flags.GetInt("split-seed", 1, &split_seed, &error) ||
      !flags.GetInt("threads", 2, &threads, &error)) {
    std::fprintf(stderr, "rollwear diagnose: %s\n", error.c_str());
    return 2;
  }
  options.split_seed = static_cast<uint64_t>(split_seed);
  options.num_threads = static_cast<int>(threads);
  if (!ParseWearLaw(flags.Get("model", "wang"), &options.law)) {
    std::fprintf(stderr, "rollwear diagnose: --model must be wang, nikitenko or cao\n");
    return 2;
  }
  StatusOr<Dataset> data = ReadDataset(flags.Get("data"));
  if (!data.ok()) {
    std::fprintf(stderr, "rollwear diagnose: %s\n", data.status().message().c_str());
    return 1;
  }
  StatusOr<DiagnosisReport> report = Diagnose(*data, options);
  if (!report.ok()) {
    std::fprintf(stderr, "rollwear diagnose: %s\n", report.status().message().c_str());
    return 1;
  }
  const DiagnosisReport& r = *report;
  std::printf("verdict: %s\n", r.verdict.c_str());
  std::printf("baseline (%s, option 1): gap training %.1f µm, validation %.1f µm\n",
              r.law.c_str(), r.baseline_gap_train_um, r.baseline_gap_val_um);
  for (size_t i = 0; i < r.findings.size(); ++i) {
    const Finding& f = r.findings[i];
    std::printf("finding %zu: %s — %s, %s (%s term), p = %.2g, validation gap %.1f -> %.1f µm\n",
                i + 1, f.mechanism.c_str(), f.covariate.c_str(), f.shape.c_str(),
                f.form.c_str(), f.p_adjusted, f.gap_val_before_um, f.gap_val_after_um);
    std::printf("  %s\n", f.explanation.c_str());
  }
  std::printf("with adopted terms: gap training %.1f µm, validation %.1f µm (%.1f s)\n",
              r.final_gap_train_um, r.final_gap_val_um, r.seconds);
  if (flags.Has("json")) {
    std::ofstream out(flags.Get("json"));
    out << DiagnosisJson(r).dump(2) << "\n";
    if (!out) {
      std::fprintf(stderr, "rollwear diagnose: cannot write %s\n", flags.Get("json").c_str());
      return 1;
    }
  }
  if (flags.Has("html")) {
    std::ofstream out(flags.Get("html"));
    out << DiagnosisHtml(r);
    if (!out) {
      std::fprintf(stderr, "rollwear diagnose: cannot write %s\n", flags.Get("html").c_str());
      return 1;
    }
  }
  return 0;
}

}  // namespace rollwear::cli
