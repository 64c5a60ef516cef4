// Internal pieces of the mill simulator (core/sim/simulator.h), shared by
// simulator.cc (campaign loop, rolls, noise), sim_process.cc (random
// streams, tables, schedules and the flow-stress force model) and
// sim_effects.cc (the concealed-effect table). Not a public interface:
// include only from those.
//
// Thread-safety: the tables are immutable; the functions are pure apart
// from the Random they are handed, which must not be shared between threads.
#ifndef ROLLWEAR_CORE_SIM_SIM_INTERNAL_H_
#define ROLLWEAR_CORE_SIM_SIM_INTERNAL_H_

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/dataset/dataset.h"
#include "core/base/random.h"
#include "core/sim/simulator.h"

namespace rollwear::sim {

// ---------------------------------------------------------------------------
// Random streams. Every purpose (schedule, roll choice, noise...) and every
// campaign draws from its own engine, seeded by SplitMix64 (Steele, Lea &
// Flood 2014) from (seed, stream, index). Switching an effect on or changing
// the missing fraction therefore leaves the other draws unchanged.
enum class Stream : uint64_t {
  kInventory = 1,
  kSchedule = 2,
  kRollChoice = 3,
  kCooling = 4,
  kScatter = 5,
  kGrinder = 6,
  kMissing = 7,
  kRegrind = 8,
  kTiming = 9,
  kGross = 10,
  kProfile = 11,
  // Effect families (sim_families.cc): variant and strengths, stoppages
  // inside campaigns, the level of a measurement-side column, per-campaign
  // random factors.
  kFamily = 12,
  kStoppage = 13,
  kColumn = 14,
  kFamilyNoise = 15,
  kRollWearFactor = 16,  // index: the roll's serial
};
Random MakeRandom(uint64_t seed, Stream stream, uint64_t index);
// exp(sigma*z - sigma^2/2), z ~ N(0,1): lognormal with mean exactly 1.
double LogNormalMeanOne(Random* rng, double sigma);
// Index drawn with probability weights[i] / sum(weights) (all >= 0, sum > 0).
int Categorical(Random* rng, const double* weights, int n);

// ---------------------------------------------------------------------------
// Wear profiles across the barrel (sim_profiles.cc).

// One pass on one roll, as the profile sees it: the wear it adds at the
// centre law's rate, where the strip ran and how wide it was.
struct StripTrace {
  double wear_um;
  double centre_mm;
  double half_width_mm;
};

// The grinder's points of one roll: x_mm every kProfileSpacingMm over the
// band the strips covered (and 40 mm beyond), with the noise-free wear.
inline constexpr double kProfileSpacingMm = 10;
std::vector<std::pair<double, double>> TrueProfile(
    const SimulatedProfileShape& shape, const std::vector<StripTrace>& traces);
// The simulator's own distribution across the strip (not the model's
// basis): g(u, b) = 1 + beta2 (u/b)^2 + A (exp(-d/lambda) - exp(-b/lambda))
// under the strip (d = b - |u|), 0 outside: g(0, b) = 1 exactly, so the
// centre wear is the centre law's.
double TrueDistribution(const SimulatedProfileShape& shape, double u_mm,
                        double half_width_mm);
SimulatedProfileShape DrawProfileShape(uint64_t seed);

// ---------------------------------------------------------------------------
// Steel grades: chemistry for the flow-stress model, schedule limits, and the
// true option-1 grade factor kS.
constexpr int kNumGrades = 9;
struct GradeSpec {
  const char* label;
  double carbon, manganese, niobium, chromium;  // wt-%
  double k_grade;                               // true kS
  double h_min_mm, h_max_mm;                    // final (F7 exit) thickness
  double w_min_mm, w_max_mm;                    // width
  double t7_target_c;                           // F7 entry temperature aim
  bool warm_up;                                 // may be rolled as warm-up coil
};
const std::array<GradeSpec, kNumGrades>& Grades();

// Work-roll types (material family and supplier) and the true factor kR.
constexpr int kNumRollTypes = 8;
struct RollTypeSpec {
  const char* label;
  double k_roll_type;      // true kR
  double preference_f6;    // planner's preference for F6 (0 = never)
  double preference_f7;    // ... for F7
  double hardness_new_hb;  // mean surface hardness of a new roll
  double hardness_slope;   // HB lost per mm of radius ground off
  double young_gpa;        // for Hitchcock's roll flattening
};
const std::array<RollTypeSpec, kNumRollTypes>& RollTypes();

// New and scrap diameters of the F6/F7 work rolls, mm.
constexpr double kNewDiameterMinMm = 752;
constexpr double kNewDiameterMaxMm = 762;
constexpr double kScrapDiameterMm = 655;

// True option-1 position factors kF for F6/top, F6/bottom, F7/top,
// F7/bottom (they carry the overall scale of K, in um per kN/mm*km).
constexpr std::array<double, 4> kPositionFactor = {0.330, 0.356, 0.350, 0.378};
// Index 0..3 of a simulated roll position: (stand - 6) * 2 + position.
inline int SimSlot(int stand, Position p) {
  return (stand - 6) * 2 + static_cast<int>(p);
}

// ---------------------------------------------------------------------------
// Schedules (sim_process.cc).

// What is decided once per campaign: programme, grade mix, width programme,
// temperature level, lubrication practice, length.
struct CampaignPlan {
  int programme = 0;
  int num_coils = 0;
  int warm_up_coils = 0;
  std::array<double, kNumGrades> grade_weights{};
  double width_max_mm = 0;
  double width_min_mm = 0;
  double temperature_offset_c = 0;
  double speed_factor = 1;
  bool lubrication = false;
  int lubrication_off_first = 0;  // coils without lubrication after change
  double shift_step_mm = 0;
  double thickness_bias = 0;  // log-scale shift of the gauge mix
  // The mill ends a campaign early once F7 has rolled this length (the
  // roll shop's km limit), whatever num_coils says.
  double max_f7_length_m = 0;
};
CampaignPlan PlanCampaign(double mean_coils, Random* rng);

// One coil through F6 and F7 before the force model: geometry, mass,
// temperatures, speeds, lubrication, shift.
struct CoilPlan {
  int grade = 0;
  double width_mm = 0;
  double mass_t = 0;
  double h5_mm = 0;               // F6 entry
  double h6_mm = 0;               // F6 exit = F7 entry
  double h7_mm = 0;               // F7 exit (final)
  double t6_c = 0, t7_c = 0;      // entry temperatures
  double v6_mps = 0, v7_mps = 0;  // roll peripheral speeds
  double slip6 = 0, slip7 = 0;    // forward slip
  bool lubrication = false;
  double shift6_mm = 0, shift7_mm = 0;
  double gap_s = 0;  // idle time before the next coil
  int coils_since_stop = 1 << 20;  // CountCoilsSinceStop
};

// Generates the coils of a campaign in rolling order (a "coffin" width
// programme after a few warm-up coils, grades in blocks, cyclic shifting).
std::vector<CoilPlan> PlanCoils(const CampaignPlan& plan, Random* rng);

// Rolling force (kN) of one pass from the flow-stress model; see
// sim_process.cc for the formulas (Misaka, Sims/Ford-Alexander, Hitchcock).
double RollForceKn(const GradeSpec& grade, double width_mm, double h_in_mm,
                   double h_out_mm, double temperature_c, double speed_mps,
                   double diameter_mm, double young_gpa, bool lubrication);

// Steel density used for rolled lengths, kg/m^3.
constexpr double kSteelDensity = 7850;

// Rounds to `decimals` decimal places (the precision the CSV carries).
double RoundTo(double x, int decimals);

// ---------------------------------------------------------------------------
// Concealed effects (sim_effects.cc).

// What an effect may look at: one pass as recorded, the roll it acts on,
// the campaign state before the pass, and (measurement effects) the cooling
// time before the grinder measurement.
struct EffectContext {
  const Pass* pass = nullptr;
  const Mount* mount = nullptr;
  double campaign_length_before_m = 0;
  int coils_before = 0;
  double hours_since_mount = 0;
  double cooling_h = 0;
  double days_since_first_campaign = 0;  // of this campaign's start
  // For the effect families (sim_families.cc): where and on what the pass
  // runs, and which level of the family's measurement column read it.
  int campaign = 0;       // index of the campaign, 0..num_campaigns-1
  int num_campaigns = 1;
  int slot = 0;           // SimSlot of the roll
  int grade = -1;         // index into Grades()
  int roll_type = -1;     // index into RollTypes()
  int column_level = -1;  // measurement effects: level of the column
  int roll_campaigns_before = 0;  // the mounted roll's earlier campaigns
  // Coils rolled since the last stoppage inside the campaign (an idle time
  // of kSimStopS or more before a coil; that coil counts 0); a large value
  // before the first.
  int coils_since_stop = 1 << 20;
};

// What the simulator's own effects call a stoppage: an idle time before a
// coil of at least five minutes.
inline constexpr double kSimStopS = 300;

// Sets each coil's coils_since_stop from the gaps before it (the campaign's
// gaps final, stoppages added): 0 on the first coil after a stoppage, a
// large value before the first.
void CountCoilsSinceStop(std::vector<CoilPlan>* coils);

enum class EffectKind {
  kWearRate,     // Apply returns a multiplier on the pass's wear increment
  kMeasurement,  // Apply returns an additive offset on the measured wear, um
  kWearAdded,    // Apply returns wear (um) added to the pass's increment
  // Random gross errors of the grinder on a fraction of the readings
  // (GrossError draws them; apply is null).
  kGrossError,
};

constexpr int kMaxEffectParameters = 3;
struct EffectParameter {
  const char* name;
  double value;
};

struct EffectSpec {
  const char* name;
  const char* covariate;  // canonical name of data-format.md
  const char* description;
  EffectKind kind;
  int num_parameters;
  std::array<EffectParameter, kMaxEffectParameters> parameters;
  double (*apply)(const EffectContext& ctx, const double* p);
};

// gross_errors: the error added to one reading, or 0 (most readings), drawn
// from `rng` with the effect's parameters (fraction, min_um, max_um); see
// sim_effects.cc.
double GrossError(Random* rng, const double* p);

// All effects the simulator knows, in a fixed order.
const std::vector<EffectSpec>& EffectTable();
// Entry called `name`, or nullptr.
const EffectSpec* FindEffect(const std::string& name);

// ---------------------------------------------------------------------------
// Effect families (sim_families.cc): effects with several forms, strengths
// and scopes, selected as NAME (variant drawn from the seed) or NAME:K
// (variant K). Each one is drawn once per simulation into a FamilyEffect.

struct FamilyEffect {
  SimulatedEffect truth;
  EffectKind kind = EffectKind::kWearRate;
  // Wear-rate multiplier, wear added (um) or reading offset (um) of one
  // pass / reading; null
  // for a family that changes no wear (the null variants).
  std::function<double(const EffectContext&)> apply;
  // Stoppages inside campaigns: each coil is followed, with this
  // probability, by an idle time uniform in [min_h, max_h] hours.
  double stoppage_probability = 0;
  double stoppage_min_h = 0, stoppage_max_h = 0;
  // A text column of measurements.csv (empty: none): its levels and the
  // share of readings each level takes.
  std::string column;
  std::vector<std::string> column_levels;
  std::vector<double> column_shares;
};

// NAME or NAME:K of a family; false if `name` is neither.
bool IsFamilyName(const std::string& name);
// The family effect `name` (IsFamilyName) for a simulation of
// `num_campaigns` campaigns with `seed`.
FamilyEffect DrawFamily(const std::string& name, uint64_t seed,
                        int num_campaigns);
// (name, description) of every family, in a fixed order.
std::vector<std::pair<std::string, std::string>> FamilyList();

}  // namespace rollwear::sim

#endif  // ROLLWEAR_CORE_SIM_SIM_INTERNAL_H_
