// Mill process model of the simulator: the grade and roll-type tables,
// per-campaign rolling programmes, coil-by-coil schedules through F6 and F7,
// and the rolling force from a flow-stress model.
#include <algorithm>
#include <cmath>

#include "core/sim/sim_internal.h"
#include "core/model/wear_law.h"

namespace rollwear::sim {

// ---------------------------------------------------------------------------
// Random helpers.

Random MakeRandom(uint64_t seed, Stream stream, uint64_t index) {
  uint64_t s = SplitMix64(seed);
  s = SplitMix64(s ^ static_cast<uint64_t>(stream));
  s = SplitMix64(s ^ index);
  return Random(s);
}

double LogNormalMeanOne(Random* rng, double sigma) {
  // E[exp(sigma z)] = exp(sigma^2 / 2), hence the correction.
  return std::exp(sigma * rng->Normal() - 0.5 * sigma * sigma);
}

int Categorical(Random* rng, const double* weights, int n) {
  double total = 0;
  for (int i = 0; i < n; ++i) total += weights[i];
  double u = rng->Uniform() * total;
  int last = 0;
  for (int i = 0; i < n; ++i) {
    if (weights[i] <= 0) continue;
    last = i;
    if (u < weights[i]) return i;
    u -= weights[i];
  }
  return last;
}

double RoundTo(double x, int decimals) {
  static constexpr double kScale[] = {1, 10, 100, 1000, 10000};
  const double s = kScale[decimals];
  return std::round(x * s) / s;
}

// ---------------------------------------------------------------------------
// Tables.

const std::array<GradeSpec, kNumGrades>& Grades() {
  // label, C, Mn, Nb, Cr, kS, h range, w range, T7 aim, warm-up grade.
  static const std::array<GradeSpec, kNumGrades> kGrades = {{
      {"CQ", 0.050, 0.25, 0.000, 0.0, 1.00, 1.5, 6.0, 900, 1650, 905, true},
      {"DQ", 0.035, 0.20, 0.000, 0.0, 0.95, 1.5, 5.0, 900, 1600, 910, true},
      {"S355", 0.160, 1.40, 0.000, 0.0, 1.12, 2.0, 8.0, 1000, 1650, 890, false},
      {"HSLA350", 0.070, 0.90, 0.030, 0.0, 1.18, 2.0, 8.0, 1000, 1650, 885,
       false},
      {"HSLA420", 0.080, 1.20, 0.040, 0.0, 1.24, 2.5, 8.0, 1000, 1600, 880,
       false},
      {"DP600", 0.090, 1.60, 0.000, 0.5, 1.26, 1.8, 4.5, 1000, 1500, 875,
       false},
      {"API-X65", 0.060, 1.50, 0.045, 0.0, 1.28, 5.0, 8.0, 1200, 1650, 865,
       false},
      {"API-X70", 0.050, 1.65, 0.060, 0.2, 1.36, 5.0, 8.0, 1200, 1650, 860,
       false},
      {"C45", 0.450, 0.70, 0.000, 0.0, 1.15, 2.0, 6.0, 900, 1400, 885, false},
  }};
  return kGrades;
}

const std::array<RollTypeSpec, kNumRollTypes>& RollTypes() {
  // Indefinite chill double poured (ICDP) cast iron for the last stands,
  // high-chromium iron (HiCr) and high-speed steel (HSS) mostly in F6.
  // label, kR, preference F6/F7, new hardness, HB per mm depth, E (GPa).
  static const std::array<RollTypeSpec, kNumRollTypes> kTypes = {{
      {"ICDP-S1", 1.00, 0.5, 1.0, 560, 0.9, 170},
      {"ICDP-S2", 1.08, 0.5, 1.0, 545, 1.0, 170},
      {"ICDP-S3", 0.94, 0.0, 1.0, 575, 0.8, 175},
      {"ICDP-S4", 1.06, 0.0, 0.8, 550, 1.1, 170},
      {"HiCr-S1", 0.86, 1.0, 0.0, 525, 0.5, 200},
      {"HiCr-S2", 0.92, 1.0, 0.4, 510, 0.6, 200},
      {"HSS-S1", 0.70, 0.9, 0.0, 620, 0.25, 225},
      {"HSS-S2", 0.76, 0.7, 0.5, 600, 0.3, 225},
  }};
  return kTypes;
}

namespace {

// Rolling programmes: the grade mix a campaign is planned around, its
// relative length and its widest coils.
struct ProgrammeSpec {
  const char* name;
  double weight;
  std::array<double, kNumGrades> grade_weights;  // order of Grades()
  double length_factor;
  double width_max_lo, width_max_hi;
};
constexpr int kNumProgrammes = 4;
const std::array<ProgrammeSpec, kNumProgrammes> kProgrammes = {{
    //                        CQ  DQ S355 H350 H420 DP  X65 X70 C45
    {"commodity", 0.35, {{40, 25, 15, 10, 0, 0, 0, 0, 10}}, 1.06, 1450, 1650},
    {"automotive", 0.25, {{15, 25, 0, 15, 15, 30, 0, 0, 0}}, 0.97, 1350, 1550},
    {"pipe", 0.15, {{10, 0, 20, 0, 10, 0, 35, 25, 0}}, 0.90, 1500, 1650},
    {"structural", 0.25, {{20, 0, 30, 25, 15, 0, 0, 0, 10}}, 1.00, 1400, 1650},
}};

constexpr double kCampaignLengthSigma = 0.17;  // log-scale spread

// Half stroke of the cyclic work-roll shift for a strip width: the barrel
// (1880 mm usable) must cover the strip with 60 mm to spare on each side.
double ShiftStroke(double width_mm) {
  return std::clamp((1880 - width_mm) / 2 - 60, 40.0, 150.0);
}

// One step of a triangular shifting cycle between -stroke and +stroke.
void StepShift(double step, double stroke, double* pos, double* dir) {
  *pos += *dir * step;
  if (*pos > stroke) {
    *pos = stroke;
    *dir = -1;
  } else if (*pos < -stroke) {
    *pos = -stroke;
    *dir = 1;
  }
}

// The running grade block of a campaign's body: coils left in it, its
// grade and its F7 gauge.
struct GradeBlock {
  int left = 0;
  int grade = 0;
  double h7 = 3;
};

// Grade, width and F7 gauge of coil i (in this order of random draws).
void PlanGradeAndSize(const CampaignPlan& plan, int i, double warm_up_width,
                      GradeBlock* block, Random* rng, CoilPlan* coil) {
  const auto& grades = Grades();
  CoilPlan& c = *coil;
  if (i < plan.warm_up_coils) {
    // Warm-up coils: an easy grade, thick, widths ramping up to the
    // programme's widest coils (the head of the "coffin").
    c.grade = rng->Uniform() < 0.6 ? 0 : 1;
    const double ramp = plan.warm_up_coils > 1
                            ? static_cast<double>(i) / (plan.warm_up_coils - 1)
                            : 1.0;
    c.width_mm = warm_up_width +
                 (plan.width_max_mm - 120 - warm_up_width) * ramp +
                 rng->Normal(0, 20);
    c.h7_mm = rng->Uniform(3.2, 5.0);
  } else {
    if (block->left == 0) {
      block->grade = Categorical(rng, plan.grade_weights.data(), kNumGrades);
      block->left = 3 + static_cast<int>(rng->Below(10));
      const GradeSpec& g = grades[block->grade];
      block->h7 =
          std::exp(rng->Uniform(std::log(g.h_min_mm), std::log(g.h_max_mm)) +
                   plan.thickness_bias);
    }
    --block->left;
    c.grade = block->grade;
    // Body of the coffin: widest first, narrowing towards the end as the
    // roll wear profile deepens.
    const int body = plan.num_coils - plan.warm_up_coils;
    const double frac =
        body > 1 ? static_cast<double>(i - plan.warm_up_coils) / (body - 1)
                 : 0.0;
    c.width_mm =
        plan.width_max_mm -
        (plan.width_max_mm - plan.width_min_mm) * std::pow(frac, 0.85) +
        rng->Normal(0, 30);
    c.h7_mm = block->h7 * std::exp(rng->Normal(0, 0.03));
  }
  const GradeSpec& g = grades[c.grade];
  // Two draws, in this order (the margin under the grade's widest first):
  // the order of a call's arguments is unspecified in C++, and GCC and
  // Clang differ; the simulator's data must not depend on the compiler.
  const double below_max = rng->Uniform(0, 60);
  const double above_min = rng->Uniform(0, 60);
  c.width_mm =
      std::clamp(c.width_mm, g.w_min_mm + above_min, g.w_max_mm - below_max);
  c.width_mm = std::round(std::clamp(c.width_mm, 900.0, 1650.0));
  c.h7_mm = RoundTo(
      std::clamp(c.h7_mm, std::max(1.5, g.h_min_mm), std::min(8.0, g.h_max_mm)),
      3);
}

// Mass, F6/F5 exit gauges, entry temperatures, roll speeds, forward slips
// and lubrication of coil i, whose grade, width and F7 gauge are set.
void PlanPasses(const CampaignPlan& plan, int i, bool warm_up, Random* rng,
                CoilPlan* coil) {
  CoilPlan& c = *coil;
  const GradeSpec& g = Grades()[c.grade];
  // Coil mass from the specific coil weight (kg per mm of width), 15-30 t.
  c.mass_t = c.width_mm * rng->Uniform(15, 20) / 1000;
  if (c.mass_t < 15) c.mass_t = 15 + rng->Uniform(0, 1.5);
  if (c.mass_t > 30) c.mass_t = 30 - rng->Uniform(0, 1.5);

  // Reductions of the last two stands fall with gauge (thick strip gets
  // lighter passes): F7 about 14% at 2 mm, 7% at 8 mm; F6 about 22..13%.
  const double r7 =
      std::clamp(0.16 - 0.012 * c.h7_mm + rng->Normal(0, 0.015), 0.05, 0.18);
  const double r6 =
      std::clamp(0.25 - 0.015 * c.h7_mm + rng->Normal(0, 0.02), 0.10, 0.30);
  c.h6_mm = RoundTo(c.h7_mm / (1 - r7), 3);
  c.h5_mm = RoundTo(c.h6_mm / (1 - r6), 3);

  // Entry temperatures: grade aim, campaign level, thick strip holds its
  // heat; F6 entry is hotter by the interstand loss (larger for thin
  // strip, ~ 1/h).
  c.t7_c = g.t7_target_c + plan.temperature_offset_c + 4 * (c.h7_mm - 3) +
           (warm_up ? 10 : 0) + rng->Normal(0, 7);
  c.t7_c = RoundTo(std::clamp(c.t7_c, 845.0, 955.0), 1);
  c.t6_c = RoundTo(
      std::min(c.t7_c + 12 + 20 / c.h6_mm + rng->Normal(0, 3), 968.0), 1);

  // F7 roll speed: threading/rolling speed falls with gauge (about 15 m/s
  // at 1.5 mm down to 6 m/s at 8 mm). F6 from volume constancy
  // h6 * v6_strip = h7 * v7_strip with forward slips f: v_strip = v (1+f).
  double v7 =
      (6.0 + 9.0 * std::pow(std::max(0.0, (8.2 - c.h7_mm) / 6.7), 1.5)) *
      plan.speed_factor * std::exp(rng->Normal(0, 0.03));
  c.v7_mps = RoundTo(std::clamp(v7, 5.8, 15.5), 3);
  c.slip7 = rng->Uniform(0.03, 0.07);
  c.slip6 = rng->Uniform(0.03, 0.07);
  const double v7_strip = c.v7_mps * (1 + c.slip7);
  const double v6_strip = v7_strip * c.h7_mm / c.h6_mm;
  c.v6_mps = RoundTo(v6_strip / (1 + c.slip6), 3);

  c.lubrication = plan.lubrication && i >= plan.lubrication_off_first &&
                  rng->Uniform() >= 0.04;
}

}  // namespace

CampaignPlan PlanCampaign(double mean_coils, Random* rng) {
  CampaignPlan plan;
  double weights[kNumProgrammes];
  for (int i = 0; i < kNumProgrammes; ++i) weights[i] = kProgrammes[i].weight;
  plan.programme = Categorical(rng, weights, kNumProgrammes);
  const ProgrammeSpec& prog = kProgrammes[plan.programme];

  // Campaign length: lognormal with mean one around the programme's share
  // of the mean, kept within 0.6..1.45 of the mean (80..190 for 131).
  const double n = mean_coils * prog.length_factor *
                   LogNormalMeanOne(rng, kCampaignLengthSigma);
  plan.num_coils = static_cast<int>(
      std::lround(std::clamp(n, 0.6 * mean_coils, 1.45 * mean_coils)));
  plan.num_coils = std::max(plan.num_coils, 8);
  plan.warm_up_coils =
      std::min(4 + static_cast<int>(rng->Below(5)), plan.num_coils / 4);

  for (int g = 0; g < kNumGrades; ++g) {
    plan.grade_weights[g] =
        prog.grade_weights[g] > 0
            ? prog.grade_weights[g] * std::exp(0.5 * rng->Normal())
            : 0;
  }
  plan.width_max_mm = rng->Uniform(prog.width_max_lo, prog.width_max_hi);
  plan.width_min_mm = rng->Uniform(900, 1100);
  plan.temperature_offset_c = rng->Normal(0, 12);
  plan.speed_factor = std::exp(rng->Normal(0, 0.05));
  plan.lubrication = rng->Uniform() < 0.4;
  plan.lubrication_off_first = 2 + static_cast<int>(rng->Below(5));
  plan.shift_step_mm = rng->Uniform(8, 25);
  plan.thickness_bias = rng->Normal(0, 0.15);
  plan.max_f7_length_m = rng->Uniform(135e3, 165e3);
  return plan;
}

std::vector<CoilPlan> PlanCoils(const CampaignPlan& plan, Random* rng) {
  std::vector<CoilPlan> coils(plan.num_coils);
  double shift6 = rng->Uniform(-40, 40), dir6 = 1;
  double shift7 = rng->Uniform(-40, 40), dir7 = -1;
  const double warm_up_width = rng->Uniform(1000, 1150);

  GradeBlock block;
  double f7_length_m = 0;
  for (int i = 0; i < plan.num_coils; ++i) {
    CoilPlan& c = coils[i];
    const bool warm_up = i < plan.warm_up_coils;
    PlanGradeAndSize(plan, i, warm_up_width, &block, rng, &c);
    PlanPasses(plan, i, warm_up, rng, &c);

    const double stroke = ShiftStroke(c.width_mm);
    StepShift(plan.shift_step_mm, stroke, &shift6, &dir6);
    StepShift(plan.shift_step_mm, stroke, &shift7, &dir7);
    c.shift6_mm = RoundTo(shift6, 1);
    c.shift7_mm = RoundTo(shift7, 1);

    // Idle time between tail out and the next head in, now and then a
    // short stoppage.
    c.gap_s = rng->Uniform(45, 85);
    if (rng->Uniform() < 0.02) c.gap_s += rng->Uniform(300, 1800);

    // km limit: L = m / (rho * w * h).
    f7_length_m +=
        c.mass_t * 1000 / (kSteelDensity * c.width_mm * 1e-3 * c.h7_mm * 1e-3);
    if (f7_length_m >= plan.max_f7_length_m) {
      coils.resize(i + 1);
      break;
    }
  }
  return coils;
}

// Rolling force of one pass.
//
// Mean flow stress: Misaka & Yoshimoto (1967) for carbon steels, in kgf/mm^2,
//   sigma = exp(0.126 - 1.75 C + 0.594 C^2 + (2851 + 2968 C - 1120 C^2) / T)
//           * eps^0.21 * epsdot^0.13,            T in K,
// times Kinoshita's alloy correction (0.916 + 0.18 Mn) and, for the last
// stands, factors for Nb (strain retained without recrystallisation,
// 1 + 3.5 Nb) and Cr (1 + 0.12 Cr).
// Strain and mean strain rate (plane strain, von Mises equivalent):
//   eps = (2/sqrt 3) ln(h_in/h_out),  epsdot = v / sqrt(R dh) * ln(h_in/h_out).
// Force: F = k * w * l'c * Qp with k = (2/sqrt 3) sigma, Sims' geometric
// factor approximated after Ford & Alexander (1964) as
//   Qp = pi/4 + l'c / (4 h_mean)  (sticking friction; 7% lower lubricated),
// and the flattened contact length l'c = sqrt(R' dh) from Hitchcock (1935):
//   R' = R (1 + c F / (w dh)),  c = 16 (1 - nu^2) / (pi E),
// solved by fixed-point iteration.
double RollForceKn(const GradeSpec& grade, double width_mm, double h_in_mm,
                   double h_out_mm, double temperature_c, double speed_mps,
                   double diameter_mm, double young_gpa, bool lubrication) {
  const double dh = h_in_mm - h_out_mm;
  const double radius = diameter_mm / 2;
  const double log_ratio = std::log(h_in_mm / h_out_mm);
  const double two_over_root3 = 2 / std::sqrt(3.0);
  const double strain = two_over_root3 * log_ratio;
  const double strain_rate =
      speed_mps * 1000 / std::sqrt(radius * dh) * log_ratio;  // 1/s
  const double t_kelvin = temperature_c + 273.15;
  const double c = grade.carbon;
  const double misaka_kgf =
      std::exp(0.126 - 1.75 * c + 0.594 * c * c +
               (2851 + 2968 * c - 1120 * c * c) / t_kelvin) *
      std::pow(strain, 0.21) * std::pow(strain_rate, 0.13);
  const double chemistry = (0.916 + 0.18 * grade.manganese) *
                           (1 + 3.5 * grade.niobium) *
                           (1 + 0.12 * grade.chromium);
  const double sigma_mpa = misaka_kgf * 9.80665 * chemistry;
  const double k_mpa = two_over_root3 * sigma_mpa;

  const double nu = 0.3;
  const double hitchcock = 16 * (1 - nu * nu) / (kPi * young_gpa * 1000);
  const double h_mean = (h_in_mm + h_out_mm) / 2;
  double flattened = radius;
  double force_n = 0;
  for (int iter = 0; iter < 8; ++iter) {
    const double lc = std::sqrt(flattened * dh);
    double q = kPi / 4 + lc / (4 * h_mean);
    if (lubrication) q *= 0.93;
    force_n = k_mpa * width_mm * lc * q;  // N/mm^2 * mm * mm
    flattened = radius * (1 + hitchcock * force_n / (width_mm * dh));
  }
  return force_n / 1000;
}

void CountCoilsSinceStop(std::vector<CoilPlan>* coils) {
  for (size_t i = 1; i < coils->size(); ++i) {
    const CoilPlan& before = (*coils)[i - 1];
    (*coils)[i].coils_since_stop =
        before.gap_s >= kSimStopS
            ? 0
            : std::min(before.coils_since_stop + 1, 1 << 20);
  }
}

}  // namespace rollwear::sim
