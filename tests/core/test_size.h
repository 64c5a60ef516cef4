// Sizes of the slow core tests: the paper-size simulations and ANN studies
// run at full size in the Release build (CI phase `readme`) and at a reduced
// size under the sanitizers (phases `asan`, `tsan`: CMake defines
// ROLLWEAR_SANITIZED there), where the same code runs 10-20 times slower
// and what is checked is memory and undefined behaviour, not the figures.
// Each test that reads these asserts the same things at both sizes, with
// the bound written for the size it runs (see the test's comment).
// docs/development.md#ci has the times.
//
// Thread-safety: constants only.
#ifndef ROLLWEAR_TESTS_CORE_TEST_SIZE_H_
#define ROLLWEAR_TESTS_CORE_TEST_SIZE_H_

namespace rollwear::test_size {

#if defined(ROLLWEAR_SANITIZED) && ROLLWEAR_SANITIZED
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif

// `full` in the Release build, `sanitized` under the sanitizers.
template <typename T>
constexpr T FullOr(T full, T sanitized) {
  return kSanitized ? sanitized : full;
}

}  // namespace rollwear::test_size

namespace rollwear {

// The study's mill: 395 campaigns (the paper's size).
inline constexpr int kPaperCampaigns = 395;

}  // namespace rollwear

#endif  // ROLLWEAR_TESTS_CORE_TEST_SIZE_H_
