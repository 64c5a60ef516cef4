#include "api/coil_fast_decode.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <span>
#include <string>
#include <string_view>
#include <system_error>

#include "api/codec.h"
#include "core/dataset/dataset.h"
#include "core/dataset/dataset_io.h"
#include "core/dataset/input_rules.h"

namespace rollwear::api {
namespace {

// A coil body nests three levels: the coil, "passes", each pass.
constexpr int kCoilDepth = 3;

enum CoilMember { kCoilId, kCampaignId, kSeq, kRolledAt, kGrade, kPasses };
constexpr std::string_view kCoilMembers[] = {
    "coil_id", "campaign_id", "seq", "rolled_at", "grade", "passes"};

enum PassMember {
  kStand,
  kForce,
  kWidth,
  kLength,
  kEntryThickness,
  kExitThickness,
  kTemperature,
  kSpeed,
  kLubrication,
  kShift
};
constexpr std::string_view kPassMembers[] = {
    "stand",         "force_kn",           "width_mm",
    "length_m",      "entry_thickness_mm", "exit_thickness_mm",
    "temperature_c", "speed_mps",          "lubrication",
    "shift_mm"};

template <size_t N>
constexpr unsigned kAllMembers = (1u << N) - 1;

// Index of `key` in `names`, or -1.
template <size_t N>
int MemberIndex(const std::string_view (&names)[N], std::string_view key) {
  for (size_t i = 0; i < N; ++i) {
    if (names[i] == key) return static_cast<int>(i);
  }
  return -1;
}

// The coil as scanned, its strings still in the body.
struct ScannedCoil {
  std::string_view coil_id;
  std::string_view campaign_id;
  int64_t seq = 0;
  UnixSeconds rolled_at = 0;
  std::string_view grade;
  storage::PassIn passes[kMaxPasses];
  size_t num_passes = 0;
};

bool IsDigit(char c) { return c >= '0' && c <= '9'; }

// Reads one coil body; every method returns false as soon as the body
// leaves the usual shape or breaks a rule, without saying why.
class CoilScanner {
 public:
  explicit CoilScanner(std::string_view body)
      : p_(body.data()), end_(body.data() + body.size()) {}

  bool Coil(ScannedCoil* coil) {
    if (!Next('{')) return false;
    unsigned seen = 0;
    do {
      const int member = Key(kCoilMembers, &seen);
      bool ok = false;
      switch (member) {
        case kCoilId:
          ok = Id(&coil->coil_id);
          break;
        case kCampaignId:
          ok = Id(&coil->campaign_id);
          break;
        case kSeq:
          ok = Seq(&coil->seq);
          break;
        case kRolledAt:
          ok = Timestamp(&coil->rolled_at);
          break;
        case kGrade:
          ok = Id(&coil->grade);
          break;
        case kPasses:
          ok = Passes(coil);
          break;
        default:
          break;
      }
      if (!ok) return false;
    } while (Next(','));
    if (!Next('}') || seen != kAllMembers<std::size(kCoilMembers)>) {
      return false;
    }
    SkipSpace();
    return p_ == end_;
  }

 private:
  // JSON whitespace, the only bytes nlohmann skips between tokens.
  void SkipSpace() {
    while (p_ < end_ &&
           (*p_ == ' ' || *p_ == '\n' || *p_ == '\r' || *p_ == '\t')) {
      ++p_;
    }
  }

  // Consumes `c` when it comes next after whitespace.
  bool Next(char c) {
    SkipSpace();
    if (p_ == end_ || *p_ != c) return false;
    ++p_;
    return true;
  }

  // A string of printable ASCII without escapes, so that its bytes in the
  // body are its value.
  bool PlainString(std::string_view* out) {
    if (!Next('"')) return false;
    const char* start = p_;
    for (; p_ < end_; ++p_) {
      const auto c = static_cast<unsigned char>(*p_);
      if (c == '"') {
        *out = std::string_view(start, static_cast<size_t>(p_ - start));
        ++p_;
        return true;
      }
      if (c < 0x20 || c > 0x7E || c == '\\') return false;
    }
    return false;
  }

  // A member name and its ':'; the index of a member not seen before in
  // this object, else -1.
  template <size_t N>
  int Key(const std::string_view (&names)[N], unsigned* seen) {
    std::string_view key;
    if (!PlainString(&key) || !Next(':')) return -1;
    const int member = MemberIndex(names, key);
    if (member < 0 || (*seen & (1u << member)) != 0) return -1;
    *seen |= 1u << member;
    return member;
  }

  // ObjectReader::Text: at most kMaxIdLength bytes.
  bool Id(std::string_view* out) {
    return PlainString(out) && out->size() <= kMaxIdLength;
  }

  bool Timestamp(UnixSeconds* out) {
    std::string_view text;
    return PlainString(&text) && ParseTimestamp(std::string(text), out);
  }

  bool Stand(int* out) {
    std::string_view text;
    if (!PlainString(&text)) return false;
    *out = ParseStand(std::string(text));
    return *out != 0;
  }

  // A positive integer of at most 10 digits, digits only (its range is
  // CoilRules').
  bool Seq(int64_t* out) {
    SkipSpace();
    const char* start = p_;
    int64_t value = 0;
    while (p_ < end_ && IsDigit(*p_) && p_ - start < 10) {
      value = value * 10 + (*p_ - '0');
      ++p_;
    }
    if (p_ == start || *start == '0') return false;
    *out = value;
    return true;
  }

  // A JSON number (RFC 8259 grammar, which nlohmann's lexer follows) as the
  // double nlohmann's DOM yields for it: from_chars rounds correctly like
  // the strtod nlohmann calls, and an integer token, which the DOM keeps as
  // an integer, converts exactly the same except that "-0" gives +0. Out of
  // range (inf, or a non-zero number that rounds to 0): give up.
  bool Number(double* out) {
    SkipSpace();
    const char* start = p_;
    if (p_ < end_ && *p_ == '-') ++p_;
    if (p_ == end_) return false;
    if (*p_ == '0') {
      ++p_;
    } else if (IsDigit(*p_)) {
      while (p_ < end_ && IsDigit(*p_)) ++p_;
    } else {
      return false;
    }
    bool integral = true;
    if (p_ < end_ && *p_ == '.') {
      integral = false;
      ++p_;
      if (!Digits()) return false;
    }
    if (p_ < end_ && (*p_ == 'e' || *p_ == 'E')) {
      integral = false;
      ++p_;
      if (p_ < end_ && (*p_ == '+' || *p_ == '-')) ++p_;
      if (!Digits()) return false;
    }
    const auto [end, error] = std::from_chars(start, p_, *out);
    if (error != std::errc() || end != p_ || !std::isfinite(*out)) {
      return false;
    }
    if (integral && *out == 0) *out = 0;
    return true;
  }

  // One or more digits.
  bool Digits() {
    const char* start = p_;
    while (p_ < end_ && IsDigit(*p_)) ++p_;
    return p_ > start;
  }

  // ObjectReader::Flag: true, false, 0 or 1 (spelt exactly so).
  bool Flag(bool* out) {
    SkipSpace();
    for (const std::string_view word : {"true", "1", "false", "0"}) {
      if (static_cast<size_t>(end_ - p_) >= word.size() &&
          std::memcmp(p_, word.data(), word.size()) == 0) {
        p_ += word.size();
        *out = word == "true" || word == "1";
        return true;
      }
    }
    return false;
  }

  // 1..kMaxPasses pass objects.
  bool Passes(ScannedCoil* coil) {
    if (!Next('[')) return false;
    do {
      if (coil->num_passes == kMaxPasses) return false;
      if (!Pass(&coil->passes[coil->num_passes++])) return false;
    } while (Next(','));
    return Next(']');
  }

  bool Pass(storage::PassIn* p) {
    if (!Next('{')) return false;
    unsigned seen = 0;
    do {
      const int member = Key(kPassMembers, &seen);
      bool ok = false;
      switch (member) {
        case kStand:
          ok = Stand(&p->stand);
          break;
        case kForce:
          ok = Number(&p->force_kn);
          break;
        case kWidth:
          ok = Number(&p->width_mm);
          break;
        case kLength:
          ok = Number(&p->length_m);
          break;
        case kEntryThickness:
          ok = Number(&p->entry_thickness_mm);
          break;
        case kExitThickness:
          ok = Number(&p->exit_thickness_mm);
          break;
        case kTemperature:
          ok = Number(&p->temperature_c);
          break;
        case kSpeed:
          ok = Number(&p->speed_mps);
          break;
        case kLubrication:
          ok = Flag(&p->lubrication);
          break;
        case kShift:
          ok = Number(&p->shift_mm);
          break;
        default:
          break;
      }
      if (!ok) return false;
    } while (Next(','));
    return Next('}') && seen == kAllMembers<std::size(kPassMembers)>;
  }

  const char* p_;
  const char* const end_;
};

}  // namespace

bool TryDecodeCoilFast(std::string_view body, int max_depth,
                       storage::CoilIn* out) {
  if (max_depth < kCoilDepth) return false;
  ScannedCoil coil;
  if (!CoilScanner(body).Coil(&coil) ||
      !CoilRules(coil.coil_id, coil.campaign_id, coil.seq, coil.grade,
                 std::span(coil.passes, coil.num_passes))
           .empty()) {
    return false;
  }
  out->coil_id.assign(coil.coil_id);
  out->campaign_id.assign(coil.campaign_id);
  out->seq = static_cast<int>(coil.seq);
  out->rolled_at = coil.rolled_at;
  out->grade.assign(coil.grade);
  out->passes.insert(out->passes.end(), coil.passes,
                     coil.passes + coil.num_passes);
  return true;
}

}  // namespace rollwear::api
