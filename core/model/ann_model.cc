#include "core/model/ann_model.h"

#include <cmath>

#include "core/model/wear_law.h"

namespace rollwear {
namespace {

int LevelOf(const std::vector<std::string>& levels, const std::string& label) {
  for (size_t i = 0; i < levels.size(); ++i) {
    if (levels[i] == label) return static_cast<int>(i);
  }
  return -1;
}

bool AllFinite(const Eigen::MatrixXd& m) { return m.allFinite(); }

}  // namespace

AnnNetwork AnnNetwork::Zero(int inputs, int hidden1, int hidden2) {
  AnnNetwork n;
  n.a = Eigen::MatrixXd::Zero(hidden1, inputs);
  n.b1 = Eigen::VectorXd::Zero(hidden1);
  n.b = Eigen::MatrixXd::Zero(hidden2, hidden1);
  n.b2 = Eigen::VectorXd::Zero(hidden2);
  n.v = Eigen::VectorXd::Zero(hidden2);
  n.q = Eigen::VectorXd::Zero(inputs);
  n.c = 0;
  return n;
}

Eigen::VectorXd AnnNetwork::Flatten() const {
  Eigen::VectorXd t(num_parameters());
  Eigen::Index k = 0;
  auto put = [&t, &k](const auto& m) {
    t.segment(k, m.size()) =
        Eigen::Map<const Eigen::VectorXd>(m.data(), m.size());
    k += m.size();
  };
  put(a);
  put(b1);
  put(b);
  put(b2);
  put(v);
  put(q);
  t[k] = c;
  return t;
}

void AnnNetwork::Unflatten(const Eigen::VectorXd& t) {
  Eigen::Index k = 0;
  auto get = [&t, &k](auto& m) {
    Eigen::Map<Eigen::VectorXd>(m.data(), m.size()) = t.segment(k, m.size());
    k += m.size();
  };
  get(a);
  get(b1);
  get(b);
  get(b2);
  get(v);
  get(q);
  c = t[k];
}

Eigen::VectorXd AnnNetwork::WeightMask() const {
  AnnNetwork m = *this;
  m.a.setOnes();
  m.b1.setZero();
  m.b.setOnes();
  m.b2.setZero();
  m.v.setOnes();
  m.q.setOnes();
  m.c = 0;
  return m.Flatten();
}

const std::vector<std::string>& AnnPassContinuousNames() {
  static const std::vector<std::string> kNames = {
      "force_kn",  "width_mm",           "specific_force_kn_per_mm",
      "length_m",  "entry_thickness_mm", "exit_thickness_mm",
      "reduction", "contact_length_mm",  "temperature_c",
      "speed_mps", "lubrication",        "shift_mm"};
  return kNames;
}

void AnnRawPassFeatures(const PassInput& p, double diameter_mm,
                        double* out) {
  const double dh = p.entry_thickness_mm - p.exit_thickness_mm;
  out[0] = p.force_kn;
  out[1] = p.width_mm;
  out[2] = p.force_kn / p.width_mm;  // specific force F/w, kN/mm
  out[3] = p.length_m;
  out[4] = p.entry_thickness_mm;
  out[5] = p.exit_thickness_mm;
  out[6] = dh / p.entry_thickness_mm;        // reduction
  out[7] = std::sqrt(diameter_mm / 2 * dh);  // contact length lc, mm
  out[8] = p.temperature_c;
  out[9] = p.speed_mps;
  out[10] = p.lubrication ? 1.0 : 0.0;
  out[11] = p.shift_mm;
}

std::vector<std::string> AnnModel::InputNames() const {
  std::vector<std::string> names;
  for (const std::string& p : positions) names.push_back("pos:" + p);
  for (const std::string& r : roll_types) names.push_back("roll_type:" + r);
  names.push_back("hardness_hb");
  names.push_back("diameter_mm");
  for (const std::string& g : grades) names.push_back("grade:" + g);
  for (const std::string& n : AnnPassContinuousNames()) names.push_back(n);
  names.push_back("wear_so_far_um");
  return names;
}

int AnnModel::PositionLevel(const std::string& label) const {
  return LevelOf(positions, label);
}
int AnnModel::RollTypeLevel(const std::string& label) const {
  return LevelOf(roll_types, label);
}
int AnnModel::GradeLevel(const std::string& label) const {
  return LevelOf(grades, label);
}

Eigen::VectorXd AnnModel::EncodeStatic(int position, int roll_type,
                                       double hardness_hb,
                                       double diameter_mm) const {
  const int np = static_cast<int>(positions.size());
  const int nr = static_cast<int>(roll_types.size());
  Eigen::VectorXd s = Eigen::VectorXd::Zero(num_static());
  if (position >= 0 && position < np) s[position] = 1;
  if (roll_type >= 0 && roll_type < nr) s[np + roll_type] = 1;
  const int h = np + nr;
  // Not recorded (a real export): the training mean, i.e. no information.
  s[h] = std::isnan(hardness_hb) ? 0.0 : (hardness_hb - input_mean[h]) / input_sd[h];
  s[h + 1] = (diameter_mm - input_mean[h + 1]) / input_sd[h + 1];
  return s;
}

void AnnModel::EncodePass(const PassInput& pass, double diameter_mm,
                          double* out) const {
  const int ns = static_cast<int>(grades.size());
  const int offset = num_static();
  for (int g = 0; g < ns; ++g) out[g] = 0;
  const int grade = GradeLevel(pass.grade);
  if (grade >= 0) out[grade] = 1;
  double raw[kAnnNumPassContinuous];
  AnnRawPassFeatures(pass, diameter_mm, raw);
  for (int j = 0; j < kAnnNumPassContinuous; ++j) {
    const int col = offset + ns + j;
    out[ns + j] = (raw[j] - input_mean[col]) / input_sd[col];
  }
}

Status AnnModel::Validate() const {
  const int d = num_inputs();
  if (hidden1 < 1 || hidden2 < 1) {
    return Status::InvalidArgument("ann model: hidden layers must be >= 1");
  }
  if (input_mean.size() != d || input_sd.size() != d) {
    return Status::InvalidArgument("ann model: input scaling has size " +
                                   std::to_string(input_mean.size()) +
                                   ", expected " + std::to_string(d));
  }
  if (!input_mean.allFinite() || !input_sd.allFinite() ||
      (input_sd.array() <= 0).any()) {
    return Status::InvalidArgument(
        "ann model: input scaling must be finite with sd > 0");
  }
  for (const auto* labels : {&positions, &roll_types, &grades}) {
    for (const std::string& l : *labels) {
      if (l.empty()) return Status::InvalidArgument("ann model: empty label");
    }
  }
  if (members.empty()) {
    return Status::InvalidArgument("ann model: no ensemble member");
  }
  for (size_t m = 0; m < members.size(); ++m) {
    const AnnNetwork& n = members[m];
    const bool shape_ok = n.a.rows() == hidden1 && n.a.cols() == d &&
                          n.b1.size() == hidden1 && n.b.rows() == hidden2 &&
                          n.b.cols() == hidden1 && n.b2.size() == hidden2 &&
                          n.v.size() == hidden2 && n.q.size() == d;
    if (!shape_ok) {
      return Status::InvalidArgument("ann model: member " + std::to_string(m) +
                                     " has the wrong shape");
    }
    if (!AllFinite(n.a) || !n.b1.allFinite() || !AllFinite(n.b) ||
        !n.b2.allFinite() || !n.v.allFinite() || !n.q.allFinite() ||
        !std::isfinite(n.c)) {
      return Status::InvalidArgument("ann model: member " + std::to_string(m) +
                                     " has non-finite weights");
    }
  }
  return Status::Ok();
}

double AnnMemberK(const AnnNetwork& net, const Eigen::VectorXd& z1,
                  double linear) {
  // h1 = selu(z1); h2 = sigmoid(B h1 + b2); K = exp(v . h2 + q . x + c).
  Eigen::VectorXd h1 = z1;
  AnnSelu(&h1);
  Eigen::VectorXd h2 = net.b2;
  h2.noalias() += net.b * h1;
  AnnSigmoid(&h2);
  return std::exp(net.c + linear + net.v.dot(h2));
}

AnnRollState MountRoll(const AnnModel& model, const std::string& position_label,
                       const std::string& roll_type, double diameter_mm,
                       double hardness_hb) {
  AnnRollState s;
  s.position = model.PositionLevel(position_label);
  s.roll_type = model.RollTypeLevel(roll_type);
  s.diameter_mm = diameter_mm;
  s.hardness_hb = hardness_hb;
  s.member_wear_um.assign(model.members.size(), 0.0);
  const Eigen::VectorXd x =
      model.EncodeStatic(s.position, s.roll_type, hardness_hb, diameter_mm);
  for (const AnnNetwork& n : model.members) {
    Eigen::VectorXd part = n.b1;
    part.noalias() += n.a.leftCols(model.num_static()) * x;
    s.static_part.push_back(std::move(part));
    s.static_linear.push_back(n.q.head(model.num_static()).dot(x));
  }
  return s;
}

double AddPass(const AnnModel& model, const PassInput& pass,
               AnnRollState* state) {
  const int ns = model.num_static();
  const int np = model.num_pass();
  Eigen::VectorXd p(np);
  model.EncodePass(pass, state->diameter_mm, p.data());
  const PassLoadInput in{pass.force_kn,          pass.width_mm,
                         pass.length_m,          pass.entry_thickness_mm,
                         pass.exit_thickness_mm, state->diameter_mm,
                         state->hardness_hb};
  const double load = BaseLoad(WearLaw::kWang, in);
  double total = 0;
  for (size_t m = 0; m < model.members.size(); ++m) {
    const AnnNetwork& n = model.members[m];
    const double u = model.EncodeState(state->member_wear_um[m]);
    Eigen::VectorXd z1 = state->static_part[m];
    z1.noalias() += n.a.middleCols(ns, np) * p;
    z1 += n.a.col(model.state_column()) * u;
    const double linear = state->static_linear[m] + n.q.segment(ns, np).dot(p) +
                          n.q[model.state_column()] * u;
    state->member_wear_um[m] += AnnMemberK(n, z1, linear) * load;
    total += state->member_wear_um[m];
  }
  const double mean = total / static_cast<double>(model.members.size());
  const double increment = mean - state->wear_um;
  state->wear_um = mean;
  state->coils += 1;
  state->rolled_length_m += pass.length_m;
  return increment;
}

}  // namespace rollwear
