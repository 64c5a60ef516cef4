// The fast path of DecodeCoil (api/codec.h) for POST /v1/coils, the
// endpoint the mill calls for every coil: one pass over the body, no DOM,
// no exceptions, no allocation but the result's own strings and passes.
//
// It accepts only the usual body: one object holding exactly the documented
// members, each once, with the expected JSON types, strings of plain
// printable ASCII (no escape sequences), and values that pass every check
// of the DOM path (DecodeCoilDom: id lengths, timestamp, stand names, 1..7
// passes, nesting within max_depth, and the same CoilRules of
// core/dataset/input_rules.h). On anything else, an
// unknown or repeated member included, it gives up, and DecodeCoil falls
// back to the DOM path, which then accepts or names the error exactly as
// before. Whatever it accepts, the DOM path accepts with an identical
// CoilIn (tests/api/codec_diff_test.cc, fuzz/fuzz_api_decode.cc).
//
// Thread-safety: stateless.
#ifndef ROLLWEAR_API_COIL_FAST_DECODE_H_
#define ROLLWEAR_API_COIL_FAST_DECODE_H_

#include <string_view>

#include "storage/store_types.h"

namespace rollwear::api {

// True: `body` decoded into *out as DecodeCoilDom would have. False: gave
// up; *out is untouched.
bool TryDecodeCoilFast(std::string_view body, int max_depth,
                       storage::CoilIn* out);

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_COIL_FAST_DECODE_H_
