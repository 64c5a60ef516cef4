// DiagnosisThresholds (core/diagnosis/diagnosis_thresholds.h): the defaults
// are valid, and DiagnosisOptions::IsValid refuses a threshold out of range
// naming the field.
#include "core/diagnosis/diagnosis_thresholds.h"

#include <string>

#include <gtest/gtest.h>

#include "core/diagnosis/diagnosis.h"

namespace rollwear {
namespace {

TEST(DiagnosisThresholdsTest, DefaultsAreValid) {
  std::string error;
  EXPECT_TRUE(DiagnosisOptions{}.IsValid(&error)) << error;
  EXPECT_TRUE(DiagnosisThresholds{}.IsValid(&error)) << error;
}

TEST(DiagnosisThresholdsTest, ABadThresholdIsRefusedByName) {
  std::string error;
  DiagnosisOptions options;
  options.thresholds.alternative_alpha = 1.5;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("alternative_alpha"), std::string::npos) << error;

  // A guard's question about an alternative stricter than the round itself.
  options = DiagnosisOptions{};
  options.thresholds.alternative_alpha = options.alpha / 2;
  error.clear();
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("alternative_alpha must be >= alpha"), std::string::npos)
      << error;
  options.thresholds.alternative_alpha = options.alpha;
  EXPECT_TRUE(options.IsValid(&error)) << error;

  options = DiagnosisOptions{};
  options.thresholds.min_scope_observations = 0;
  error.clear();
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("min_scope_observations"), std::string::npos) << error;

  // A flag share of a half or more would leave no flag on offer.
  options = DiagnosisOptions{};
  options.thresholds.min_flag_share = 0.5;
  error.clear();
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("min_flag_share"), std::string::npos) << error;

  options = DiagnosisOptions{};
  options.thresholds.material_noise_share = -0.25;
  EXPECT_FALSE(options.IsValid(nullptr));
}

TEST(DiagnosisThresholdsTest, TheTwoChiSquarePointsKeepTheirValues) {
  // The chi2(1) 1 % point, rounded (the guard) and to four decimals (the
  // reference): both kept as they were so results do not move.
  const DiagnosisThresholds t;
  EXPECT_EQ(t.shadow_delta, 6.63);
  EXPECT_EQ(t.reference_chi2_critical, 6.6349);
}

}  // namespace
}  // namespace rollwear
