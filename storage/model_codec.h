// WearModel <-> JSON: how calibrated models are stored (models.model_json)
// and shown (the api layer reuses it for GET /v1/models/active).
//
//   {"format": 1, "law": "wang", "option": 1,
//    "positions": ["F6/top", ...], "roll_types": [...], "grades": [...],
//    "coefficients": {"kF[F6/top]": 0.33, ...},
//    "cao_exponent": 1.0,
//    "covariance": [[...], ...],          // (log k..., a); [] when unknown
//    "noise_sd_um": 4.1, "noise_rel": 0.05,
//    "terms": [{"covariate": "campaign_length_before_m",
//               "form": "saturating", "params": [...], "center": 0,
//               "scale": 1, "edges": [], "num_levels": 0}, ...]}
//   (a per-level term also has "levels": its factor's level labels)
//
// The recurrent network (WearModel::ann) is stored as
//   {"format": 1, "law": "wang", "option": 0, "ann": "<SerializeAnnModel
//    text>", "noise_sd_um": ..., "noise_rel": ...}
//
// A model version with a calibrated profile shape
// (core/model/profile_calibration.h, fitted by core/fit/profile_fit.h) stores
// it beside the model as
//   "profile": {"beta2", "beta4", "alpha1", "alpha2", "alpha3",
//               "std_error": {"beta2", ...}, "residual_sd_um",
//               "n_points_train", "gap_train_um", "n_points_val",
//               "gap_val_um"}
// (EncodeModelJson); a model JSON without it (every model stored before
// schema 7) has no profile shape: the default g = 1.
//
// Numbers are written in the shortest form that reads back to the same
// double, so Decode(Encode(m)) equals m exactly (every coefficient, every
// covariance entry). Non-finite covariance entries are written as the
// strings "NaN", "Infinity", "-Infinity". Should two coefficients share a
// name (labels containing '|' or ']'), an extra "k" array in coefficient
// order makes the round trip exact anyway.
//
// Thread-safety: pure functions.
#ifndef ROLLWEAR_STORAGE_MODEL_CODEC_H_
#define ROLLWEAR_STORAGE_MODEL_CODEC_H_

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/status.h"
#include "core/model/model_terms.h"
#include "core/model/profile_calibration.h"
#include "core/model/wear_model.h"

namespace rollwear::storage {

// Compact JSON text of `model`.
std::string EncodeWearModel(const WearModel& model);

// EncodeWearModel's text plus "profile" when `profile` is set.
std::string EncodeModelJson(const WearModel& model,
                            const std::optional<ProfileFit>& profile);
// The "profile" of a model JSON; nullopt when it has none. InvalidArgument
// naming the field when present but malformed.
StatusOr<std::optional<ProfileFit>> DecodeProfileShape(std::string_view json);

// Parses EncodeWearModel's output; InvalidArgument naming the field when
// the text is not a valid model.
StatusOr<WearModel> DecodeWearModel(std::string_view json);

// The "terms" array alone (JSON array text), as EncodeWearModel writes it.
std::string EncodeTerms(const std::vector<ModelTerm>& terms);

// The terms of a model JSON, or of the "adopted_model" of the JSON that
// `rollwear diagnose --json` writes; InvalidArgument naming the field.
StatusOr<std::vector<ModelTerm>> DecodeModelTerms(std::string_view json);

}  // namespace rollwear::storage

#endif  // ROLLWEAR_STORAGE_MODEL_CODEC_H_
