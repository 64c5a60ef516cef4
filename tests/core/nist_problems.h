// NIST StRD nonlinear least-squares reference problems for the tests of
// rollwear's Levenberg-Marquardt set-up (core/fit/lm_setup.h).
//
// Source: NIST Information Technology Laboratory, Statistical Reference
// Datasets (StRD), nonlinear regression,
// https://www.itl.nist.gov/div898/strd/ (public domain). The 27 .dat files
// are copied unchanged into tests/data/nist/ (see the README there).
//
// This file provides
//   - ParseNistFile: reads one .dat file (two starting points, certified
//     parameter values and standard deviations, certified residual sum of
//     squares, the data table "y x" or, for Nelson, "y x1 x2");
//   - FindNistModel: the 27 model functions, each a templated functor for
//     ceres::AutoDiffCostFunction (formulas copied from the .dat files);
//   - Lre: the log relative error NIST uses to score results.
//
// Thread-safety: pure functions; the model table is immutable.
#ifndef ROLLWEAR_TESTS_CORE_NIST_PROBLEMS_H_
#define ROLLWEAR_TESTS_CORE_NIST_PROBLEMS_H_

#include <string>
#include <string_view>
#include <vector>

#include <ceres/problem.h>

#include "core/base/status.h"

namespace rollwear::nist {

// Certified values are given to 11 significant digits, so an LRE above 11
// carries no information.
inline constexpr double kMaxLre = 11.0;

// One parsed StRD .dat file.
struct NistProblem {
  std::string name;        // "Misra1a" (from "Dataset Name:")
  std::string difficulty;  // "Lower", "Average" or "Higher"
  int num_params = 0;
  int num_observations = 0;
  // n - p. The file's own "Degrees of Freedom" line is kept separately:
  // NIST's Rat43.dat states 9 where n - p = 11 (its residual standard
  // deviation, sqrt(RSS / 11), confirms 11).
  int degrees_of_freedom = 0;
  int stated_degrees_of_freedom = 0;
  int num_predictors = 0;  // 1, or 2 for Nelson
  std::vector<double> start1;
  std::vector<double> start2;
  std::vector<double> certified;     // certified parameter values
  std::vector<double> certified_sd;  // their certified standard deviations
  double certified_rss = 0.0;        // certified residual sum of squares
  double certified_rsd = 0.0;        // residual standard deviation
  std::vector<double> y;             // num_observations responses
  std::vector<double> x;             // row-major, num_predictors per row
};

// Parses a NIST StRD nonlinear regression file (CRLF or LF line ends).
// Checks internal consistency: parameters b1..bp in order, 4 numbers each,
// the data row count equals "Number of Observations", and
// RSD^2 * (n - p) equals the RSS to 1e-8 (relative).
StatusOr<NistProblem> ParseNistFile(const std::string& path);

// The model of one StRD problem, wired for Ceres.
struct NistModel {
  const char* name;  // dataset name, e.g. "Misra1a"
  int num_params;
  int num_predictors;
  const char* formula;  // as written in the .dat file
  // Adds one residual block per observation of `problem` on the parameter
  // block `b` (num_params doubles):
  //   r_i = y_i - f(x_i; b)            (Nelson: r_i = log(y_i) - f).
  void (*add_residuals)(const NistProblem& problem, double* b,
                        ceres::Problem* ceres_problem);
  // f(x_i; b) in double precision (the response scale of the residual).
  double (*predict)(const double* b, const double* x);
  // True when the residual is taken on log(y) (Nelson).
  bool log_response;
};

// The model for dataset `name`, or nullptr if it is not one of the 27.
const NistModel* FindNistModel(std::string_view name);

// The 27 dataset names in NIST's order (lower, average, higher difficulty).
const std::vector<std::string>& NistProblemNames();

// Residual sum of squares of `model` on `problem` at parameters `b`.
double NistResidualSumOfSquares(const NistModel& model,
                                const NistProblem& problem, const double* b);

// Log relative error, NIST's score of an estimate against a certified value:
//   LRE = -log10(|estimate - certified| / |certified|)
// (absolute error if certified == 0), clamped to [0, kMaxLre]; a non-finite
// estimate scores 0.
double Lre(double estimate, double certified);

}  // namespace rollwear::nist

#endif  // ROLLWEAR_TESTS_CORE_NIST_PROBLEMS_H_
