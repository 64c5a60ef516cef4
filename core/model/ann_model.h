// AnnModel: the rollwear study's recurrent neural K-estimator as a value the
// daemon can serve, with incremental (coil-by-coil) prediction and a compact
// versioned text serialisation. Training lives in ann_train.h.
//
// For pass i of a roll position, each network (ensemble member) m computes
//   x_i  = [ static roll inputs s | pass inputs p_i | u_{i-1} ]   (scaled)
//   h1   = selu(A x_i + b1)                  (hidden layer 1, H1 neurons)
//   h2   = sigmoid(B h1 + b2)                (hidden layer 2, H2 neurons)
//   K_i  = exp(v . h2 + q . x_i + c)         (K > 0 by construction)
//   w_i  = K_i * (F/w) * L                   (Wang's law, wear_law.h)
//   W_i  = W_{i-1} + w_i,  W_0 = 0,  u_{i-1} = (W_{i-1} - mu_W) / sd_W
// so the network sees the roll's own cumulative predicted wear (the
// recurrence). q is an optional linear skip path from the inputs to log K
// (q = 0 is the study's network; with q the network nests a log-linear K
// such as the classical option 1, see docs/ann.md). The campaign's predicted
// wear is W_n; the model's prediction is the mean of the members' W_n (each
// member feeds back its own W). selu: Klambauer et al., "Self-normalizing
// neural networks", NIPS 2017.
//
// Inputs: s = one-hot roll position, one-hot roll type, hardness_hb (0,
// the training mean, when not recorded),
// diameter_mm; p_i = one-hot grade, force_kn, width_mm, specific force,
// length_m, entry/exit thickness, reduction, contact length, temperature_c,
// speed_mps, lubrication, shift_mm. Continuous inputs are standardised with
// (x - mean) / sd fitted on training campaigns; one-hot inputs are 0/1; an
// unknown label gives an all-zero one-hot block.
//
// Thread-safety: AnnModel is immutable after training or parsing; its const
// functions may be called concurrently. AnnRollState is a plain value;
// callers serialise updates of one state.
#ifndef ROLLWEAR_CORE_MODEL_ANN_MODEL_H_
#define ROLLWEAR_CORE_MODEL_ANN_MODEL_H_

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/dataset/dataset.h"
#include "core/dataset/pass_input.h"
#include "core/base/status.h"

namespace rollwear {

// Model name of the recurrent network in runs and model versions (the
// other models are named by their law, WearLawName).
inline constexpr char kAnnModelName[] = "ann";

// selu(z) = lambda * z (z > 0), lambda * alpha * (exp(z) - 1) (z <= 0);
// constants of Klambauer et al. 2017, Eq. 14.
constexpr double kAnnSeluLambda = 1.0507009873554804934193349852946;
constexpr double kAnnSeluAlpha = 1.6732632423543772848170429916717;

// In-place activations on a vector or column block (vectorised by Eigen):
//   selu(z) as above; sigmoid(z) = 1 / (1 + exp(-z)).
template <typename V>
void AnnSelu(V* z) {
  auto a = z->array();
  a = (a > 0).select(kAnnSeluLambda * a,
                     (kAnnSeluLambda * kAnnSeluAlpha) * (a.exp() - 1));
}
template <typename V>
void AnnSigmoid(V* z) {
  auto a = z->array();
  a = (-a).exp();
  a = (a + 1).inverse();
}

// Weights of one network. Columns of `a` follow AnnModel's input layout.
struct AnnNetwork {
  Eigen::MatrixXd a;   // H1 x D
  Eigen::VectorXd b1;  // H1
  Eigen::MatrixXd b;   // H2 x H1
  Eigen::VectorXd b2;  // H2
  Eigen::VectorXd v;   // H2
  Eigen::VectorXd q;   // D, linear skip (zero = the study's architecture)
  double c = 0;

  int num_parameters() const {
    return static_cast<int>(a.size() + b1.size() + b.size() + b2.size() +
                            v.size() + q.size() + 1);
  }
  // A network of the given shape with every weight zero.
  static AnnNetwork Zero(int inputs, int hidden1, int hidden2);
  // Flattened parameters (a, b1, b, b2 column-major, then v, q, c) and back.
  Eigen::VectorXd Flatten() const;
  void Unflatten(const Eigen::VectorXd& theta);
  // 1 for weights (a, b, v, q), 0 for biases (b1, b2, c): weight-decay mask.
  Eigen::VectorXd WeightMask() const;
};

// The raw (unscaled) continuous pass inputs, in input order.
constexpr int kAnnNumPassContinuous = 12;
// Names of those inputs (data-format.md columns and derived names).
const std::vector<std::string>& AnnPassContinuousNames();

// Raw continuous inputs of a pass on a roll of `diameter_mm` (size
// kAnnNumPassContinuous).
void AnnRawPassFeatures(const PassInput& pass, double diameter_mm,
                        double* out);

struct AnnModel {
  static constexpr int kFormatVersion = 1;

  std::vector<std::string> positions;   // "F6/top", one-hot order
  std::vector<std::string> roll_types;  // one-hot order
  std::vector<std::string> grades;      // one-hot order
  int hidden1 = 10;
  int hidden2 = 10;
  // Scaling of every input column (one-hot columns: mean 0, sd 1; the last
  // column is the cumulative wear state, µm).
  Eigen::VectorXd input_mean;
  Eigen::VectorXd input_sd;
  std::vector<AnnNetwork> members;  // the ensemble; prediction = mean

  // Input layout: [static | pass | state].
  int num_static() const {
    return static_cast<int>(positions.size() + roll_types.size()) + 2;
  }
  int num_pass() const {
    return static_cast<int>(grades.size()) + kAnnNumPassContinuous;
  }
  int num_inputs() const { return num_static() + num_pass() + 1; }
  int state_column() const { return num_inputs() - 1; }
  // Input names in layout order ("pos:F6/top", "grade:CQ", "force_kn", ...,
  // "wear_so_far_um").
  std::vector<std::string> InputNames() const;

  // Level index of a label, -1 when unknown.
  int PositionLevel(const std::string& label) const;
  int RollTypeLevel(const std::string& label) const;
  int GradeLevel(const std::string& label) const;

  // Scaled static inputs (size num_static()).
  Eigen::VectorXd EncodeStatic(int position, int roll_type, double hardness_hb,
                               double diameter_mm) const;
  // Scaled pass inputs (size num_pass()) written to `out`.
  void EncodePass(const PassInput& pass, double diameter_mm,
                  double* out) const;
  // Scaled state input u = (W - mu_W) / sd_W.
  double EncodeState(double wear_um) const {
    return (wear_um - input_mean[state_column()]) / input_sd[state_column()];
  }

  // Structural consistency (sizes, finite values, positive sd).
  Status Validate() const;
};

// The state the daemon keeps per mounted roll.
struct AnnRollState {
  int position = -1;   // position level (-1 unknown)
  int roll_type = -1;  // roll type level (-1 unknown)
  double diameter_mm = 0;
  double hardness_hb = 0;
  double wear_um = 0;                  // ensemble mean of member_wear_um
  std::vector<double> member_wear_um;  // W of each member (its recurrence)
  int coils = 0;
  double rolled_length_m = 0;
  // Per member A_s s + b1 and q_s . s, the pass-independent parts of layer 1
  // and of the skip path.
  std::vector<Eigen::VectorXd> static_part;
  std::vector<double> static_linear;
};

// A freshly mounted roll at `position_label` ("F6/top").
AnnRollState MountRoll(const AnnModel& model, const std::string& position_label,
                       const std::string& roll_type, double diameter_mm,
                       double hardness_hb);

// Adds one pass; returns the increment of the ensemble-mean wear in µm.
double AddPass(const AnnModel& model, const PassInput& pass,
               AnnRollState* state);

// One member's K for a pass given the layer-1 pre-activation `z1` (H1) and
// the skip term q . x: the single-pass forward used by AddPass.
double AnnMemberK(const AnnNetwork& net, const Eigen::VectorXd& z1,
                  double linear);

// Versioned, whitespace-separated text form; Parse(Serialize(m)) == m
// exactly (doubles written with 17 significant digits). Labels are
// percent-encoded so that they hold no whitespace.
std::string SerializeAnnModel(const AnnModel& model);
StatusOr<AnnModel> ParseAnnModel(const std::string& text);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_MODEL_ANN_MODEL_H_
