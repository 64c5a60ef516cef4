// Proves that rollwear's one Levenberg-Marquardt set-up
// (MakeLmSolverOptions in core/fit/lm_setup.h, default LmOptions) reproduces
// the certified values of the 27 NIST StRD nonlinear regression problems
// (https://www.itl.nist.gov/div898/strd/, data in tests/data/nist/).
//
// Score: LRE = -log10(|b - c| / |c|) per parameter, capped at 11 (the
// digits NIST certifies); a problem is "solved" when its minimum LRE over
// the parameters is >= 4. NIST's reference start is start 2 (closer to the
// solution); start 1 is reported and checked too.
//
// Standard errors are checked against the certified standard deviations
// with ceres::Covariance (DENSE_SVD, null_space_rank = -1):
//   se_k = sqrt(s^2 * [(J'J)^+]_kk),   s^2 = RSS / (n - p).
// With null_space_rank = -1 Ceres drops singular values of J with
// sigma_i / sigma_max < sqrt(min_reciprocal_condition_number) = 1e-7. That
// ratio depends on the units of the parameters: on the raw Jacobian of
// e.g. Misra1b (b1 ~ 3e2, b2 ~ 4e-4) a perfectly identifiable direction is
// dropped and the standard errors come out wrong. The checked variant
// therefore equilibrates first: it computes the covariance in
// delta = S^-1 (b - b*), S = diag(1 / ||J_k||) (unit-norm Jacobian columns,
// the Jacobi scaling LM itself uses), through a ceres::Manifold, and Ceres
// lifts it back, Cov(b) = S Cov(delta) S. S is computed from the Jacobian,
// the same rule for every problem. The table prints both variants.
//
// All problems are solved with the same options; only max_iterations is
// raised above the default (see kMaxIterations).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <ceres/covariance.h>
#include <ceres/crs_matrix.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <gtest/gtest.h>

#include "core/fit/lm_setup.h"
#include "tests/core/nist_problems.h"

namespace rollwear::nist {
namespace {

// Same options for every problem: the defaults with a higher iteration cap
// (MGH17 from start 1 needs ~600 steps; the default is 500).
constexpr int kMaxIterations = 2000;

// A problem is solved at this minimum parameter LRE (digits).
constexpr double kSolvedLre = 4.0;
// Certified standard deviations must be matched to this many digits.
constexpr double kStandardErrorLre = 2.0;

// Solved today (min LRE >= 4, CONVERGENCE). Listed explicitly, not derived
// from the run, so that a regression on any one problem fails its own test.
// Roszman1 is missing only because of a defect of the local copy of its
// data file (see kCopyDefects). BoxBOD from start 1 (b = (1, 1)) ends on
// the plateau b2 -> large, b1 = mean(y) (b = (172.5, 84.2), RSS 9771.5 vs
// 1168.0 certified): exp(-b2*x) ~ 0 for every x >= 1, so the gradient
// vanishes there; it is not listed for start 1.
const char* const kSolvedFromStart2[] = {
    "Misra1a",  "Chwirut2", "Chwirut1", "Lanczos3", "Gauss1",  "Gauss2",
    "DanWood",  "Misra1b",  "Kirby2",   "Hahn1",    "Nelson",  "MGH17",
    "Lanczos1", "Lanczos2", "Gauss3",   "Misra1c",  "Misra1d", "ENSO",
    "MGH09",    "Thurber",  "BoxBOD",   "Rat42",    "MGH10",   "Eckerle4",
    "Rat43",    "Bennett5"};
const char* const kSolvedFromStart1[] = {
    "Misra1a", "Chwirut2", "Chwirut1", "Lanczos3", "Gauss1",
    "Gauss2",  "DanWood",  "Misra1b",  "Kirby2",   "Hahn1",
    "Nelson",  "MGH17",    "Lanczos1", "Lanczos2", "Gauss3",
    "Misra1c", "Misra1d",  "ENSO",     "MGH09",    "Thurber",
    "Rat42",   "MGH10",    "Eckerle4", "Rat43",    "Bennett5"};

// Defects of the copies in tests/data/nist (not of NIST's data): the value
// found in the copy and the value NIST publishes for the same entry.
struct CopyDefect {
  const char* name;
  int param;  // 0-based: 0 is b1
  double value_in_copy;
  double nist_value;
};
// Roszman1.dat here reads "b1 = 0.1 0.2 1.20196866396E-0 ..."; NIST's file
// reads 2.0196866396E-01 (https://www.itl.nist.gov/div898/strd/nls/data/
// LINKS/DATA/Roszman1.dat).
constexpr CopyDefect kCopyDefects[] = {
    {"Roszman1", 0, 1.20196866396, 2.0196866396E-01}};

bool HasCopyDefect(const std::string& name) {
  for (const CopyDefect& d : kCopyDefects) {
    if (name == d.name) return true;
  }
  return false;
}

std::string DataPath(const std::string& name) {
  return std::string(ROLLWEAR_TEST_DATA_DIR) + "/nist/" + name + ".dat";
}

ceres::Solver::Options NistSolverOptions() {
  LmOptions lm;
  lm.max_iterations = kMaxIterations;
  return MakeLmSolverOptions(lm);
}

// b = b* + S delta: the tangent space of this manifold is the equilibrated
// parameter delta (Jacobian J S); Ceres lifts covariances back by S.
class ColumnScalingManifold : public ceres::Manifold {
 public:
  explicit ColumnScalingManifold(std::vector<double> scale)
      : scale_(std::move(scale)) {}
  int AmbientSize() const override { return static_cast<int>(scale_.size()); }
  int TangentSize() const override { return static_cast<int>(scale_.size()); }
  bool Plus(const double* x, const double* delta,
            double* x_plus_delta) const override {
    for (size_t k = 0; k < scale_.size(); ++k) {
      x_plus_delta[k] = x[k] + scale_[k] * delta[k];
    }
    return true;
  }
  bool PlusJacobian(const double* x, double* jacobian) const override {
    return Diagonal(false, jacobian);
  }
  bool Minus(const double* y, const double* x,
             double* y_minus_x) const override {
    for (size_t k = 0; k < scale_.size(); ++k) {
      y_minus_x[k] = (y[k] - x[k]) / scale_[k];
    }
    return true;
  }
  bool MinusJacobian(const double* x, double* jacobian) const override {
    return Diagonal(true, jacobian);
  }

 private:
  bool Diagonal(bool inverse, double* jacobian) const {
    const size_t p = scale_.size();
    std::fill(jacobian, jacobian + p * p, 0.0);
    for (size_t k = 0; k < p; ++k) {
      jacobian[k * p + k] = inverse ? 1.0 / scale_[k] : scale_[k];
    }
    return true;
  }

  std::vector<double> scale_;
};

struct StandardErrors {
  bool ok = false;
  std::vector<double> se;
  double min_lre = 0.0;
};

// se_k = sqrt(RSS / (n - p) * Cov_kk) by ceres::Covariance (DENSE_SVD,
// null_space_rank = -1), optionally equilibrated (see file comment).
// Setting the manifold changes `ceres_problem`: call with equilibrate last.
StandardErrors ComputeStandardErrors(const NistProblem& problem, double rss,
                                     double* b, ceres::Problem* ceres_problem,
                                     bool equilibrate) {
  const int p = problem.num_params;
  if (equilibrate) {
    ceres::CRSMatrix jacobian;
    ceres_problem->Evaluate(ceres::Problem::EvaluateOptions(), nullptr, nullptr,
                            nullptr, &jacobian);
    std::vector<double> norm2(p, 0.0);
    for (size_t i = 0; i < jacobian.values.size(); ++i) {
      norm2[jacobian.cols[i]] += jacobian.values[i] * jacobian.values[i];
    }
    std::vector<double> scale(p);
    for (int k = 0; k < p; ++k) {
      scale[k] = norm2[k] > 0.0 ? 1.0 / std::sqrt(norm2[k]) : 1.0;
    }
    ceres_problem->SetManifold(b, new ColumnScalingManifold(scale));
  }
  ceres::Covariance::Options options;
  options.algorithm_type = ceres::DENSE_SVD;
  options.null_space_rank = -1;
  ceres::Covariance covariance(options);
  const std::vector<std::pair<const double*, const double*>> blocks = {{b, b}};
  std::vector<double> cov(static_cast<size_t>(p) * p, 0.0);
  StandardErrors out;
  if (!covariance.Compute(blocks, ceres_problem) ||
      !covariance.GetCovarianceBlock(b, b, cov.data())) {
    return out;
  }
  const double s2 = rss / problem.degrees_of_freedom;
  out.ok = true;
  out.min_lre = kMaxLre;
  for (int k = 0; k < p; ++k) {
    out.se.push_back(std::sqrt(s2 * cov[k * p + k]));
    out.min_lre =
        std::min(out.min_lre, Lre(out.se.back(), problem.certified_sd[k]));
  }
  return out;
}

// The outcome of one solve from one starting point.
struct Run {
  std::vector<double> b;
  double rss = 0.0;
  int iterations = 0;
  ceres::TerminationType termination = ceres::FAILURE;
  std::vector<double> lre;  // per parameter
  double min_lre = 0.0;
  double rss_lre = 0.0;
  StandardErrors raw_se;           // covariance of the raw Jacobian
  StandardErrors equilibrated_se;  // covariance of J S (checked)
};

Run Solve(const NistProblem& problem, const NistModel& model,
          const std::vector<double>& start) {
  Run run;
  run.b = start;
  ceres::Problem ceres_problem;
  model.add_residuals(problem, run.b.data(), &ceres_problem);
  ceres::Solver::Summary summary;
  ceres::Solve(NistSolverOptions(), &ceres_problem, &summary);

  run.termination = summary.termination_type;
  run.iterations =
      summary.num_successful_steps + summary.num_unsuccessful_steps;
  run.rss = NistResidualSumOfSquares(model, problem, run.b.data());
  run.rss_lre = Lre(run.rss, problem.certified_rss);
  run.min_lre = kMaxLre;
  for (int k = 0; k < problem.num_params; ++k) {
    run.lre.push_back(Lre(run.b[k], problem.certified[k]));
    run.min_lre = std::min(run.min_lre, run.lre.back());
  }
  run.raw_se = ComputeStandardErrors(problem, run.rss, run.b.data(),
                                     &ceres_problem, /*equilibrate=*/false);
  run.equilibrated_se = ComputeStandardErrors(
      problem, run.rss, run.b.data(), &ceres_problem, /*equilibrate=*/true);
  return run;
}

struct Result {
  NistProblem problem;
  Run start1;
  Run start2;
};

// Solves each problem once per process (gtest_discover_tests runs every
// test in its own process, so a per-problem test solves only its problem).
const Result& GetResult(const std::string& name) {
  static auto* const kCache = new std::map<std::string, Result>;
  auto it = kCache->find(name);
  if (it != kCache->end()) return it->second;
  Result result;
  StatusOr<NistProblem> parsed = ParseNistFile(DataPath(name));
  EXPECT_TRUE(parsed.ok()) << parsed.status().ToString();
  const NistModel* model = FindNistModel(name);
  EXPECT_NE(model, nullptr) << name;
  if (parsed.ok() && model != nullptr) {
    result.problem = *parsed;
    result.start1 = Solve(result.problem, *model, result.problem.start1);
    result.start2 = Solve(result.problem, *model, result.problem.start2);
  }
  return kCache->emplace(name, std::move(result)).first->second;
}

// "b1 = 238.94212917 (certified 238.94212918, LRE 10.3) ..." for failures.
std::string Describe(const NistProblem& problem, const Run& run) {
  std::string out;
  char line[200];
  for (int k = 0; k < problem.num_params; ++k) {
    std::snprintf(line, sizeof(line),
                  "\n  b%d = %.10e (certified %.10e, LRE %.1f)", k + 1,
                  run.b[k], problem.certified[k], run.lre[k]);
    out += line;
    if (run.equilibrated_se.ok) {
      std::snprintf(line, sizeof(line), "  se %.6e (certified %.6e)",
                    run.equilibrated_se.se[k], problem.certified_sd[k]);
      out += line;
    }
  }
  std::snprintf(line, sizeof(line), "\n  RSS %.10e (certified %.10e)", run.rss,
                problem.certified_rss);
  return out + line;
}

std::string SeCell(const StandardErrors& se) {
  char cell[16];
  if (!se.ok) return "   n/a";
  std::snprintf(cell, sizeof(cell), "%6.1f", se.min_lre);
  return cell;
}

// ---------------------------------------------------------------------------
// Parser, models, data.
// ---------------------------------------------------------------------------

TEST(NistParserTest, ParsesAll27Files) {
  ASSERT_EQ(NistProblemNames().size(), 27u);
  for (const std::string& name : NistProblemNames()) {
    SCOPED_TRACE(name);
    StatusOr<NistProblem> parsed = ParseNistFile(DataPath(name));
    ASSERT_TRUE(parsed.ok()) << parsed.status().ToString();
    const NistProblem& p = *parsed;
    const NistModel* model = FindNistModel(name);
    ASSERT_NE(model, nullptr);
    EXPECT_EQ(p.name, name);
    EXPECT_EQ(p.num_params, model->num_params);
    EXPECT_EQ(p.num_predictors, model->num_predictors);
    EXPECT_EQ(p.start1.size(), static_cast<size_t>(p.num_params));
    EXPECT_EQ(p.start2.size(), static_cast<size_t>(p.num_params));
    EXPECT_EQ(p.certified_sd.size(), static_cast<size_t>(p.num_params));
    EXPECT_EQ(p.y.size(), static_cast<size_t>(p.num_observations));
    EXPECT_EQ(p.x.size(),
              static_cast<size_t>(p.num_observations * p.num_predictors));
    EXPECT_TRUE(p.difficulty == "Lower" || p.difficulty == "Average" ||
                p.difficulty == "Higher")
        << p.difficulty;
    // NIST's Rat43.dat is the one file whose stated degrees of freedom
    // (9) differ from n - p (11).
    if (name != "Rat43") {
      EXPECT_EQ(p.stated_degrees_of_freedom, p.degrees_of_freedom);
    }
  }
}

TEST(NistParserTest, ReadsMisra1aExactly) {
  StatusOr<NistProblem> parsed = ParseNistFile(DataPath("Misra1a"));
  ASSERT_TRUE(parsed.ok()) << parsed.status().ToString();
  const NistProblem& p = *parsed;
  EXPECT_EQ(p.difficulty, "Lower");
  EXPECT_EQ(p.num_observations, 14);
  EXPECT_EQ(p.degrees_of_freedom, 12);
  EXPECT_EQ(p.start1, (std::vector<double>{500, 0.0001}));
  EXPECT_EQ(p.start2, (std::vector<double>{250, 0.0005}));
  EXPECT_EQ(p.certified,
            (std::vector<double>{2.3894212918E+02, 5.5015643181E-04}));
  EXPECT_EQ(p.certified_sd,
            (std::vector<double>{2.7070075241E+00, 7.2668688436E-06}));
  EXPECT_EQ(p.certified_rss, 1.2455138894E-01);
  EXPECT_EQ(p.certified_rsd, 1.0187876330E-01);
  EXPECT_EQ(p.y.front(), 10.07);
  EXPECT_EQ(p.x.front(), 77.6);
  EXPECT_EQ(p.y.back(), 81.78);
  EXPECT_EQ(p.x.back(), 760.0);
}

TEST(NistParserTest, ReadsNelsonTwoPredictorsAndRat43Dof) {
  StatusOr<NistProblem> nelson = ParseNistFile(DataPath("Nelson"));
  ASSERT_TRUE(nelson.ok()) << nelson.status().ToString();
  EXPECT_EQ(nelson->num_predictors, 2);
  EXPECT_EQ(nelson->x.size(), 2u * 128u);
  StatusOr<NistProblem> rat43 = ParseNistFile(DataPath("Rat43"));
  ASSERT_TRUE(rat43.ok()) << rat43.status().ToString();
  EXPECT_EQ(rat43->stated_degrees_of_freedom, 9);
  EXPECT_EQ(rat43->degrees_of_freedom, 11);
}

TEST(NistParserTest, RejectsMissingAndTruncatedFiles) {
  StatusOr<NistProblem> missing = ParseNistFile(DataPath("NoSuchProblem"));
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.status().code(), StatusCode::kIoError);

  // Misra1a without its last data row: row count no longer matches.
  std::ifstream in(DataPath("Misra1a"), std::ios::binary);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  while (!lines.empty() &&
         lines.back().find_first_not_of(" \r") == std::string::npos) {
    lines.pop_back();
  }
  ASSERT_FALSE(lines.empty());
  lines.pop_back();
  const std::string path = testing::TempDir() + "/nist_truncated.dat";
  {
    std::ofstream out(path, std::ios::binary);
    for (const std::string& line : lines) out << line << "\n";
  }
  StatusOr<NistProblem> truncated = ParseNistFile(path);
  ASSERT_FALSE(truncated.ok());
  EXPECT_EQ(truncated.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(truncated.status().message().find("13 data rows"),
            std::string::npos)
      << truncated.status().message();
}

TEST(NistParserTest, LreMatchesDefinition) {
  EXPECT_NEAR(Lre(1.0001, 1.0), 4.0, 1e-9);
  EXPECT_NEAR(Lre(-2.02, -2.0), 2.0, 1e-9);
  EXPECT_EQ(Lre(3.0, 3.0), kMaxLre);
  EXPECT_EQ(Lre(1.0 + 1e-15, 1.0), kMaxLre);
  EXPECT_EQ(Lre(100.0, 1.0), 0.0);
  EXPECT_EQ(Lre(std::nan(""), 1.0), 0.0);
}

// Evaluating each model at the certified parameters must give the certified
// residual sum of squares: checks the transcription of all 27 formulas and
// the parsed data in one go. Certified parameters are rounded to 11 digits,
// so Lanczos1 (RSS 1.4e-25 on y ~ 1) can only be checked to be tiny.
TEST(NistModelTest, CertifiedParametersGiveCertifiedRss) {
  for (const std::string& name : NistProblemNames()) {
    if (HasCopyDefect(name)) continue;  // see NistDataTest
    SCOPED_TRACE(name);
    StatusOr<NistProblem> parsed = ParseNistFile(DataPath(name));
    ASSERT_TRUE(parsed.ok()) << parsed.status().ToString();
    const NistModel& model = *FindNistModel(name);
    const double rss =
        NistResidualSumOfSquares(model, *parsed, parsed->certified.data());
    if (name == "Lanczos1") {
      EXPECT_LT(rss, 1e-20);
    } else {
      EXPECT_GE(Lre(rss, parsed->certified_rss), 6.0)
          << "rss " << rss << " certified " << parsed->certified_rss;
    }
  }
}

// The local copies listed in kCopyDefects still carry their defect (if one
// has been repaired, move the problem into kSolvedFromStart1/2), and with
// NIST's published value restored the model gives the certified RSS and the
// solve from start 2 reaches the certified values.
TEST(NistDataTest, KnownDefectsOfLocalCopies) {
  for (const CopyDefect& d : kCopyDefects) {
    SCOPED_TRACE(d.name);
    const Result& r = GetResult(d.name);
    ASSERT_EQ(r.problem.name, d.name);
    if (r.problem.certified[d.param] != d.value_in_copy) {
      ADD_FAILURE() << d.name << ".dat has been repaired (b" << d.param + 1
                    << " = " << r.problem.certified[d.param]
                    << "): remove it from kCopyDefects and add it to "
                       "kSolvedFromStart1/kSolvedFromStart2";
      continue;
    }
    std::vector<double> certified = r.problem.certified;
    certified[d.param] = d.nist_value;
    EXPECT_GE(Lre(NistResidualSumOfSquares(*FindNistModel(d.name), r.problem,
                                           certified.data()),
                  r.problem.certified_rss),
              6.0);
    for (int k = 0; k < r.problem.num_params; ++k) {
      EXPECT_GE(Lre(r.start2.b[k], certified[k]), kSolvedLre)
          << "b" << k + 1 << " = " << r.start2.b[k];
    }
    EXPECT_GE(r.start2.rss_lre, kSolvedLre);
  }
}

// ---------------------------------------------------------------------------
// Solver: the NIST table, the overall bar and one test per solved problem.
// ---------------------------------------------------------------------------

TEST(NistStrdTest, LevenbergMarquardtReproducesCertifiedValues) {
  int solved_start1 = 0, solved_start2 = 0, se_ok = 0;
  std::printf(
      "\nNIST StRD nonlinear regression with rollwear's LM set-up "
      "(MakeLmSolverOptions, default LmOptions, max_iterations %d)\n"
      "LRE = -log10(|b-c|/|c|) capped at %.0f, min over parameters; RSS and "
      "SE columns are for start 2\n(SE raw: covariance of J; SE eq: of the "
      "column-equilibrated J, the checked one).\n\n",
      kMaxIterations, kMaxLre);
  std::printf(
      "%-9s %-7s %3s %2s | %6s %6s | %6s | %6s %6s | %5s %5s | %-11s %s\n",
      "problem", "diff", "n", "p", "LRE s1", "LRE s2", "RSS", "SE raw", "SE eq",
      "it s1", "it s2", "term s1", "term s2");
  for (const std::string& name : NistProblemNames()) {
    const Result& r = GetResult(name);
    const NistProblem& p = r.problem;
    if (r.start1.min_lre >= kSolvedLre) ++solved_start1;
    if (r.start2.min_lre >= kSolvedLre) ++solved_start2;
    if (r.start2.equilibrated_se.ok &&
        r.start2.equilibrated_se.min_lre >= kStandardErrorLre) {
      ++se_ok;
    }
    std::printf(
        "%-9s %-7s %3d %2d | %6.1f %6.1f | %6.1f | %6s %6s | %5d %5d | "
        "%-11s %s%s\n",
        name.c_str(), p.difficulty.c_str(), p.num_observations, p.num_params,
        r.start1.min_lre, r.start2.min_lre, r.start2.rss_lre,
        SeCell(r.start2.raw_se).c_str(),
        SeCell(r.start2.equilibrated_se).c_str(), r.start1.iterations,
        r.start2.iterations,
        ceres::TerminationTypeToString(r.start1.termination),
        ceres::TerminationTypeToString(r.start2.termination),
        HasCopyDefect(name) ? "  (defective copy, see NistDataTest)" : "");
  }
  std::printf(
      "\nsolved (min LRE >= %.0f): start 1 %d/27, start 2 %d/27; "
      "SE eq >= %.0f digits: %d/27\n\n",
      kSolvedLre, solved_start1, solved_start2, kStandardErrorLre, se_ok);
  std::fflush(stdout);
  EXPECT_GE(solved_start2, 24);
}

class NistStart2Test : public testing::TestWithParam<const char*> {};
class NistStart1Test : public testing::TestWithParam<const char*> {};

TEST_P(NistStart2Test, ReachesCertifiedValues) {
  const Result& r = GetResult(GetParam());
  ASSERT_EQ(r.problem.name, GetParam());
  EXPECT_EQ(r.start2.termination, ceres::CONVERGENCE);
  EXPECT_GE(r.start2.min_lre, kSolvedLre) << Describe(r.problem, r.start2);
  // Lanczos1's certified RSS (1.4e-25) sits at the rounding level of
  // sum((y - f)^2) for y ~ 1: only ~4 of its digits are reproducible.
  const double rss_digits = GetParam() == std::string("Lanczos1") ? 3.0 : 6.0;
  EXPECT_GE(r.start2.rss_lre, rss_digits) << Describe(r.problem, r.start2);
}

TEST_P(NistStart2Test, ReachesCertifiedStandardDeviations) {
  const Result& r = GetResult(GetParam());
  ASSERT_TRUE(r.start2.equilibrated_se.ok) << "covariance failed";
  EXPECT_GE(r.start2.equilibrated_se.min_lre, kStandardErrorLre)
      << Describe(r.problem, r.start2);
}

TEST_P(NistStart1Test, ReachesCertifiedValues) {
  const Result& r = GetResult(GetParam());
  ASSERT_EQ(r.problem.name, GetParam());
  EXPECT_EQ(r.start1.termination, ceres::CONVERGENCE);
  EXPECT_GE(r.start1.min_lre, kSolvedLre) << Describe(r.problem, r.start1);
}

std::string ParamName(const testing::TestParamInfo<const char*>& info) {
  return info.param;
}

INSTANTIATE_TEST_SUITE_P(Nist, NistStart2Test,
                         testing::ValuesIn(kSolvedFromStart2), ParamName);
INSTANTIATE_TEST_SUITE_P(Nist, NistStart1Test,
                         testing::ValuesIn(kSolvedFromStart1), ParamName);

}  // namespace
}  // namespace rollwear::nist
