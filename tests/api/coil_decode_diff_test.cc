// DecodeCoil's fast path (api/coil_fast_decode.h) against its DOM path
// (DecodeCoilDom) on many bodies: valid coils with random values, member
// orders and whitespace; the same with members removed, repeated, added or
// given wrong types, special numbers, ids and timestamps, escapes, deep
// nesting; byte-level mutations; and the fuzz corpus. For every body:
// whatever the fast path accepts the DOM path accepts with an identical
// CoilIn (doubles bit for bit), a fast path that gives up leaves *out
// untouched, and DecodeCoil answers exactly as the DOM path (the same CoilIn
// or the same error).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "api/codec.h"
#include "api/coil_fast_decode.h"

namespace rollwear::api {
namespace {

using Rng = std::mt19937_64;

int Uniform(Rng& rng, int lo, int hi) {
  return std::uniform_int_distribution<int>(lo, hi)(rng);
}
double Real(Rng& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}
template <typename T, size_t N>
const T& Pick(Rng& rng, const T (&items)[N]) {
  return items[Uniform(rng, 0, static_cast<int>(N) - 1)];
}

// ---- Bodies as members with raw JSON values, serialised with random
// whitespace.

struct Member {
  std::string key;    // raw JSON text, quotes included
  std::string value;  // raw JSON text
};
using Object = std::vector<Member>;

struct Body {
  Object coil;  // "passes" holds kPassesSlot until serialised
  std::vector<Object> passes;
};
constexpr char kPassesSlot[] = "<passes>";

std::string Quote(std::string_view s) { return "\"" + std::string(s) + "\""; }

std::string Space(Rng& rng, int mode) {
  static const char* const kSpaces[] = {" ", "\n", "\t", "\r\n", "  ", "\n  "};
  if (mode == 0 || Uniform(rng, 0, 3) != 0) return "";
  return Pick(rng, kSpaces);
}

std::string Serialize(const Object& object, const std::vector<Object>* passes,
                      Rng& rng, int mode) {
  std::string out = "{";
  for (size_t i = 0; i < object.size(); ++i) {
    if (i > 0) out += ",";
    out += Space(rng, mode) + object[i].key + Space(rng, mode) + ":" +
           Space(rng, mode);
    if (passes != nullptr && object[i].value == kPassesSlot) {
      out += "[";
      for (size_t k = 0; k < passes->size(); ++k) {
        if (k > 0) out += "," + Space(rng, mode);
        out += Serialize((*passes)[k], nullptr, rng, mode);
      }
      out += Space(rng, mode) + "]";
    } else {
      out += object[i].value;
    }
    out += Space(rng, mode);
  }
  return out + "}";
}

std::string Serialize(const Body& body, Rng& rng) {
  const int mode = Uniform(rng, 0, 1);
  return Space(rng, mode) + Serialize(body.coil, &body.passes, rng, mode) +
         Space(rng, mode);
}

std::string RandomId(Rng& rng) {
  const int n =
      Uniform(rng, 0, 9) == 0 ? Uniform(rng, 1, 200) : Uniform(rng, 1, 16);
  std::string s;
  while (static_cast<int>(s.size()) < n) {
    const char c = static_cast<char>(Uniform(rng, 0x20, 0x7E));
    if (c != '"' && c != '\\') s.push_back(c);
  }
  return Quote(s);
}

std::string RandomTimestamp(Rng& rng) {
  char text[64];
  int n = std::snprintf(text, sizeof(text), "%04d-%02d-%02dT%02d:%02d:%02d",
                        Uniform(rng, 1970, 2099), Uniform(rng, 1, 12),
                        Uniform(rng, 1, 28), Uniform(rng, 0, 23),
                        Uniform(rng, 0, 59), Uniform(rng, 0, 59));
  if (Uniform(rng, 0, 3) == 0) {
    n += std::snprintf(text + n, sizeof(text) - n, ".%d",
                       Uniform(rng, 0, 999999));
  }
  switch (Uniform(rng, 0, 2)) {
    case 0:
      std::snprintf(text + n, sizeof(text) - n, "Z");
      break;
    case 1:
      std::snprintf(text + n, sizeof(text) - n, "%c%02d:%02d",
                    Uniform(rng, 0, 1) ? '+' : '-', Uniform(rng, 0, 14),
                    Uniform(rng, 0, 59));
      break;
    default:
      std::snprintf(text + n, sizeof(text) - n, "%c%02d%02d",
                    Uniform(rng, 0, 1) ? '+' : '-', Uniform(rng, 0, 14),
                    Uniform(rng, 0, 59));
      break;
  }
  return Quote(text);
}

// `v` in one of the ways a client may print it; all are exact enough to
// keep exit < entry.
std::string NumberText(double v, Rng& rng) {
  char text[128];
  switch (Uniform(rng, 0, 6)) {
    case 0:
      std::snprintf(text, sizeof(text), "%.17g", v);
      break;
    case 1:
      std::snprintf(text, sizeof(text), "%.*e", Uniform(rng, 10, 20), v);
      break;
    case 2:
      std::snprintf(text, sizeof(text), "%.*E", Uniform(rng, 10, 16), v);
      break;
    case 3:
      std::snprintf(text, sizeof(text), "%.*f", Uniform(rng, 6, 30), v);
      break;
    case 4:  // an integer token
      std::snprintf(text, sizeof(text), "%.0f", std::round(v));
      break;
    case 5:  // a few decimals, as measurements come
      std::snprintf(text, sizeof(text), "%.*f", Uniform(rng, 1, 3), v);
      break;
    default:
      std::snprintf(text, sizeof(text), "%.40g", v);
      break;
  }
  return text;
}

Object RandomPass(int stand, Rng& rng) {
  const double entry = Real(rng, 1.5, 60);
  // Rounded as NumberText may round, and still below entry.
  const double exit = std::round(entry * Real(rng, 0.5, 0.95) * 10) / 10;
  static const char* const kFlags[] = {"0", "1", "true", "false"};
  Object pass = {
      {Quote("stand"), Quote("F" + std::to_string(stand))},
      {Quote("force_kn"), NumberText(Real(rng, 100, 30000), rng)},
      {Quote("width_mm"), NumberText(Real(rng, 600, 2100), rng)},
      {Quote("length_m"), NumberText(Real(rng, 50, 3000), rng)},
      {Quote("entry_thickness_mm"), NumberText(std::ceil(entry) + 0.5, rng)},
      {Quote("exit_thickness_mm"), NumberText(exit, rng)},
      {Quote("temperature_c"), NumberText(Real(rng, -50, 1200), rng)},
      {Quote("speed_mps"), NumberText(Real(rng, 0.5, 25), rng)},
      {Quote("lubrication"), Pick(rng, kFlags)},
      {Quote("shift_mm"), NumberText(Real(rng, -150, 150), rng)}};
  std::shuffle(pass.begin(), pass.end(), rng);
  return pass;
}

Body RandomBody(Rng& rng) {
  Body body;
  body.coil = {{Quote("coil_id"), RandomId(rng)},
               {Quote("campaign_id"), RandomId(rng)},
               {Quote("seq"), std::to_string(Uniform(rng, 1, 1'000'000'000))},
               {Quote("rolled_at"), RandomTimestamp(rng)},
               {Quote("grade"), RandomId(rng)},
               {Quote("passes"), kPassesSlot}};
  if (Uniform(rng, 0, 1)) std::shuffle(body.coil.begin(), body.coil.end(), rng);
  int stands[] = {1, 2, 3, 4, 5, 6, 7};
  std::shuffle(std::begin(stands), std::end(stands), rng);
  const int n = Uniform(rng, 0, 2) == 0 ? Uniform(rng, 1, 7) : 2;
  for (int i = 0; i < n; ++i) body.passes.push_back(RandomPass(stands[i], rng));
  return body;
}

// ---- Mutations.

const char* const kOddValues[] = {"null",
                                  "true",
                                  "false",
                                  "\"x\"",
                                  "[]",
                                  "{}",
                                  "[1]",
                                  "{\"a\":1}",
                                  "\"12.5\"",
                                  "\"1\"",
                                  "0",
                                  "-0",
                                  "0.0",
                                  "-0.0",
                                  "1e400",
                                  "-1e400",
                                  "1e-400",
                                  "5e-324",
                                  "2.2250738585072014e-308",
                                  "1.7976931348623157e308",
                                  "123456789012345678901234567890",
                                  "18446744073709551615",
                                  "18446744073709551616",
                                  "-9223372036854775808",
                                  "-9223372036854775809",
                                  "1E2",
                                  "1e+2",
                                  "1.0",
                                  "01",
                                  "1.",
                                  ".5",
                                  "+1",
                                  "-",
                                  "1e",
                                  "0x10",
                                  "NaN",
                                  "Infinity",
                                  "-1",
                                  "1",
                                  "2",
                                  "1000000000",
                                  "1000000001",
                                  "999999999",
                                  "4294967297",
                                  "2147483648",
                                  "10000000000",
                                  "1e3",
                                  "tru",
                                  "nul",
                                  "1e0",
                                  "[[[[[[[[[[[[[[[[[[[[]]]]]]]]]]]]]]]]]]]]",
                                  "[[[]]]",
                                  R"("\u0000")",
                                  "3.1 ",
                                  "7e-1",
                                  "0.5",
                                  "1200",
                                  "-273.5"};
const char* const kOddStrings[] = {"\"\"",
                                   "\"F0\"",
                                   "\"F8\"",
                                   "\"f1\"",
                                   "\"F1 \"",
                                   "\"F\"",
                                   "\"F10\"",
                                   R"("F\u0031")",
                                   "\"F6\"",
                                   "\"F7\"",
                                   "\"top\"",
                                   R"("K\"1")",
                                   R"("K\\1")",
                                   R"("K\u0000")",
                                   R"("K\u00e9")",
                                   R"("\ud83d\ude00")",
                                   R"("\ud83d")",
                                   "\"K\xC3\xA9\"",
                                   "\"K\xFF\"",
                                   "\"K\x01\"",
                                   "\"K\t1\"",
                                   "\"K\x7F\"",
                                   R"("K\/1")",
                                   R"("K\x")",
                                   "\"2026-03-01T06:00:00Z\"",
                                   "\"2026-02-30T00:00:00Z\"",
                                   "\"2026-03-01T06:00:00\"",
                                   "\"2026-03-01 06:00:00Z\"",
                                   "\"2026-03-01T06:00:00.5+01:00\"",
                                   "\"2026-03-01T06:00:00z\"",
                                   R"("2026-03-01T06:00:00\u005a")",
                                   "\"2026-03-01T24:00:00Z\"",
                                   "\"2026-03-01T06:00:00+2400\""};
const char* const kOddKeys[] = {
    R"("coil\u005fid")", "\"Coil_id\"",  "\"seq \"", "\"\"",
    "\"passes\"",        "\"stand\"",    "\"note\"", "\"force_kn\"",
    "\"shift_mm\"",      R"("s\u0065q")"};

std::string LongId(size_t bytes, std::string_view tail) {
  return Quote(std::string(bytes, 'a') + std::string(tail));
}

// One structural change to a random member of the coil or of a pass.
void Mutate(Body* body, Rng& rng) {
  Object* object = &body->coil;
  if (!body->passes.empty() && Uniform(rng, 0, 2) != 0) {
    object = &body->passes[Uniform(rng, 0,
                                   static_cast<int>(body->passes.size()) - 1)];
  }
  if (object->empty()) return;
  Member& m = (*object)[Uniform(rng, 0, static_cast<int>(object->size()) - 1)];
  if (m.value == kPassesSlot && Uniform(rng, 0, 1)) {
    switch (Uniform(rng, 0, 3)) {
      case 0:
        body->passes.clear();
        return;
      case 1:  // more passes than stands
        while (body->passes.size() < 8) {
          body->passes.push_back(RandomPass(Uniform(rng, 1, 7), rng));
        }
        return;
      case 2:
        if (!body->passes.empty()) {
          body->passes.push_back(body->passes[0]);  // the same stand again
        }
        return;
      default:
        m.value = Pick(rng, kOddValues);
        return;
    }
  }
  switch (Uniform(rng, 0, 9)) {
    case 0:
      object->erase(object->begin() + (&m - object->data()));
      return;
    case 1: {  // the member twice, with the same or another value
      Member copy = m;
      if (Uniform(rng, 0, 1)) copy.value = Pick(rng, kOddValues);
      object->insert(
          object->begin() + Uniform(rng, 0, static_cast<int>(object->size())),
          copy);
      return;
    }
    case 2:
      object->push_back({Pick(rng, kOddKeys), Uniform(rng, 0, 1)
                                                  ? Pick(rng, kOddValues)
                                                  : Pick(rng, kOddStrings)});
      return;
    case 3:
    case 4:
      m.value = Pick(rng, kOddValues);
      return;
    case 5:
    case 6:
      m.value = Pick(rng, kOddStrings);
      return;
    case 7:
      m.key = Pick(rng, kOddKeys);
      return;
    case 8: {
      static const char* const kTails[] = {"", "\\/", "\\u0041", "\xC3\xA9"};
      m.value = LongId(Uniform(rng, 0, 1) ? 199 : 200, Pick(rng, kTails));
      return;
    }
    default:
      if (m.value.size() > 2) m.value = "\"" + m.value + "\"";  // as a string
      return;
  }
}

// One byte-level change to the text.
void MutateText(std::string* text, Rng& rng) {
  static const char kBytes[] = {
      '{',  '}',  '[',  ']', ',', ':', '"', '\\', ' ',    '\t',   '\n',
      '\v', '\f', '\0', '0', '-', 'e', '.', 'x',  '\xEF', '\xBB', '\xFF'};
  const size_t at = Uniform(rng, 0, static_cast<int>(text->size()));
  switch (Uniform(rng, 0, 5)) {
    case 0:
      text->resize(at);
      return;
    case 1:
      text->insert(at, 1, Pick(rng, kBytes));
      return;
    case 2:
      if (at < text->size()) text->erase(at, 1);
      return;
    case 3:
      if (at < text->size()) (*text)[at] = Pick(rng, kBytes);
      return;
    case 4: {
      static const char* const kAround[] = {"\xEF\xBB\xBF", " ", "[",
                                            "\xC2\xA0"};
      text->insert(0, Pick(rng, kAround));
      return;
    }
    default: {
      static const char* const kAfter[] = {"x", ",", "}", "{}", " \n", "]"};
      text->append(Pick(rng, kAfter));
      return;
    }
  }
}

// ---- The comparison.

std::string Describe(const storage::CoilIn& c) {
  std::ostringstream out;
  out << c.coil_id << "|" << c.campaign_id << "|" << c.seq << "|" << c.rolled_at
      << "|" << c.grade;
  char text[64];
  for (const storage::PassIn& p : c.passes) {
    out << " [F" << p.stand;
    for (double v :
         {p.force_kn, p.width_mm, p.length_m, p.entry_thickness_mm,
          p.exit_thickness_mm, p.temperature_c, p.speed_mps, p.shift_mm}) {
      std::snprintf(text, sizeof(text), " %a", v);
      out << text;
    }
    out << " " << p.lubrication << "]";
  }
  return out.str();
}

std::string Printable(std::string_view body) {
  std::string out;
  for (unsigned char c : body.substr(0, 800)) {
    if (c >= 0x20 && c < 0x7F) {
      out.push_back(static_cast<char>(c));
    } else {
      char text[8];
      std::snprintf(text, sizeof(text), "\\x%02x", c);
      out += text;
    }
  }
  return out;
}

// Counts over one test, to check the fast path did its share.
struct Tally {
  int bodies = 0;
  int dom_accepted = 0;
  int fast_accepted = 0;
  ~Tally() {
    std::printf("  %d bodies: DOM path accepted %d, fast path %d\n", bodies,
                dom_accepted, fast_accepted);
  }
};

::testing::AssertionResult Agree(std::string_view body, int max_depth,
                                 Tally* tally) {
  ++tally->bodies;
  storage::CoilIn dom;
  ApiError dom_error;
  const bool dom_ok = DecodeCoilDom(body, max_depth, &dom, &dom_error);
  storage::CoilIn fast;
  const bool fast_ok = TryDecodeCoilFast(body, max_depth, &fast);
  storage::CoilIn decoded;
  ApiError error;
  const bool ok = DecodeCoil(body, max_depth, &decoded, &error);
  tally->dom_accepted += dom_ok;
  tally->fast_accepted += fast_ok;
  const std::string where =
      " (max_depth " + std::to_string(max_depth) + ") " + Printable(body);
  if (fast_ok && !dom_ok) {
    return ::testing::AssertionFailure()
           << "fast path accepted what the DOM path refuses ("
           << dom_error.message << ")" << where;
  }
  if (fast_ok && Describe(fast) != Describe(dom)) {
    return ::testing::AssertionFailure()
           << "fast " << Describe(fast) << " vs DOM " << Describe(dom) << where;
  }
  if (!fast_ok && Describe(fast) != Describe(storage::CoilIn())) {
    return ::testing::AssertionFailure() << "gave up but wrote *out" << where;
  }
  if (ok != dom_ok || Describe(decoded) != Describe(dom) ||
      error.status != dom_error.status || error.code != dom_error.code ||
      error.message != dom_error.message || error.field != dom_error.field) {
    return ::testing::AssertionFailure()
           << "DecodeCoil answered " << ok << " " << error.message
           << Describe(decoded) << ", the DOM path " << dom_ok << " "
           << dom_error.message << Describe(dom) << where;
  }
  return ::testing::AssertionSuccess();
}

TEST(CoilDecodeDiffTest, ValidBodiesTakeTheFastPathWithTheSameResult) {
  Rng rng(1);
  Tally tally;
  for (int i = 0; i < 20'000; ++i) {
    const std::string text = Serialize(RandomBody(rng), rng);
    ASSERT_TRUE(Agree(text, 16, &tally)) << "case " << i;
  }
  // Every generated body is valid and plain, so the fast path takes all.
  EXPECT_EQ(tally.dom_accepted, tally.bodies);
  EXPECT_EQ(tally.fast_accepted, tally.bodies);
}

TEST(CoilDecodeDiffTest, TheBenchmarkBodyTakesTheFastPath) {
  const std::string body =
      R"({"coil_id":"K1","campaign_id":"C1","seq":1,)"
      R"("rolled_at":"2030-01-01T06:00:00Z","grade":"CQ","passes":[)"
      R"({"stand":"F6","force_kn":8294.4,"width_mm":1031,"length_m":509.6,)"
      R"("entry_thickness_mm":5.81,"exit_thickness_mm":4.561,)"
      R"("temperature_c":946.3,"speed_mps":8.95,"lubrication":0,)"
      R"("shift_mm":37.8}]})";
  storage::CoilIn coil;
  ASSERT_TRUE(TryDecodeCoilFast(body, 16, &coil));
  EXPECT_EQ(coil.coil_id, "K1");
  ASSERT_EQ(coil.passes.size(), 1u);
  EXPECT_EQ(coil.passes[0].width_mm, 1031.0);
  Tally tally;
  for (int depth : {1, 2, 3, 4, 16}) EXPECT_TRUE(Agree(body, depth, &tally));
  EXPECT_EQ(tally.fast_accepted, 3);  // not at depths 1 and 2
}

TEST(CoilDecodeDiffTest, MutatedBodiesAnswerAsTheDomPath) {
  Rng rng(2);
  Tally tally;
  for (int i = 0; i < 30'000; ++i) {
    Body body = RandomBody(rng);
    const int changes = Uniform(rng, 1, 3);
    for (int k = 0; k < changes; ++k) Mutate(&body, rng);
    const int depth = Uniform(rng, 0, 9) == 0 ? Uniform(rng, 1, 5) : 16;
    ASSERT_TRUE(Agree(Serialize(body, rng), depth, &tally)) << "case " << i;
  }
  // The fast path takes some, the fallback accepts more (escapes, extra
  // members...), most are refused.
  EXPECT_GT(tally.fast_accepted, tally.bodies / 100);
  EXPECT_GT(tally.dom_accepted, tally.fast_accepted);
  EXPECT_LT(tally.dom_accepted, tally.bodies / 2);
}

TEST(CoilDecodeDiffTest, ByteMutationsAnswerAsTheDomPath) {
  Rng rng(3);
  Tally tally;
  for (int i = 0; i < 30'000; ++i) {
    std::string text = Serialize(RandomBody(rng), rng);
    const int changes = Uniform(rng, 1, 2);
    for (int k = 0; k < changes; ++k) MutateText(&text, rng);
    ASSERT_TRUE(Agree(text, 16, &tally)) << "case " << i;
  }
  EXPECT_GT(tally.fast_accepted, 0);
}

TEST(CoilDecodeDiffTest, FuzzCorpusAnswersAsTheDomPath) {
  // From the source tree CMake names (not __FILE__, which a compiler
  // launcher such as ccache with base_dir may make relative).
  const std::filesystem::path corpus =
      std::filesystem::path(ROLLWEAR_SOURCE_DIR) / "fuzz" / "corpus" /
      "api_decode";
  ASSERT_TRUE(std::filesystem::is_directory(corpus)) << corpus;
  Rng rng(4);
  Tally tally;
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(corpus)) {
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string seed((std::istreambuf_iterator<char>(in)),
                           std::istreambuf_iterator<char>());
    ++files;
    for (int depth : {2, 3, 16}) {
      ASSERT_TRUE(Agree(seed, depth, &tally)) << entry.path();
    }
    for (int i = 0; i < 3'000; ++i) {
      std::string text = seed;
      const int changes = Uniform(rng, 1, 3);
      for (int k = 0; k < changes; ++k) MutateText(&text, rng);
      ASSERT_TRUE(Agree(text, 16, &tally)) << entry.path() << " case " << i;
    }
  }
  EXPECT_GE(files, 1);
  EXPECT_GT(tally.fast_accepted, 0);  // coil_valid and some of its mutants
}

}  // namespace
}  // namespace rollwear::api
