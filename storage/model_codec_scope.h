// The stored form of a model term's scope (model_codec.cc's "scope"
// object): where the term applies, its place, grade and gate
// (core/model/model_terms.h, TermScope), written and read with each
// field's rules; absent fields mean everywhere, so models stored before
// scopes (and gates) existed read unchanged.
// Thread-safety: stateless functions, reentrant.
#ifndef ROLLWEAR_STORAGE_MODEL_CODEC_SCOPE_H_
#define ROLLWEAR_STORAGE_MODEL_CODEC_SCOPE_H_

#include <string>

#include <nlohmann/json.hpp>

#include "core/base/status.h"
#include "core/model/model_terms.h"

namespace rollwear::storage {

// The codec's error for a stored field that breaks its rule:
// InvalidArgument "model json: <field>: <rule>".
Status BadModelField(const std::string& field, const std::string& rule);

// {"stand": "F7", "position": "top", "roll_type": "...", "grade": "...",
// "gate": "speed_mps", "gate_side": "above", "gate_at": 11.5}, the fields
// of `scope` that are set.
nlohmann::ordered_json EncodeScope(const TermScope& scope);

// Reads the optional "scope" of stored term `term` (whose fields are named
// `at` + "scope..." in errors) into `scope`.
Status DecodeScope(const nlohmann::ordered_json& term, const std::string& at,
                   TermScope* scope);

}  // namespace rollwear::storage

#endif  // ROLLWEAR_STORAGE_MODEL_CODEC_SCOPE_H_
