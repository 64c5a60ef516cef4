// Reproducible random numbers for splits, initial sets and training: a
// std::mt19937_64 engine (its output sequence is fixed by the C++ standard)
// with explicit transforms, so results do not depend on how a standard
// library implements its distributions.
//
// Thread-safety: a Random object is not thread-safe; use one per thread.
#ifndef ROLLWEAR_CORE_BASE_RANDOM_H_
#define ROLLWEAR_CORE_BASE_RANDOM_H_

#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

namespace rollwear {

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
