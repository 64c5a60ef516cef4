// core/fit/candidate_model.h: the promotion rule, the choice of candidate,
// and that a candidate is scored with the active model on the same
// validation campaigns.
#include "core/fit/candidate_model.h"

#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "core/sim/simulator.h"
#include "tests/core/simulator_test_util.h"

namespace rollwear {
namespace {

using simulator_test::Simulated;

CandidateScore Scored(double gap_val, double active_gap_val, int n_val) {
  CandidateScore s;
  s.gap_val_um = gap_val;
  s.active_gap_val_um = active_gap_val;
  s.n_val = n_val;
  return s;
}

TEST(CandidateModelTest, PromotesWhenNoWorseAndSaysWhy) {
  PromotionDecision d = DecidePromotion(Scored(10.0, 12.5, 40), 3);
  EXPECT_TRUE(d.comparable);
  EXPECT_TRUE(d.promote);
  EXPECT_EQ(d.reason,
            "; validation gap 10.00 um vs 12.50 um for active model version 3: "
            "promoted");
  d = DecidePromotion(Scored(12.5, 12.5, 40), 3);  // equal: no worse
  EXPECT_TRUE(d.promote);
  d = DecidePromotion(Scored(12.51, 12.5, 40), 7);
  EXPECT_TRUE(d.comparable);
  EXPECT_FALSE(d.promote);
  EXPECT_EQ(d.reason,
            "; validation gap 12.51 um vs 12.50 um for active model version 7: "
            "kept the active model");
  // An active model without a finite gap is beaten by any finite one.
  d = DecidePromotion(Scored(90.0, std::numeric_limits<double>::infinity(), 5),
                      1);
  EXPECT_TRUE(d.promote);
}

// The gate judges as `rollwear calibrate` does (identification.h): a
// candidate whose coefficients are not identified is kept out however good
// its gap, and the reason carries the verdict; a verdict on the validation
// gap alone is reported but does not stop a better candidate.
TEST(CandidateModelTest, UnidentifiedCoefficientsAreNotPromoted) {
  CandidateScore score = Scored(10.0, 12.5, 40);
  score.coefficients_identified = false;
  score.identification =
      "not identified: 1 coefficient at a bound (kS[API-X70])";
  PromotionDecision d = DecidePromotion(score, 3);
  EXPECT_TRUE(d.comparable);
  EXPECT_FALSE(d.promote);
  EXPECT_EQ(d.reason,
            "; validation gap 10.00 um vs 12.50 um for active model version 3: "
            "kept the active model (the candidate is not identified: 1 "
            "coefficient at a bound (kS[API-X70]))");
  score.coefficients_identified = true;
  score.identification =
      "not identified: validation gap 1.55 x training, the noise model "
      "allows 1.10 (z = 4.0)";
  d = DecidePromotion(score, 3);
  EXPECT_TRUE(d.promote);
  EXPECT_NE(d.reason.find("promoted (the candidate is not identified: "
                          "validation gap 1.55 x"),
            std::string::npos)
      << d.reason;
}

TEST(CandidateModelTest, NothingToCompareOnIsNotComparable) {
  PromotionDecision d = DecidePromotion(Scored(10.0, 12.5, 0), 3);
  EXPECT_FALSE(d.comparable);
  EXPECT_FALSE(d.promote);
  EXPECT_EQ(d.reason,
            "; no measured validation campaign: nothing to compare on");
  d = DecidePromotion(Scored(std::nan(""), 12.5, 10), 3);
  EXPECT_FALSE(d.comparable);
  EXPECT_FALSE(d.promote);
  EXPECT_EQ(d.reason, "; the validation gap is not finite");
}

TEST(CandidateModelTest, ClassicalCandidateIsScoredWithTheActiveOnOneSplit) {
  const Simulation mill = Simulated(5, 60);
  CandidateRequest request;
  request.model = ModelChoice::Law(WearLaw::kWang, 1);
  request.split_seed = 1;
  const CandidateEvaluation fitted =
      FitCandidate(mill.data, request, WearModel());
  ASSERT_TRUE(fitted.error.ok()) << fitted.error.ToString();
  EXPECT_FALSE(fitted.candidate.is_ann());
  EXPECT_FALSE(fitted.summary.empty());
  EXPECT_GT(fitted.score.cost, 0);
  EXPECT_GT(fitted.score.n_train, fitted.score.n_val);
  EXPECT_GT(fitted.score.n_val, 0);
  EXPECT_FALSE(fitted.score.coefficients.empty());
  EXPECT_TRUE(std::isfinite(fitted.score.gap_val_um));
  // Judged by the verdict of identification.h: its grades are shrunk and
  // its coefficients identified.
  EXPECT_TRUE(fitted.score.coefficients_identified)
      << fitted.score.identification;
  EXPECT_FALSE(fitted.score.identification.empty());
  // Scoring the fitted model as a proposal against itself: the same
  // figures on the same split, and its own gap as the active one's.
  const CandidateEvaluation again =
      ScoreCandidate(fitted.candidate, fitted.candidate, mill.data, 1);
  ASSERT_TRUE(again.error.ok());
  EXPECT_DOUBLE_EQ(again.score.gap_val_um, fitted.score.gap_val_um);
  EXPECT_DOUBLE_EQ(again.score.gap_train_um, fitted.score.gap_train_um);
  EXPECT_DOUBLE_EQ(again.score.active_gap_val_um, fitted.score.gap_val_um);
  EXPECT_EQ(again.score.n_val, fitted.score.n_val);
  // Equal gaps: no worse, so promoted.
  EXPECT_TRUE(DecidePromotion(again.score, 1).promote);
}

TEST(CandidateModelTest, NetworkNeedsItsTrainerAndUnknownLawsFail) {
  const Simulation mill = Simulated(6, 30);
  CandidateRequest request;
  request.model = ModelChoice::Network();
  CandidateEvaluation out = FitCandidate(mill.data, request, WearModel());
  EXPECT_EQ(out.error.code(), StatusCode::kInternal);
  int trained_on = 0;
  request.train_network =
      [&](const Dataset&,
          const std::vector<int>& train) -> StatusOr<FittedCandidate> {
    trained_on = static_cast<int>(train.size());
    return Status::NumericalFailure("network diverged");
  };
  out = FitCandidate(mill.data, request, WearModel());
  EXPECT_EQ(out.error.code(), StatusCode::kNumericalFailure);
  EXPECT_EQ(out.error.message(), "network diverged");
  EXPECT_GT(trained_on, 0);  // handed the training campaigns
}

// A stored run's model name is read as a typed choice once: a law with its
// K structure, or the network; anything else is refused with the field.
TEST(CandidateModelTest, StoredModelNamesAreReadAsATypedChoice) {
  StatusOr<ModelChoice> c = ParseModelChoice("nikitenko", 3);
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(c->family, ModelFamily::kWearLaw);
  EXPECT_EQ(c->law, WearLaw::kNikitenko);
  EXPECT_EQ(c->option, 3);
  EXPECT_EQ(c->Name(), "nikitenko");
  c = ParseModelChoice(kAnnModelName, 0);  // a network run stores option 0
  ASSERT_TRUE(c.ok());
  EXPECT_TRUE(c->is_network());
  EXPECT_EQ(c->Name(), kAnnModelName);
  c = ParseModelChoice("lstm", 1);
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(c.status().message().rfind("model: ", 0), 0u);
  EXPECT_NE(c.status().message().find("lstm"), std::string::npos);
  c = ParseModelChoice("cao", 4);
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(c.status().message().rfind("option: ", 0), 0u);
}

}  // namespace
}  // namespace rollwear
