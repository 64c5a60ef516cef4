// NIST StRD nonlinear regression problems: .dat parser, the 27 model
// functions as Ceres autodiff functors, and the LRE score. See
// nist_problems.h; data and formulas from https://www.itl.nist.gov/div898/strd/
#include "tests/core/nist_problems.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include <ceres/autodiff_cost_function.h>

namespace rollwear::nist {
namespace {

// ---------------------------------------------------------------------------
// Parser
// ---------------------------------------------------------------------------

std::vector<std::string> SplitWhitespace(std::string_view line) {
  std::vector<std::string> out;
  std::istringstream in{std::string(line)};
  std::string token;
  while (in >> token) out.push_back(token);
  return out;
}

// Strict: the whole token must be a number ("1.20196866396E-0" is fine).
bool ParseDouble(std::string_view token, double* out) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  auto [ptr, ec] = std::from_chars(token.data(), end, *out);
  return ec == std::errc() && ptr == end && std::isfinite(*out);
}

bool StartsWith(std::string_view s, std::string_view prefix) {
  return s.substr(0, prefix.size()) == prefix;
}

std::string_view TrimLeft(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) {
    s.remove_prefix(1);
  }
  return s;
}

// The number following `label` on a line such as
// "Residual Sum of Squares:        1.2455138894E-01".
bool ValueAfterLabel(std::string_view line, std::string_view label,
                     double* out) {
  if (!StartsWith(line, label)) return false;
  const auto tokens = SplitWhitespace(line.substr(label.size()));
  return tokens.size() == 1 && ParseDouble(tokens[0], out);
}

}  // namespace

StatusOr<NistProblem> ParseNistFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::IoError(path + ": cannot open");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(std::move(line));
  }
  auto error = [&path](size_t line_index, const std::string& what) {
    return Status::InvalidArgument(path + ":" + std::to_string(line_index + 1) +
                                   ": " + what);
  };

  NistProblem p;
  double rss = -1.0, rsd = -1.0, n_obs = -1.0, dof = -1.0;
  size_t data_header = lines.size();
  for (size_t i = 0; i < lines.size(); ++i) {
    const std::string_view line = TrimLeft(lines[i]);
    if (StartsWith(line, "Dataset Name:")) {
      const auto tokens = SplitWhitespace(line.substr(13));
      if (tokens.empty()) return error(i, "empty dataset name");
      p.name = tokens[0];
    } else if (line.find("Level of Difficulty") != std::string_view::npos) {
      p.difficulty = SplitWhitespace(line)[0];
    } else if (line.size() > 1 && line[0] == 'b' &&
               std::isdigit(static_cast<unsigned char>(line[1]))) {
      // "b1 =   500   250   2.3894212918E+02  2.7070075241E+00"
      const auto tokens = SplitWhitespace(line);
      if (tokens.size() != 6 || tokens[1] != "=") {
        return error(i, "parameter line must read 'bK = s1 s2 value sd'");
      }
      if (tokens[0] != "b" + std::to_string(p.num_params + 1)) {
        return error(i, "parameters out of order: " + tokens[0]);
      }
      double v[4];
      for (int k = 0; k < 4; ++k) {
        if (!ParseDouble(tokens[2 + k], &v[k])) {
          return error(i, "not a number: " + tokens[2 + k]);
        }
      }
      p.start1.push_back(v[0]);
      p.start2.push_back(v[1]);
      p.certified.push_back(v[2]);
      p.certified_sd.push_back(v[3]);
      ++p.num_params;
    } else if (ValueAfterLabel(line, "Residual Sum of Squares:", &rss) ||
               ValueAfterLabel(line, "Residual Standard Deviation:", &rsd) ||
               ValueAfterLabel(line, "Number of Observations:", &n_obs) ||
               ValueAfterLabel(line, "Degrees of Freedom:", &dof)) {
      // Stored by ValueAfterLabel.
    } else if (StartsWith(line, "Data:")) {
      // The first "Data:" describes the variables; the data table header is
      // "Data:   y   x" (or "y x1 x2").
      const auto tokens = SplitWhitespace(line);
      if (tokens.size() >= 3 && tokens[1] == "y") {
        p.num_predictors = static_cast<int>(tokens.size()) - 2;
        data_header = i;
        break;
      }
    }
  }

  if (p.name.empty()) return error(0, "no 'Dataset Name:'");
  if (p.difficulty.empty()) return error(0, "no 'Level of Difficulty'");
  if (p.num_params == 0) return error(0, "no parameter lines");
  if (rss < 0 || rsd < 0) return error(0, "no certified RSS or RSD");
  if (n_obs <= 0 || dof <= 0) return error(0, "no observation/dof counts");
  if (data_header == lines.size()) return error(0, "no data table header");
  p.certified_rss = rss;
  p.certified_rsd = rsd;
  p.num_observations = static_cast<int>(n_obs);
  p.stated_degrees_of_freedom = static_cast<int>(dof);
  p.degrees_of_freedom = p.num_observations - p.num_params;
  if (p.degrees_of_freedom <= 0) return error(0, "n <= p");
  // RSD = sqrt(RSS / (n - p)); both are certified to 11 digits.
  if (std::abs(rsd * rsd * p.degrees_of_freedom - rss) > 1e-8 * rss) {
    return error(0, "RSD^2 * (n - p) != RSS");
  }

  for (size_t i = data_header + 1; i < lines.size(); ++i) {
    const auto tokens = SplitWhitespace(lines[i]);
    if (tokens.empty()) continue;
    if (static_cast<int>(tokens.size()) != 1 + p.num_predictors) {
      return error(i, "expected " + std::to_string(1 + p.num_predictors) +
                          " numbers on a data row");
    }
    double v;
    for (size_t k = 0; k < tokens.size(); ++k) {
      if (!ParseDouble(tokens[k], &v)) {
        return error(i, "not a number: " + tokens[k]);
      }
      (k == 0 ? p.y : p.x).push_back(v);
    }
  }
  if (static_cast<int>(p.y.size()) != p.num_observations) {
    return error(data_header, "found " + std::to_string(p.y.size()) +
                                  " data rows, header says " +
                                  std::to_string(p.num_observations));
  }
  return p;
}

double Lre(double estimate, double certified) {
  if (!std::isfinite(estimate)) return 0.0;
  const double abs_error = std::abs(estimate - certified);
  if (abs_error == 0.0) return kMaxLre;
  const double rel_error =
      certified != 0.0 ? abs_error / std::abs(certified) : abs_error;
  // std::max also maps -0.0 (= -log10(1)) to +0.0.
  return std::min(kMaxLre, std::max(0.0, -std::log10(rel_error)));
}

// ---------------------------------------------------------------------------
// Models. Each struct computes the model prediction f(x; b) for T = double
// or ceres::Jet (unqualified exp/pow/... resolve to ceres:: for Jets by ADL).
// b[0] is NIST's b1. Formulas are those of the "Model:" section of each
// .dat file.
// ---------------------------------------------------------------------------
namespace {

using std::atan;
using std::cos;
using std::exp;
using std::pow;
using std::sin;
constexpr double kPi = std::numbers::pi;  // Roszman1, ENSO

// Misra1a, BoxBOD: y = b1*(1-exp[-b2*x])
struct ExpRise {
  static constexpr int kNumParams = 2;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    return b[0] * (1.0 - exp(-b[1] * x[0]));
  }
};

// Misra1b: y = b1 * (1-(1+b2*x/2)**(-2))
struct Misra1b {
  static constexpr int kNumParams = 2;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    return b[0] * (1.0 - pow(1.0 + b[1] * x[0] / 2.0, -2.0));
  }
};

// Misra1c: y = b1 * (1-(1+2*b2*x)**(-.5))
struct Misra1c {
  static constexpr int kNumParams = 2;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    return b[0] * (1.0 - pow(1.0 + 2.0 * b[1] * x[0], -0.5));
  }
};

// Misra1d: y = b1*b2*x*((1+b2*x)**(-1))
struct Misra1d {
  static constexpr int kNumParams = 2;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    return b[0] * b[1] * x[0] / (1.0 + b[1] * x[0]);
  }
};

// Chwirut1, Chwirut2: y = exp[-b1*x]/(b2+b3*x)
struct Chwirut {
  static constexpr int kNumParams = 3;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    return exp(-b[0] * x[0]) / (b[1] + b[2] * x[0]);
  }
};

// Lanczos1/2/3: y = b1*exp(-b2*x) + b3*exp(-b4*x) + b5*exp(-b6*x)
struct Lanczos {
  static constexpr int kNumParams = 6;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    return b[0] * exp(-b[1] * x[0]) + b[2] * exp(-b[3] * x[0]) +
           b[4] * exp(-b[5] * x[0]);
  }
};

// Gauss1/2/3: y = b1*exp( -b2*x ) + b3*exp( -(x-b4)**2 / b5**2 )
//                                 + b6*exp( -(x-b7)**2 / b8**2 )
struct Gauss {
  static constexpr int kNumParams = 8;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    const T d1 = x[0] - b[3];
    const T d2 = x[0] - b[6];
    return b[0] * exp(-b[1] * x[0]) + b[2] * exp(-d1 * d1 / (b[4] * b[4])) +
           b[5] * exp(-d2 * d2 / (b[7] * b[7]));
  }
};

// DanWood: y = b1*x**b2
struct DanWood {
  static constexpr int kNumParams = 2;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    return b[0] * pow(x[0], b[1]);
  }
};

// MGH09: y = b1*(x**2+x*b2) / (x**2+x*b3+b4)
struct Mgh09 {
  static constexpr int kNumParams = 4;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    const double xx = x[0] * x[0];
    return b[0] * (xx + x[0] * b[1]) / (xx + x[0] * b[2] + b[3]);
  }
};

// MGH10: y = b1 * exp[b2/(x+b3)]
struct Mgh10 {
  static constexpr int kNumParams = 3;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    return b[0] * exp(b[1] / (x[0] + b[2]));
  }
};

// MGH17: y = b1 + b2*exp[-x*b4] + b3*exp[-x*b5]
struct Mgh17 {
  static constexpr int kNumParams = 5;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    return b[0] + b[1] * exp(-x[0] * b[3]) + b[2] * exp(-x[0] * b[4]);
  }
};

// Kirby2: y = (b1 + b2*x + b3*x**2) / (1 + b4*x + b5*x**2)
struct Kirby2 {
  static constexpr int kNumParams = 5;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    const double t = x[0];
    return (b[0] + b[1] * t + b[2] * (t * t)) /
           (1.0 + b[3] * t + b[4] * (t * t));
  }
};

// Hahn1, Thurber: y = (b1+b2*x+b3*x**2+b4*x**3) / (1+b5*x+b6*x**2+b7*x**3)
struct CubicOverCubic {
  static constexpr int kNumParams = 7;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    const double t = x[0], t2 = t * t, t3 = t2 * t;
    return (b[0] + b[1] * t + b[2] * t2 + b[3] * t3) /
           (1.0 + b[4] * t + b[5] * t2 + b[6] * t3);
  }
};

// Nelson: log[y] = b1 - b2*x1 * exp[-b3*x2]   (x[0] = x1, x[1] = x2; the
// residual is taken on log(y), see kLogResponse).
struct Nelson {
  static constexpr int kNumParams = 3;
  static constexpr bool kLogResponse = true;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    return b[0] - b[1] * x[0] * exp(-b[2] * x[1]);
  }
};

// Roszman1: y = b1 - b2*x - arctan[b3/(x-b4)]/pi
struct Roszman1 {
  static constexpr int kNumParams = 4;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    return b[0] - b[1] * x[0] - atan(b[2] / (x[0] - b[3])) / kPi;
  }
};

// ENSO: y = b1 + b2*cos( 2*pi*x/12 ) + b3*sin( 2*pi*x/12 )
//          + b5*cos( 2*pi*x/b4 ) + b6*sin( 2*pi*x/b4 )
//          + b8*cos( 2*pi*x/b7 ) + b9*sin( 2*pi*x/b7 )
struct Enso {
  static constexpr int kNumParams = 9;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    const double w = 2.0 * kPi * x[0];
    const T a4 = w / b[3];
    const T a7 = w / b[6];
    return b[0] + b[1] * cos(w / 12.0) + b[2] * sin(w / 12.0) + b[4] * cos(a4) +
           b[5] * sin(a4) + b[7] * cos(a7) + b[8] * sin(a7);
  }
};

// Rat42: y = b1 / (1+exp[b2-b3*x])
struct Rat42 {
  static constexpr int kNumParams = 3;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    return b[0] / (1.0 + exp(b[1] - b[2] * x[0]));
  }
};

// Rat43: y = b1 / ((1+exp[b2-b3*x])**(1/b4))
struct Rat43 {
  static constexpr int kNumParams = 4;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    return b[0] / pow(1.0 + exp(b[1] - b[2] * x[0]), 1.0 / b[3]);
  }
};

// Eckerle4: y = (b1/b2) * exp[-0.5*((x-b3)/b2)**2]
struct Eckerle4 {
  static constexpr int kNumParams = 3;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    const T z = (x[0] - b[2]) / b[1];
    return (b[0] / b[1]) * exp(-0.5 * z * z);
  }
};

// Bennett5: y = b1 * (b2+x)**(-1/b3)
struct Bennett5 {
  static constexpr int kNumParams = 3;
  template <typename T>
  static T Predict(const T* b, const double* x) {
    return b[0] * pow(b[1] + x[0], -1.0 / b[2]);
  }
};

template <typename Model>
constexpr bool IsLogResponse() {
  if constexpr (requires { Model::kLogResponse; }) {
    return Model::kLogResponse;
  } else {
    return false;
  }
}

// The templated cost functor of one observation: r = y - f(x; b), with
// y replaced by log(y) for log-response models.
template <typename Model>
class NistResidual {
 public:
  NistResidual(double y, const double* x, int num_predictors)
      : y_(IsLogResponse<Model>() ? std::log(y) : y) {
    for (int k = 0; k < num_predictors; ++k) x_[k] = x[k];
  }

  // Returns false where the model overflows or leaves its domain (a trial
  // step of LM far from the solution); Ceres then rejects the step, as it
  // would for a non-finite residual, but without logging a warning.
  template <typename T>
  bool operator()(const T* b, T* residual) const {
    residual[0] = T(y_) - Model::Predict(b, x_);
    using ceres::isfinite;
    using std::isfinite;
    return isfinite(residual[0]);
  }

 private:
  double y_;
  double x_[2] = {0.0, 0.0};
};

template <typename Model>
void AddResiduals(const NistProblem& problem, double* b,
                  ceres::Problem* ceres_problem) {
  const size_t m = problem.num_predictors;
  for (size_t i = 0; i < problem.y.size(); ++i) {
    auto* cost = new ceres::AutoDiffCostFunction<NistResidual<Model>, 1,
                                                 Model::kNumParams>(
        new NistResidual<Model>(problem.y[i], &problem.x[i * m],
                                problem.num_predictors));
    ceres_problem->AddResidualBlock(cost, nullptr, b);
  }
}

template <typename Model>
double PredictDouble(const double* b, const double* x) {
  return Model::template Predict<double>(b, x);
}

template <typename Model>
constexpr NistModel Entry(const char* name, int num_predictors,
                          const char* formula) {
  return NistModel{name,
                   Model::kNumParams,
                   num_predictors,
                   formula,
                   &AddResiduals<Model>,
                   &PredictDouble<Model>,
                   IsLogResponse<Model>()};
}

// NIST's order: lower, average, higher level of difficulty.
const NistModel kModels[] = {
    Entry<ExpRise>("Misra1a", 1, "y = b1*(1-exp[-b2*x])"),
    Entry<Chwirut>("Chwirut2", 1, "y = exp(-b1*x)/(b2+b3*x)"),
    Entry<Chwirut>("Chwirut1", 1, "y = exp[-b1*x]/(b2+b3*x)"),
    Entry<Lanczos>("Lanczos3", 1,
                   "y = b1*exp(-b2*x) + b3*exp(-b4*x) + b5*exp(-b6*x)"),
    Entry<Gauss>("Gauss1", 1,
                 "y = b1*exp(-b2*x) + b3*exp(-(x-b4)**2/b5**2) + "
                 "b6*exp(-(x-b7)**2/b8**2)"),
    Entry<Gauss>("Gauss2", 1,
                 "y = b1*exp(-b2*x) + b3*exp(-(x-b4)**2/b5**2) + "
                 "b6*exp(-(x-b7)**2/b8**2)"),
    Entry<DanWood>("DanWood", 1, "y = b1*x**b2"),
    Entry<Misra1b>("Misra1b", 1, "y = b1 * (1-(1+b2*x/2)**(-2))"),
    Entry<Kirby2>("Kirby2", 1,
                  "y = (b1 + b2*x + b3*x**2) / (1 + b4*x + b5*x**2)"),
    Entry<CubicOverCubic>("Hahn1", 1,
                          "y = (b1+b2*x+b3*x**2+b4*x**3) / "
                          "(1+b5*x+b6*x**2+b7*x**3)"),
    Entry<Nelson>("Nelson", 2, "log[y] = b1 - b2*x1 * exp[-b3*x2]"),
    Entry<Mgh17>("MGH17", 1, "y = b1 + b2*exp[-x*b4] + b3*exp[-x*b5]"),
    Entry<Lanczos>("Lanczos1", 1,
                   "y = b1*exp(-b2*x) + b3*exp(-b4*x) + b5*exp(-b6*x)"),
    Entry<Lanczos>("Lanczos2", 1,
                   "y = b1*exp(-b2*x) + b3*exp(-b4*x) + b5*exp(-b6*x)"),
    Entry<Gauss>("Gauss3", 1,
                 "y = b1*exp(-b2*x) + b3*exp(-(x-b4)**2/b5**2) + "
                 "b6*exp(-(x-b7)**2/b8**2)"),
    Entry<Misra1c>("Misra1c", 1, "y = b1 * (1-(1+2*b2*x)**(-.5))"),
    Entry<Misra1d>("Misra1d", 1, "y = b1*b2*x*((1+b2*x)**(-1))"),
    Entry<Roszman1>("Roszman1", 1, "y = b1 - b2*x - arctan[b3/(x-b4)]/pi"),
    Entry<Enso>("ENSO", 1,
                "y = b1 + b2*cos(2*pi*x/12) + b3*sin(2*pi*x/12) + "
                "b5*cos(2*pi*x/b4) + b6*sin(2*pi*x/b4) + b8*cos(2*pi*x/b7) + "
                "b9*sin(2*pi*x/b7)"),
    Entry<Mgh09>("MGH09", 1, "y = b1*(x**2+x*b2) / (x**2+x*b3+b4)"),
    Entry<CubicOverCubic>("Thurber", 1,
                          "y = (b1 + b2*x + b3*x**2 + b4*x**3) / "
                          "(1 + b5*x + b6*x**2 + b7*x**3)"),
    Entry<ExpRise>("BoxBOD", 1, "y = b1*(1-exp[-b2*x])"),
    Entry<Rat42>("Rat42", 1, "y = b1 / (1+exp[b2-b3*x])"),
    Entry<Mgh10>("MGH10", 1, "y = b1 * exp[b2/(x+b3)]"),
    Entry<Eckerle4>("Eckerle4", 1, "y = (b1/b2) * exp[-0.5*((x-b3)/b2)**2]"),
    Entry<Rat43>("Rat43", 1, "y = b1 / ((1+exp[b2-b3*x])**(1/b4))"),
    Entry<Bennett5>("Bennett5", 1, "y = b1 * (b2+x)**(-1/b3)"),
};

}  // namespace

const NistModel* FindNistModel(std::string_view name) {
  for (const NistModel& model : kModels) {
    if (name == model.name) return &model;
  }
  return nullptr;
}

const std::vector<std::string>& NistProblemNames() {
  static const std::vector<std::string>* const kNames = [] {
    auto* names = new std::vector<std::string>;
    for (const NistModel& model : kModels) names->push_back(model.name);
    return names;
  }();
  return *kNames;
}

double NistResidualSumOfSquares(const NistModel& model,
                                const NistProblem& problem, const double* b) {
  const size_t m = problem.num_predictors;
  double rss = 0.0;
  for (size_t i = 0; i < problem.y.size(); ++i) {
    const double y = model.log_response ? std::log(problem.y[i]) : problem.y[i];
    const double r = y - model.predict(b, &problem.x[i * m]);
    rss += r * r;
  }
  return rss;
}

}  // namespace rollwear::nist
