// The proxy guard's look again and its judgement beside the rolls' own
// scatter (diagnosis_look_again.cc; docs/diagnosis.md, "The proxy guard"),
// and the campaign design effect of its nested test; the per-roll term it
// fits is RollScatterTerm (diagnosis_stages_internal.h).
// Internal to core/diagnosis; the guard chain that calls them is in
// diagnosis_guard.cc.
//
// Thread-safety: reentrant functions (they read their arguments only).
#ifndef ROLLWEAR_CORE_DIAGNOSIS_DIAGNOSIS_LOOK_AGAIN_H_
#define ROLLWEAR_CORE_DIAGNOSIS_DIAGNOSIS_LOOK_AGAIN_H_

#include <vector>

#include "core/diagnosis/diagnosis_stages_internal.h"

namespace rollwear::diag {

// The proxy guard's look again (diagnosis_look_again.cc): the strongest
// breakdown of `before` (Locate under the model before the term, clipped at
// `clip`) must be materially reduced under `after` (the predictions with
// the term, aligned with st.train), or the candidate is refused with the
// structure's place.
GuardResult LookAgain(const Dataset& data, const DiagnosisState& st,
                      const DiagnosisOptions& options,
                      const std::vector<Breakdown>& before,
                      const std::vector<double>& clip,
                      const std::vector<double>& after);

// `look_again` when it passed or refused over another dimension than
// roll_id; otherwise the look again beside a per-roll term
// (RollScatterTerm) in both models: the candidate (last term of
// `with_term`) must add beside it at the round's level (Bonferroni over
// `num_tests`) and take away the strongest other breakdown
// (diagnosis_look_again.cc).
GuardResult LookAgainBesideRolls(const Dataset& data, const DiagnosisState& st,
                                 const DiagnosisOptions& options,
                                 const std::vector<double>& sd,
                                 const Fitted& with_term,
                                 const std::vector<double>& clip,
                                 double num_tests,
                                 const GuardResult& look_again);

// The design effect of a nested test whose candidate changes the training
// predictions from `p_before` to `p_after` (aligned with st.train; sd
// indexed like td.obs): 1 + (n0 - 1) rho_e rho_x, the intraclass
// correlations within campaigns of the standardised residuals and of the
// candidate's standardised contribution (Scott & Holt 1982; intraclass.h),
// at least 1 (diagnosis_look_again.cc).
double CampaignDesignEffect(const DiagnosisState& st,
                            const std::vector<double>& sd,
                            const std::vector<double>& p_before,
                            const std::vector<double>& p_after);

}  // namespace rollwear::diag

#endif  // ROLLWEAR_CORE_DIAGNOSIS_DIAGNOSIS_LOOK_AGAIN_H_
