#include "storage/model_codec.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <unordered_set>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/dataset/dataset.h"
#include "core/model/ann_model.h"
#include "core/model/covariates.h"
#include "core/model/term_family.h"
#include "storage/model_codec_scope.h"

namespace rollwear::storage {
namespace {

using Json = nlohmann::ordered_json;

constexpr int kFormat = 1;

Json Number(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "Infinity" : "-Infinity";
  return v;
}

bool NamesUnique(const KStructure& s) {
  std::unordered_set<std::string> seen;
  for (int i = 0; i < s.num_coefficients(); ++i) {
    if (!seen.insert(s.CoefficientName(i)).second) return false;
  }
  return true;
}

constexpr auto Bad = BadModelField;

// A finite or non-finite number as written by Number().
bool ReadNumber(const Json& j, double* out) {
  if (j.is_number()) {
    *out = j.get<double>();
    return true;
  }
  if (j.is_null() || (j.is_string() && j.get<std::string>() == "NaN")) {
    *out = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  if (j.is_string() && j.get<std::string>() == "Infinity") {
    *out = std::numeric_limits<double>::infinity();
    return true;
  }
  if (j.is_string() && j.get<std::string>() == "-Infinity") {
    *out = -std::numeric_limits<double>::infinity();
    return true;
  }
  return false;
}

// doc[field], optional: an array of strings; an error names `at` + field
// (`at`: the path of `doc`, e.g. "terms[0].").
Status ReadLabels(const Json& doc, const char* field,
                  std::vector<std::string>* out, const std::string& at = "") {
  auto it = doc.find(field);
  if (it == doc.end()) return Status::Ok();  // optional: empty
  if (!it->is_array()) return Bad(at + field, "must be an array of strings");
  for (const Json& v : *it) {
    if (!v.is_string()) return Bad(at + field, "must be an array of strings");
    out->push_back(v.get<std::string>());
  }
  return Status::Ok();
}

Status ReadScalar(const Json& doc, const char* field, double* out) {
  auto it = doc.find(field);
  if (it == doc.end()) return Status::Ok();  // optional: keep default
  if (!ReadNumber(*it, out)) return Bad(field, "must be a number");
  return Status::Ok();
}

Json Numbers(const std::vector<double>& v) {
  Json arr = Json::array();
  for (double x : v) arr.push_back(Number(x));
  return arr;
}

Json EncodeTerm(const ModelTerm& t) {
  Json j = Json::object();
  j["covariate"] = t.covariate;
  j["form"] = TermFormName(t.form);
  j["params"] = Numbers(t.params);
  j["center"] = Number(t.center);
  j["scale"] = Number(t.scale);
  j["edges"] = Numbers(t.edges);
  j["num_levels"] = t.num_levels;
  if (!t.levels.empty()) j["levels"] = t.levels;
  if (t.reference_level != 0) j["reference_level"] = t.reference_level;
  if (!t.level_sd.empty()) j["level_sd"] = Numbers(t.level_sd);
  if (!t.level_readings.empty()) j["level_readings"] = t.level_readings;
  // Scope: absent (or a missing field) = everywhere, so models stored
  // before scopes existed read unchanged.
  if (!t.scope.IsAll()) j["scope"] = EncodeScope(t.scope);
  return j;
}

Status ReadNumbers(const Json& obj, const char* key, const std::string& field,
                   std::vector<double>* out) {
  auto it = obj.find(key);
  if (it == obj.end()) return Status::Ok();
  if (!it->is_array()) return Bad(field, "must be an array of numbers");
  for (const Json& v : *it) {
    double x = 0;
    if (!ReadNumber(v, &x)) return Bad(field, "must be an array of numbers");
    out->push_back(x);
  }
  return Status::Ok();
}

// A roll-effect term's optional per-roll spread: "level_sd" (finite,
// >= 0) and "level_readings" (integers >= 0), one per level each.
Status DecodeRollSpread(const Json& j, const std::string& at, ModelTerm* t) {
  ROLLWEAR_RETURN_IF_ERROR(
      ReadNumbers(j, "level_sd", at + "level_sd", &t->level_sd));
  std::vector<double> readings;
  ROLLWEAR_RETURN_IF_ERROR(
      ReadNumbers(j, "level_readings", at + "level_readings", &readings));
  for (double r : readings) {
    if (!(r >= 0 && r == std::floor(r) && r < 1e9)) {
      return Bad(at + "level_readings", "must be integers >= 0");
    }
    t->level_readings.push_back(static_cast<int>(r));
  }
  const size_t n = static_cast<size_t>(std::max(0, t->num_levels));
  if (!t->level_sd.empty() && t->level_sd.size() != n) {
    return Bad(at + "level_sd", "needs one number per level");
  }
  if (!t->level_readings.empty() && t->level_readings.size() != n) {
    return Bad(at + "level_readings", "needs one number per level");
  }
  for (double sd : t->level_sd) {
    if (!(std::isfinite(sd) && sd >= 0))
      return Bad(at + "level_sd", "must be finite and >= 0");
  }
  return Status::Ok();
}

Status DecodeTerms(const Json& doc, std::vector<ModelTerm>* out) {
  auto terms = doc.find("terms");
  if (terms == doc.end()) return Status::Ok();
  if (!terms->is_array()) return Bad("terms", "must be an array");
  for (size_t i = 0; i < terms->size(); ++i) {
    const Json& j = (*terms)[i];
    const std::string at = "terms[" + std::to_string(i) + "].";
    if (!j.is_object()) return Bad(at, "must be an object");
    ModelTerm t;
    auto cov = j.find("covariate");
    if (cov == j.end() || !cov->is_string()) {
      return Bad(at + "covariate", "must be a string");
    }
    t.covariate = cov->get<std::string>();
    auto form = j.find("form");
    if (form == j.end() || !form->is_string() ||
        !ParseTermForm(form->get<std::string>(), &t.form)) {
      return Bad(at + "form", "unknown term form");
    }
    ROLLWEAR_RETURN_IF_ERROR(
        ReadNumbers(j, "params", at + "params", &t.params));
    if (!ReadScalar(j, "center", &t.center).ok())
      return Bad(at + "center", "must be a number");
    if (!ReadScalar(j, "scale", &t.scale).ok())
      return Bad(at + "scale", "must be a number");
    ROLLWEAR_RETURN_IF_ERROR(ReadNumbers(j, "edges", at + "edges", &t.edges));
    auto levels = j.find("num_levels");
    if (levels != j.end()) {
      if (!levels->is_number_integer()) {
        return Bad(at + "num_levels", "must be an integer");
      }
      t.num_levels = levels->get<int>();
    }
    ROLLWEAR_RETURN_IF_ERROR(ReadLabels(j, "levels", &t.levels, at));
    auto ref = j.find("reference_level");
    if (ref != j.end()) {
      if (!ref->is_number_integer())
        return Bad(at + "reference_level", "must be an integer");
      t.reference_level = ref->get<int>();
    }
    ROLLWEAR_RETURN_IF_ERROR(DecodeScope(j, at, &t.scope));
    ROLLWEAR_RETURN_IF_ERROR(DecodeRollSpread(j, at, &t));
    // The family's own rules (term_family.h): roll_effect and roll_id go
    // together, the reference level is offset_per_level's, the per-roll
    // spread roll_effect's, the power form's center is > 0.
    if (std::optional<TermFieldError> e = FamilyOf(t.form).CheckStored(t)) {
      return Bad(at + e->field, e->message);
    }
    if (t.IsMeasurementTerm() && !t.scope.grade.empty()) {
      // A reading is of a roll, not of a grade (model_eval.h).
      return Bad(at + "scope.grade",
                 "a measurement term cannot be scoped by grade");
    }
    if ((t.IsMeasurementTerm() || t.form == TermForm::kRollEffect) &&
        !t.scope.gate.empty()) {
      // A gate selects passes; a reading is of a roll, and a roll's own
      // factor acts on all its wear.
      return Bad(at + "scope.gate",
                 "a measurement term or a roll's own factor cannot be gated");
    }
    out->push_back(std::move(t));
  }
  return Status::Ok();
}

// The recurrent network's model: its own versioned text form under "ann",
// and the noise model.
Status DecodeAnn(const Json& doc, const Json& ann, WearModel* m) {
  if (!ann.is_string()) return Bad("ann", "must be the network's text form");
  StatusOr<AnnModel> net = ParseAnnModel(ann.get<std::string>());
  if (!net.ok()) return Bad("ann", net.status().message());
  ROLLWEAR_RETURN_IF_ERROR(net->Validate());
  m->ann = std::make_shared<const AnnModel>(std::move(net).value());
  ROLLWEAR_RETURN_IF_ERROR(ReadScalar(doc, "noise_sd_um", &m->noise_sd_um));
  ROLLWEAR_RETURN_IF_ERROR(ReadScalar(doc, "noise_rel", &m->noise_rel));
  return Status::Ok();
}

// The K structure: "option" and the position, roll-type and grade labels.
Status DecodeStructure(const Json& doc, WearModel* m) {
  auto option = doc.find("option");
  if (option == doc.end() || !option->is_number_integer()) {
    return Bad("option", "must be 1, 2 or 3");
  }
  std::vector<std::string> positions, roll_types, grades;
  ROLLWEAR_RETURN_IF_ERROR(ReadLabels(doc, "positions", &positions));
  ROLLWEAR_RETURN_IF_ERROR(ReadLabels(doc, "roll_types", &roll_types));
  ROLLWEAR_RETURN_IF_ERROR(ReadLabels(doc, "grades", &grades));
  StatusOr<KStructure> ks =
      KStructure::ForOption(option->get<int>(), std::move(positions),
                            std::move(roll_types), std::move(grades));
  if (!ks.ok()) return Bad("option", ks.status().message());
  m->structure = std::move(ks).value();
  return Status::Ok();
}

// The coefficients: the array "k" in structure order, or else the object
// "coefficients" by name.
Status DecodeCoefficients(const Json& doc, WearModel* m) {
  const int n = m->structure.num_coefficients();
  m->k.assign(n, 0.0);
  auto k_array = doc.find("k");
  if (k_array != doc.end()) {
    if (!k_array->is_array() || static_cast<int>(k_array->size()) != n) {
      return Bad("k", "must be an array of " + std::to_string(n) + " numbers");
    }
    for (int i = 0; i < n; ++i) {
      if (!ReadNumber((*k_array)[i], &m->k[i])) {
        return Bad("k", "must hold numbers");
      }
    }
    return Status::Ok();
  }
  auto coefs = doc.find("coefficients");
  if (coefs == doc.end() || !coefs->is_object()) {
    return Bad("coefficients", "must be an object of name: value");
  }
  if (static_cast<int>(coefs->size()) != n) {
    return Bad("coefficients", "has " + std::to_string(coefs->size()) +
                                   " entries, the structure needs " +
                                   std::to_string(n));
  }
  for (int i = 0; i < n; ++i) {
    const std::string& name = m->structure.CoefficientName(i);
    auto v = coefs->find(name);
    if (v == coefs->end() || !ReadNumber(*v, &m->k[i])) {
      return Bad("coefficients." + name, "missing or not a number");
    }
  }
  return Status::Ok();
}

// "covariance": absent, [] or num_parameters() rows of as many numbers.
Status DecodeCovariance(const Json& doc, WearModel* m) {
  auto cov = doc.find("covariance");
  if (cov == doc.end() || cov->empty()) return Status::Ok();
  const int p = m->num_parameters();
  if (!cov->is_array() || static_cast<int>(cov->size()) != p) {
    return Bad("covariance", "must be a " + std::to_string(p) + "x" +
                                 std::to_string(p) + " array of arrays or []");
  }
  m->covariance.resize(p, p);
  for (int r = 0; r < p; ++r) {
    const Json& row = (*cov)[r];
    if (!row.is_array() || static_cast<int>(row.size()) != p) {
      return Bad("covariance[" + std::to_string(r) + "]",
                 "must hold " + std::to_string(p) + " numbers");
    }
    for (int c = 0; c < p; ++c) {
      if (!ReadNumber(row[c], &m->covariance(r, c))) {
        return Bad(
            "covariance[" + std::to_string(r) + "][" + std::to_string(c) + "]",
            "must be a number");
      }
    }
  }
  return Status::Ok();
}

StatusOr<WearModel> Decode(const Json& doc) {
  if (!doc.is_object()) return Bad("(document)", "must be an object");
  WearModel m;
  auto law = doc.find("law");
  if (law == doc.end() || !law->is_string() ||
      !ParseWearLaw(law->get<std::string>(), &m.law)) {
    return Bad("law", "must be one of wang, nikitenko, cao");
  }
  auto ann = doc.find("ann");
  if (ann != doc.end()) {
    ROLLWEAR_RETURN_IF_ERROR(DecodeAnn(doc, *ann, &m));
    return m;
  }
  ROLLWEAR_RETURN_IF_ERROR(DecodeStructure(doc, &m));
  ROLLWEAR_RETURN_IF_ERROR(DecodeCoefficients(doc, &m));
  ROLLWEAR_RETURN_IF_ERROR(ReadScalar(doc, "cao_exponent", &m.cao_exponent));
  ROLLWEAR_RETURN_IF_ERROR(ReadScalar(doc, "noise_sd_um", &m.noise_sd_um));
  ROLLWEAR_RETURN_IF_ERROR(ReadScalar(doc, "noise_rel", &m.noise_rel));
  ROLLWEAR_RETURN_IF_ERROR(DecodeCovariance(doc, &m));
  ROLLWEAR_RETURN_IF_ERROR(DecodeTerms(doc, &m.terms));
  return m;
}

}  // namespace

std::string EncodeWearModel(const WearModel& model) {
  const KStructure& s = model.structure;
  Json doc = Json::object();
  doc["format"] = kFormat;
  doc["law"] = WearLawName(model.law);
  if (model.is_ann()) {
    doc["option"] = 0;
    doc["ann"] = SerializeAnnModel(*model.ann);
    doc["noise_sd_um"] = Number(model.noise_sd_um);
    doc["noise_rel"] = Number(model.noise_rel);
    return doc.dump();
  }
  doc["option"] = s.option();
  doc["positions"] = s.positions();
  doc["roll_types"] = s.roll_types();
  doc["grades"] = s.grades();
  Json coefs = Json::object();
  for (int i = 0; i < s.num_coefficients(); ++i) {
    coefs[s.CoefficientName(i)] = Number(model.k[i]);
  }
  doc["coefficients"] = std::move(coefs);
  if (!NamesUnique(s)) {
    Json k = Json::array();
    for (double v : model.k) k.push_back(Number(v));
    doc["k"] = std::move(k);
  }
  doc["cao_exponent"] = Number(model.cao_exponent);
  Json cov = Json::array();
  for (Eigen::Index r = 0; r < model.covariance.rows(); ++r) {
    Json row = Json::array();
    for (Eigen::Index c = 0; c < model.covariance.cols(); ++c) {
      row.push_back(Number(model.covariance(r, c)));
    }
    cov.push_back(std::move(row));
  }
  doc["covariance"] = std::move(cov);
  doc["noise_sd_um"] = Number(model.noise_sd_um);
  doc["noise_rel"] = Number(model.noise_rel);
  Json terms = Json::array();
  for (const ModelTerm& t : model.terms) terms.push_back(EncodeTerm(t));
  doc["terms"] = std::move(terms);
  return doc.dump();
}

std::string EncodeTerms(const std::vector<ModelTerm>& terms) {
  Json arr = Json::array();
  for (const ModelTerm& t : terms) arr.push_back(EncodeTerm(t));
  return arr.dump();
}

StatusOr<std::vector<ModelTerm>> DecodeModelTerms(std::string_view json) {
  Json doc = Json::parse(json.begin(), json.end(), nullptr,
                         /*allow_exceptions=*/false);
  if (doc.is_discarded() || !doc.is_object()) {
    return Status::InvalidArgument("terms: not a JSON object");
  }
  auto adopted = doc.find("adopted_model");
  const Json& holder = adopted != doc.end() ? *adopted : doc;
  if (!holder.is_object() || !holder.contains("terms")) {
    return Status::InvalidArgument(
        "terms: no \"terms\" array (expected a model or the JSON of "
        "`rollwear diagnose --json`)");
  }
  std::vector<ModelTerm> terms;
  try {
    ROLLWEAR_RETURN_IF_ERROR(DecodeTerms(holder, &terms));
  } catch (const std::exception& e) {
    return Status::InvalidArgument(std::string("terms: ") + e.what());
  }
  for (size_t i = 0; i < terms.size(); ++i) {
    const ModelTerm& t = terms[i];
    const std::string at = "terms[" + std::to_string(i) + "].";
    if (static_cast<int>(t.params.size()) != t.NumParams()) {
      return Bad(at + "params", "has " + std::to_string(t.params.size()) +
                                    " numbers, the form needs " +
                                    std::to_string(t.NumParams()));
    }
    for (double p : t.params) {
      if (!std::isfinite(p)) return Bad(at + "params", "must be finite");
    }
    if (!std::isfinite(t.center)) return Bad(at + "center", "must be finite");
    if (!(std::isfinite(t.scale) &&
          (t.scale > 0 || (FamilyOf(t.form).SignedScale() && t.scale != 0)))) {
      return Bad(at + "scale", FamilyOf(t.form).SignedScale()
                                   ? "must be a finite number other than 0"
                                   : "must be > 0");
    }
    if (!std::is_sorted(t.edges.begin(), t.edges.end())) {
      return Bad(at + "edges", "must be ascending");
    }
  }
  return terms;
}

std::string EncodeModelJson(const WearModel& model,
                            const std::optional<ProfileFit>& profile) {
  std::string text = EncodeWearModel(model);
  if (!profile.has_value()) return text;
  Json doc = Json::parse(text);
  const auto names = ProfileShapeNames();
  const auto values = ProfileShapeValues(profile->shape);
  Json p = Json::object();
  Json se = Json::object();
  for (int i = 0; i < kProfileShapeParameters; ++i) {
    p[names[i]] = Number(values[i]);
    se[names[i]] = Number(profile->std_error[i]);
  }
  p["std_error"] = std::move(se);
  // The shape's roll-clustered covariance, rows in the order of the names.
  Json cov = Json::array();
  for (const auto& row : profile->covariance) {
    Json r = Json::array();
    for (double v : row) r.push_back(Number(v));
    cov.push_back(std::move(r));
  }
  p["covariance"] = std::move(cov);
  p["residual_sd_um"] = Number(profile->residual_sd_um);
  p["within_roll_sd_um"] = Number(profile->within_roll_sd_um);
  p["n_points_train"] = profile->train.n_points;
  p["gap_train_um"] = Number(profile->train.gap_um);
  p["n_points_val"] = profile->validation.n_points;
  p["gap_val_um"] = Number(profile->validation.gap_um);
  doc["profile"] = std::move(p);
  return doc.dump();
}

StatusOr<std::optional<ProfileFit>> DecodeProfileShape(std::string_view json) {
  Json doc = Json::parse(json.begin(), json.end(), nullptr,
                         /*allow_exceptions=*/false);
  if (doc.is_discarded()) {
    return Status::InvalidArgument("model json: not valid JSON");
  }
  if (!doc.is_object() || !doc.contains("profile")) {
    return std::optional<ProfileFit>();
  }
  const Json& p = doc["profile"];
  if (!p.is_object()) return Bad("profile", "must be an object");
  const auto names = ProfileShapeNames();
  std::array<double, kProfileShapeParameters> v{};
  ProfileFit fit;
  const auto num = [](const Json& j) {
    double x = 0;
    if (!ReadNumber(j, &x)) throw std::invalid_argument("not a number");
    return x;
  };
  try {
    for (int i = 0; i < kProfileShapeParameters; ++i) {
      v[i] = num(p.at(names[i]));
      fit.std_error[i] = num(p.at("std_error").at(names[i]));
    }
    fit.residual_sd_um = num(p.at("residual_sd_um"));
    fit.within_roll_sd_um = num(p.value("within_roll_sd_um", Json("NaN")));
    if (p.contains("covariance")) {
      const Json& cov = p.at("covariance");
      if (!cov.is_array() || cov.size() != kProfileShapeParameters) {
        return Bad("profile.covariance", "must be a 5 x 5 array of numbers");
      }
      for (int i = 0; i < kProfileShapeParameters; ++i) {
        if (!cov[i].is_array() || cov[i].size() != kProfileShapeParameters) {
          return Bad("profile.covariance[" + std::to_string(i) + "]",
                     "must be an array of 5 numbers");
        }
        for (int j = 0; j < kProfileShapeParameters; ++j) {
          fit.covariance[i][j] = num(cov[i][j]);
        }
      }
    } else {
      // Stored before the covariance was kept: its diagonal only.
      for (int i = 0; i < kProfileShapeParameters; ++i) {
        fit.covariance[i][i] = fit.std_error[i] * fit.std_error[i];
      }
    }
    fit.train.n_points = p.value("n_points_train", 0);
    fit.train.gap_um = num(p.value("gap_train_um", Json("NaN")));
    fit.validation.n_points = p.value("n_points_val", 0);
    fit.validation.gap_um = num(p.value("gap_val_um", Json("NaN")));
  } catch (const std::exception& e) {
    return Bad("profile", e.what());
  }
  fit.shape.beta2 = v[0];
  fit.shape.beta4 = v[1];
  for (int m = 0; m < kEdgeRamps; ++m) fit.shape.alpha[m] = v[2 + m];
  return std::optional<ProfileFit>(std::move(fit));
}

StatusOr<WearModel> DecodeWearModel(std::string_view json) {
  Json doc = Json::parse(json.begin(), json.end(), nullptr,
                         /*allow_exceptions=*/false);
  if (doc.is_discarded()) {
    return Status::InvalidArgument("model json: not valid JSON");
  }
  try {
    return Decode(doc);
  } catch (const std::exception& e) {
    return Status::InvalidArgument(std::string("model json: ") + e.what());
  }
}

}  // namespace rollwear::storage
