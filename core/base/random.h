// Reproducible random numbers for splits, initial sets and training: a
// std::mt19937_64 engine (its output sequence is fixed by the C++ standard)
// with explicit transforms, so results do not depend on how a standard
// library implements its distributions; and SplitMix64 to derive
// independent seeds (per simulated campaign, per ensemble member).
//
// Thread-safety: a Random object is not thread-safe; use one per thread.
// SplitMix64 is a pure function.
#ifndef ROLLWEAR_CORE_BASE_RANDOM_H_
#define ROLLWEAR_CORE_BASE_RANDOM_H_

#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

namespace rollwear {

// The SplitMix64 finaliser (Steele, Lea & Flood, "Fast splittable
// pseudorandom number generators", OOPSLA 2014): a bijective 64-bit mix,
//   x += 0x9e3779b97f4a7c15; x = (x ^ x>>30) * 0xbf58476d1ce4e5b9;
//   x = (x ^ x>>27) * 0x94d049bb133111eb; return x ^ x>>31,
// used to turn (seed, stream, index) into a well-spread engine seed.
constexpr uint64_t SplitMix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

class Random {
 public:
  explicit Random(uint64_t seed) : engine_(seed) {}

  // Uniform in [0, 1) with 53 random bits.
  double Uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  // Uniform integer in [0, n) (n > 0), by rejection to avoid modulo bias.
  uint64_t Below(uint64_t n) {
    const uint64_t limit = UINT64_MAX - UINT64_MAX % n;
    uint64_t x;
    do {
      x = engine_();
    } while (x >= limit);
    return x % n;
  }
  // Standard normal by Box-Muller (Box & Muller 1958).
  double Normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1;
    do {
      u1 = Uniform();
    } while (u1 <= 0);
    const double u2 = Uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2 * 3.14159265358979323846 * u2);
    has_spare_ = true;
    return r * std::cos(2 * 3.14159265358979323846 * u2);
  }
  double Normal(double mean, double sd) { return mean + sd * Normal(); }
  // Fisher-Yates shuffle (Knuth, TAOCP vol. 2, Algorithm P).
  template <typename T>
  void Shuffle(std::vector<T>* v) {
    for (size_t i = v->size(); i > 1; --i) {
      std::swap((*v)[i - 1], (*v)[Below(i)]);
    }
  }

 private:
  std::mt19937_64 engine_;
  bool has_spare_ = false;
  double spare_ = 0;
};

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_BASE_RANDOM_H_
