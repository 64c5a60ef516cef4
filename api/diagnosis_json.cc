#include "api/diagnosis_json.h"

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/data_quality_json.h"
#include "api/json_number.h"
#include "storage/model_codec.h"

namespace rollwear::api {
namespace {

// A term as the stored model writes it (storage/model_codec.h: scope,
// reference level and all), so that `calibrate --terms` and clients read
// back exactly the term the diagnosis adopted.
nlohmann::json TermJson(const ModelTerm& t) {
  return nlohmann::json::parse(storage::EncodeTerms({t})).at(0);
}

// A finding's scope: null when global, else {"stand":"F7",...}.
nlohmann::json ScopeJson(const std::map<std::string, std::string>& scope) {
  if (scope.empty()) return nullptr;
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [k, v] : scope) j[k] = v;
  return j;
}

nlohmann::json UnexplainedJson(const std::vector<Unexplained>& list) {
  nlohmann::json j = nlohmann::json::array();
  for (const Unexplained& u : list) {
    j.push_back({{"dimension", u.dimension},
                 {"where", u.where},
                 {"test", u.test},
                 {"statistic", JsonNumber(u.statistic)},
                 {"mean_residual_um", JsonNumber(u.mean_residual_um)},
                 {"p_value", JsonNumber(u.p_adjusted)},
                 {"p_value_unadjusted", JsonNumber(u.p_value)}});
  }
  return j;
}

nlohmann::json RunnersUpJson(const std::vector<RunnerUp>& list) {
  nlohmann::json j = nlohmann::json::array();
  for (const RunnerUp& u : list) {
    j.push_back({{"round", u.round},
                 {"covariate", u.covariate},
                 {"form", u.form},
                 {"p_value", JsonNumber(u.p_adjusted)},
                 {"cv_error_ratio", JsonNumber(u.cv_mse_ratio)},
                 {"reason", u.reason},
                 {"refusal", RefusalKindName(u.refusal)},
                 {"guard", u.guard}});
  }
  return j;
}

nlohmann::json DiagnosisJson(const DiagnosisReport& r) {
  nlohmann::json j;
  j["baseline"] = {{"model", r.law},
                   {"option", 1},
                   {"gap_train_um", r.baseline_gap_train_um},
                   {"gap_val_um", r.baseline_gap_val_um},
                   {"grades", r.baseline_grades}};
  j["final"] = {{"gap_train_um", r.final_gap_train_um}, {"gap_val_um", r.final_gap_val_um}};
  j["n_train"] = r.n_train;
  j["n_val"] = r.n_val;
  j["verdict"] = r.verdict;
  j["findings"] = nlohmann::json::array();
  for (const Finding& f : r.findings) {
    nlohmann::json params = nlohmann::json::object(), se = nlohmann::json::object();
    for (const auto& [k, v] : f.parameters) params[k] = JsonNumber(v);
    for (const auto& [k, v] : f.parameter_std_errors) se[k] = JsonNumber(v);
    j["findings"].push_back({{"covariate", f.covariate},
                             {"scope", ScopeJson(f.scope)},
                             {"levels", f.levels},
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
                             {"p_value", JsonNumber(f.p_adjusted)},
                             {"p_value_unadjusted", JsonNumber(f.p_value)},
                             {"cv_gap_before_um", f.cv_gap_before_um},
                             {"cv_gap_after_um", f.cv_gap_after_um},
                             {"cv_error_ratio", JsonNumber(f.cv_mse_ratio)},
                             {"gap_val_before_um", f.gap_val_before_um},
                             {"gap_val_after_um", f.gap_val_after_um},
                             {"alternatives", f.alternatives},
                             {"carriers", f.carriers},
                             {"scope_undetermined", f.scope_undetermined}});
  }
  j["unexplained"] = UnexplainedJson(r.unexplained);
  j["runners_up"] = RunnersUpJson(r.runners_up);
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
                           {"statistic", JsonNumber(b.statistic)},
                           {"p_value", JsonNumber(b.p_value)},
                           {"effect_size", JsonNumber(b.effect_size)},
                           {"groups", groups}});
  }
  j["candidates_first_round"] = nlohmann::json::array();
  for (const CandidateResult& c : r.first_round) {
    j["candidates_first_round"].push_back({{"covariate", c.covariate},
                                           {"form", c.form},
                                           {"df", c.df},
                                           {"lr_statistic", c.lr},
                                           {"p_value", JsonNumber(c.p_adjusted)},
                                           {"cv_error_ratio", JsonNumber(c.cv_mse_ratio)},
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

}  // namespace

std::string DiagnosisJsonText(const DiagnosisReport& report, int indent,
                              const DataQuality* quality) {
  nlohmann::json j = DiagnosisJson(report);
  if (quality != nullptr) {
    j["data_quality"] = DataQualityJson(*quality, &report.suspected_outliers);
  }
  return j.dump(indent);
}

}  // namespace rollwear::api
