// JsonWriter and the answer encoders built on it against nlohmann's dump():
// byte for byte the same text for random strings (quotes, backslashes,
// control characters, valid and invalid UTF-8), random doubles (tiny, huge,
// negative, integral, NaN, infinities) and random answers, compared with the
// DOM-built encoders they replaced (codec_reference.h).
#include "api/json_writer.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "api/codec.h"
#include "tests/api/codec_reference.h"

namespace rollwear::api {
namespace {

using Rng = std::mt19937_64;

int Uniform(Rng& rng, int lo, int hi) {
  return std::uniform_int_distribution<int>(lo, hi)(rng);
}

void AppendUtf8(uint32_t cp, std::string* out) {
  if (cp < 0x80) {
    out->push_back(static_cast<char>(cp));
  } else if (cp < 0x800) {
    out->push_back(static_cast<char>(0xC0 | (cp >> 6)));
    out->push_back(static_cast<char>(0x80 | (cp & 0x3F)));
  } else if (cp < 0x10000) {
    out->push_back(static_cast<char>(0xE0 | (cp >> 12)));
    out->push_back(static_cast<char>(0x80 | ((cp >> 6) & 0x3F)));
    out->push_back(static_cast<char>(0x80 | (cp & 0x3F)));
  } else {
    out->push_back(static_cast<char>(0xF0 | (cp >> 18)));
    out->push_back(static_cast<char>(0x80 | ((cp >> 12) & 0x3F)));
    out->push_back(static_cast<char>(0x80 | ((cp >> 6) & 0x3F)));
    out->push_back(static_cast<char>(0x80 | (cp & 0x3F)));
  }
}

// A code point encoded in 2, 3 or 4 bytes, not a surrogate.
uint32_t RandomCodePoint(Rng& rng) {
  while (true) {
    const int bytes = Uniform(rng, 2, 4);
    const uint32_t cp = bytes == 2   ? Uniform(rng, 0x80, 0x7FF)
                        : bytes == 3 ? Uniform(rng, 0x800, 0xFFFF)
                                     : Uniform(rng, 0x10000, 0x10FFFF);
    if (cp < 0xD800 || cp > 0xDFFF) return cp;
  }
}

// A string that exercises every branch of the escaping: plain ASCII,
// quotes and backslashes, control characters, valid UTF-8 of each length
// (boundaries included), truncated sequences, overlong forms, surrogates,
// code points above U+10FFFF and stray bytes.
std::string RandomText(Rng& rng) {
  static const char* const kBad[] = {"\xC0\x80",
                                     "\xC1\xBF",
                                     "\xE0\x80\x80",
                                     "\xE0\x9F\xBF",
                                     "\xED\xA0\x80",
                                     "\xED\xBF\xBF",
                                     "\xF0\x80\x80\x80",
                                     "\xF0\x8F\xBF\xBF",
                                     "\xF4\x90\x80\x80",
                                     "\xF5\x80\x80\x80",
                                     "\xFE",
                                     "\xFF"};
  static const uint32_t kEdges[] = {0x80,     0x7FF,  0x800,  0xD7FF,
                                    0xE000,   0xFFFD, 0xFFFF, 0x10000,
                                    0x10FFFF, 0xFEFF, 0x2028, 0xE9};
  std::string s;
  const int pieces =
      Uniform(rng, 0, 3) == 0 ? Uniform(rng, 0, 40) : Uniform(rng, 0, 8);
  for (int i = 0; i < pieces; ++i) {
    switch (Uniform(rng, 0, 9)) {
      case 0:
      case 1:
        s.push_back(static_cast<char>(Uniform(rng, 0x20, 0x7E)));
        break;
      case 2:
        s.push_back(Uniform(rng, 0, 1) ? '"' : '\\');
        break;
      case 3:
        s.push_back(static_cast<char>(
            Uniform(rng, 0, 4) == 0 ? 0x7F : Uniform(rng, 0x00, 0x1F)));
        break;
      case 4:
        AppendUtf8(RandomCodePoint(rng), &s);
        break;
      case 5:
        AppendUtf8(
            kEdges[Uniform(rng, 0, static_cast<int>(std::size(kEdges)) - 1)],
            &s);
        break;
      case 6: {  // a valid sequence cut short
        std::string full;
        AppendUtf8(RandomCodePoint(rng), &full);
        s += full.substr(0, Uniform(rng, 1, static_cast<int>(full.size()) - 1));
        break;
      }
      case 7:
        s += kBad[Uniform(rng, 0, static_cast<int>(std::size(kBad)) - 1)];
        break;
      case 8:
        s.push_back(static_cast<char>(Uniform(rng, 0x80, 0xFF)));
        break;
      default:
        s.push_back(static_cast<char>(Uniform(rng, 0, 255)));
        break;
    }
  }
  return s;
}

double RandomDouble(Rng& rng) {
  static const double kSpecial[] = {0.0,
                                    -0.0,
                                    1.0,
                                    -1.0,
                                    1031.0,
                                    0.1,
                                    1.0 / 3,
                                    1e15,
                                    1e16,
                                    999999999999999.0,
                                    9999999999999998.0,
                                    123456789012345.6,
                                    1e-4,
                                    1e-5,
                                    0.00012345,
                                    1e21,
                                    1e22,
                                    1e-7,
                                    std::numeric_limits<double>::denorm_min(),
                                    std::numeric_limits<double>::min(),
                                    std::numeric_limits<double>::max(),
                                    std::numeric_limits<double>::lowest(),
                                    std::numeric_limits<double>::epsilon(),
                                    std::numeric_limits<double>::quiet_NaN(),
                                    -std::numeric_limits<double>::quiet_NaN(),
                                    std::numeric_limits<double>::infinity(),
                                    -std::numeric_limits<double>::infinity(),
                                    9007199254740993.0,
                                    1.229920341416101,
                                    123.4567890123};
  const double sign = Uniform(rng, 0, 3) == 0 ? -1 : 1;
  switch (Uniform(rng, 0, 5)) {
    case 0: {  // any bit pattern, NaN and infinities included
      const uint64_t bits = rng();
      double d;
      std::memcpy(&d, &bits, sizeof(d));
      return d;
    }
    case 1:
      return kSpecial[Uniform(rng, 0,
                              static_cast<int>(std::size(kSpecial)) - 1)];
    case 2: {  // integral, up to beyond 2^53 and 1e15 (the exponent
               // drawn first: argument order is unspecified in C++)
      const int exponent = Uniform(rng, 0, 70);
      return sign * std::round(std::ldexp(
                        std::uniform_real_distribution<double>(0.5, 1)(rng),
                        exponent));
    }
    case 3:  // a measurement with a few decimals
      return sign *
             std::round(std::uniform_real_distribution<double>(0, 1e5)(rng) *
                        1000) /
             1000;
    case 4: {  // tiny to huge (mantissa, then exponent)
      const double mantissa =
          std::uniform_real_distribution<double>(1, 10)(rng);
      return sign * mantissa * std::pow(10.0, Uniform(rng, -330, 310));
    }
    default:
      return sign * std::uniform_real_distribution<double>(0, 20000)(rng);
  }
}

TEST(JsonWriterTest, WritesCompactJson) {
  JsonWriter w;
  w.BeginObject();
  w.Key("a");
  w.BeginArray();
  w.Int(1);
  w.Double(2);
  w.Null();
  w.String("x\"y");
  w.BeginObject();
  w.EndObject();
  w.EndArray();
  w.Key("b");
  w.Bool(false);
  w.Key("c");
  w.Double(std::nan(""));
  w.EndObject();
  EXPECT_EQ(w.Take(), R"({"a":[1,2.0,null,"x\"y",{}],"b":false,"c":null})");
}

TEST(JsonWriterTest, EscapesLikeNlohmann) {
  std::string out;
  AppendJsonString(std::string("\x01\b\t\n\f\r\x1f\x7f/\"\\", 11), &out);
  EXPECT_EQ(out, "\"\\u0001\\b\\t\\n\\f\\r\\u001f\x7f/\\\"\\\\\"");
  out.clear();
  AppendJsonString(std::string("a\0b", 3), &out);
  EXPECT_EQ(out, "\"a\\u0000b\"");
  out.clear();
  // A sequence cut short by the next character loses its bytes to one
  // U+FFFD; the character is kept.
  AppendJsonString(
      "\xE2\x82"
      "A\xE2\x82",
      &out);
  EXPECT_EQ(out,
            "\"\xEF\xBF\xBD"
            "A\xEF\xBF\xBD\"");
}

TEST(JsonWriterTest, EveryShortByteStringMatchesDump) {
  // All strings of one and two bytes, and of three bytes from a lead byte.
  for (int a = 0; a < 256; ++a) {
    for (int b = -1; b < 256; ++b) {
      std::string s(1, static_cast<char>(a));
      if (b >= 0) s.push_back(static_cast<char>(b));
      std::string out;
      AppendJsonString(s, &out);
      ASSERT_EQ(out, reference::DumpString(s)) << a << " " << b;
      if (a >= 0xE0 && b >= 0x80 && b < 0xC0) {
        for (int c : {0x41, 0x7F, 0x80, 0x9F, 0xA0, 0xBF, 0xC0, 0xF0}) {
          std::string t = s + static_cast<char>(c);
          out.clear();
          AppendJsonString(t, &out);
          ASSERT_EQ(out, reference::DumpString(t)) << a << " " << b << " " << c;
        }
      }
    }
  }
}

TEST(JsonWriterTest, RandomStringsMatchDump) {
  Rng rng(20240611);
  for (int i = 0; i < 200'000; ++i) {
    const std::string s = RandomText(rng);
    std::string out;
    AppendJsonString(s, &out);
    ASSERT_EQ(out, reference::DumpString(s)) << "case " << i;
  }
}

TEST(JsonWriterTest, RandomDoublesMatchDump) {
  Rng rng(7);
  for (int i = 0; i < 300'000; ++i) {
    const double d = RandomDouble(rng);
    std::string out;
    AppendJsonDouble(d, &out);
    ASSERT_EQ(out, reference::DumpDouble(d)) << "case " << i;
  }
}

TEST(JsonWriterTest, IntegralDoublesKeepTheirFraction) {
  std::string out;
  AppendJsonDouble(1031.0, &out);
  out += ' ';
  AppendJsonDouble(-0.0, &out);
  out += ' ';
  AppendJsonDouble(999999999999999.0, &out);
  out += ' ';
  AppendJsonDouble(1e15, &out);
  out += ' ';
  AppendJsonDouble(std::numeric_limits<double>::infinity(), &out);
  EXPECT_EQ(out, "1031.0 -0.0 999999999999999.0 1e+15 null");
}

Position RandomPosition(Rng& rng) {
  return Uniform(rng, 0, 1) ? Position::kTop : Position::kBottom;
}

int64_t RandomInt(Rng& rng) {
  switch (Uniform(rng, 0, 3)) {
    case 0:
      return Uniform(rng, -3, 3);
    case 1:
      return std::numeric_limits<int64_t>::max();
    case 2:
      return std::numeric_limits<int64_t>::min();
    default:
      return static_cast<int64_t>(rng());
  }
}

TEST(EncoderDiffTest, CoilAnswersMatchTheDomEncoder) {
  Rng rng(11);
  for (int i = 0; i < 20'000; ++i) {
    storage::CoilIn in;
    in.coil_id = RandomText(rng);
    in.campaign_id = RandomText(rng);
    storage::CoilOutcome outcome;
    outcome.outcome = Uniform(rng, 0, 1) ? storage::WriteOutcome::kCreated
                                         : storage::WriteOutcome::kUnchanged;
    const int n = Uniform(rng, 0, 14);
    for (int k = 0; k < n; ++k) {
      outcome.added.push_back(
          {Uniform(rng, 0, 5) == 0 ? Uniform(rng, -20, 20) : Uniform(rng, 1, 7),
           RandomPosition(rng), RandomText(rng), RandomDouble(rng),
           RandomDouble(rng)});
    }
    const int64_t version = Uniform(rng, 0, 1) ? -1 : RandomInt(rng);
    ASSERT_EQ(EncodeCoilAnswer(in, outcome, version),
              reference::EncodeCoilAnswer(in, outcome, version))
        << "case " << i;
  }
}

engine::PositionWear RandomPositionWear(Rng& rng) {
  engine::PositionWear w;
  w.stand =
      Uniform(rng, 0, 5) == 0 ? Uniform(rng, -20, 20) : Uniform(rng, 1, 7);
  w.position = RandomPosition(rng);
  w.roll_id = RandomText(rng);
  w.roll_type = RandomText(rng);
  w.campaign_id = RandomText(rng);
  w.coils = static_cast<int>(RandomInt(rng));
  w.rolled_length_m = RandomDouble(rng);
  w.predicted_wear_um = RandomDouble(rng);
  w.interval_lo_um = RandomDouble(rng);
  w.interval_hi_um = RandomDouble(rng);
  if (Uniform(rng, 0, 2) > 0) w.wear_limit_um = RandomDouble(rng);
  if (Uniform(rng, 0, 2) > 0) {
    RemainingLife life;
    life.length_m = RandomDouble(rng);
    life.coils = RandomDouble(rng);
    life.length_lo_m = RandomDouble(rng);
    life.coils_lo = RandomDouble(rng);
    if (Uniform(rng, 0, 1) > 0) {
      life.length_hi_m = RandomDouble(rng);
      life.coils_hi = RandomDouble(rng);
    }
    w.remaining = life;
  }
  return w;
}

TEST(EncoderDiffTest, WearAnswersMatchTheDomEncoder) {
  Rng rng(13);
  for (int i = 0; i < 10'000; ++i) {
    engine::WearSnapshot snapshot;
    snapshot.model_version = RandomInt(rng);
    const int n = Uniform(rng, 0, 14);
    for (int k = 0; k < n; ++k) {
      snapshot.positions.push_back(RandomPositionWear(rng));
    }
    ASSERT_EQ(EncodeWear(snapshot), reference::EncodeWear(snapshot))
        << "case " << i;
    const engine::PositionWear one = RandomPositionWear(rng);
    const int64_t version = RandomInt(rng);
    ASSERT_EQ(EncodePositionWear(one, version),
              reference::EncodePositionWear(one, version))
        << "case " << i;
  }
}

TEST(EncoderDiffTest, ErrorAnswersMatchTheDomEncoder) {
  Rng rng(17);
  for (int i = 0; i < 20'000; ++i) {
    ApiError e{Uniform(rng, 400, 599), RandomText(rng), RandomText(rng),
               Uniform(rng, 0, 1) ? std::string() : RandomText(rng)};
    ASSERT_EQ(EncodeError(e), reference::EncodeError(e)) << "case " << i;
  }
}

}  // namespace
}  // namespace rollwear::api
