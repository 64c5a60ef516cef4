// The DOM-built answer encoders that api/codec_encode.cc replaced with
// JsonWriter, kept as the reference the new ones must match byte for byte
// (json_writer_test.cc): each builds the nlohmann ordered_json DOM and dumps
// it with error_handler_t::replace, as the daemon did.
//
// Thread-safety: stateless functions.
#ifndef ROLLWEAR_TESTS_API_CODEC_REFERENCE_H_
#define ROLLWEAR_TESTS_API_CODEC_REFERENCE_H_

#include <cstdint>
#include <string>

#include "api/codec.h"
#include "storage/mill_store.h"

namespace rollwear::api::reference {

std::string EncodeError(const ApiError& error);
std::string EncodeCoilAnswer(const storage::CoilIn& in,
                             const storage::CoilOutcome& outcome,
                             int64_t model_version);
std::string EncodeWear(const engine::WearSnapshot& snapshot);
std::string EncodePositionWear(const engine::PositionWear& wear,
                               int64_t model_version);
// One string or double alone, as dump() prints it.
std::string DumpString(const std::string& value);
std::string DumpDouble(double value);

}  // namespace rollwear::api::reference

#endif  // ROLLWEAR_TESTS_API_CODEC_REFERENCE_H_
