// The recurrent K-estimator: exact BPTT gradient, incremental == batch
// prediction, serialisation, determinism, and its honest comparison with
// classical calibration on simulated mills.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/model/aggregation.h"
#include "core/ann/ann_bptt.h"
#include "core/ann/ann_data.h"
#include "core/model/ann_model.h"
#include "core/ann/ann_study.h"
#include "core/ann/ann_train.h"
#include "core/sim/simulator.h"
#include "tests/core/test_size.h"

namespace rollwear {
namespace {

Simulation Mill(uint64_t seed, int campaigns,
                std::vector<std::string> effects = {}) {
  SimulatorOptions o;
  o.seed = seed;
  o.num_campaigns = campaigns;
  o.effects = std::move(effects);
  StatusOr<Simulation> s = Simulate(o);
  EXPECT_TRUE(s.ok()) << s.status().ToString();
  return std::move(s).value();
}

// A dataset encoded for the ANN with scaling fitted on all campaigns.
struct Encoded {
  Dataset data;
  WearStatistics stats;
  AnnModel model;  // no members
  AnnInputs inputs;
};

Encoded Encode(const Dataset& data, int hidden1 = 10, int hidden2 = 10) {
  Encoded e;
  e.data = data;
  const DatasetIndex index(e.data);
  e.stats = *Aggregate(e.data, index, WearLaw::kWang);
  std::vector<int> all(e.data.campaigns.size());
  for (size_t c = 0; c < all.size(); ++c) all[c] = static_cast<int>(c);
  StatusOr<AnnModel> m =
      FitAnnScaling(e.data, index, e.stats, all, hidden1, hidden2);
  EXPECT_TRUE(m.ok()) << m.status().ToString();
  e.model = *m;
  e.inputs = BuildAnnInputs(e.model, e.data, index, e.stats);
  return e;
}

double EmpiricalLogK(const Encoded& e) {
  double m = 0, l = 0;
  for (const AnnSequence& s : e.inputs.sequences) {
    if (!s.measured) continue;
    m += s.measured_um;
    l += e.inputs.load.segment(s.begin, s.end - s.begin).sum();
  }
  return std::log(m / l);
}

TEST(AnnGradientTest, AnnBpttMatchesCentralDifferencesThroughTheRecurrence) {
  const Encoded e = Encode(Mill(5, 6).data);
  AnnNetwork net = InitialAnnNetwork(e.model, 7, EmpiricalLogK(e));
  // Make every layer and the fed-back wear input matter: larger output
  // weights and a strong state column, so that K varies along a campaign.
  net.v *= 8;
  net.c -= 0.5 * net.v.sum() - 0.5 * (net.v.sum() / 8);
  net.a.col(e.model.state_column()) *= 3;
  // A non-zero skip path so that its gradient is checked too.
  for (Eigen::Index i = 0; i < net.q.size(); ++i) {
    net.q[i] = 0.02 * std::sin(1.0 + i);
  }
  std::vector<int> seqs;
  std::vector<double> weights;
  for (size_t s = 0; s < e.inputs.sequences.size() && seqs.size() < 6; ++s) {
    if (!e.inputs.sequences[s].measured) continue;
    seqs.push_back(static_cast<int>(s));
    weights.push_back(1e-4);  // (residual / 100 µm)^2
  }
  ASSERT_EQ(seqs.size(), 6u);
  AnnNetwork grad;
  const double j0 = AnnObjective(e.model, net, e.inputs, seqs, weights, &grad);
  ASSERT_TRUE(std::isfinite(j0));
  const Eigen::VectorXd g = grad.Flatten();
  const Eigen::VectorXd theta = net.Flatten();
  Eigen::VectorXd fd(theta.size());
  const double h = 1e-5;
  for (Eigen::Index i = 0; i < theta.size(); ++i) {
    AnnNetwork p = net, m = net;
    Eigen::VectorXd tp = theta, tm = theta;
    tp[i] += h;
    tm[i] -= h;
    p.Unflatten(tp);
    m.Unflatten(tm);
    fd[i] = (AnnObjective(e.model, p, e.inputs, seqs, weights, nullptr) -
             AnnObjective(e.model, m, e.inputs, seqs, weights, nullptr)) /
            (2 * h);
  }
  const double scale = g.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0);
  EXPECT_LT((fd - g).cwiseAbs().maxCoeff() / scale, 1e-6)
      << "max |fd - analytic| relative to max |gradient|";
  for (Eigen::Index i = 0; i < theta.size(); ++i) {
    if (std::abs(g[i]) > 1e-3 * scale) {
      EXPECT_NEAR(fd[i], g[i], 1e-5 * std::abs(g[i])) << "parameter " << i;
    }
  }

  // The check goes through the recurrence: without the fed-back wear,
  // dd/dc would equal d (K_i = exp(o_i) scales with exp(c)). Here it differs
  // by several per cent, and BPTT still matches finite differences.
  const AnnSequence& s0 = e.inputs.sequences[seqs[0]];
  const double d0 = PredictAnnMember(e.model, net, e.inputs, seqs[0]);
  AnnNetwork cp = net, cm = net;
  cp.c += h;
  cm.c -= h;
  const double dd_dc = (PredictAnnMember(e.model, cp, e.inputs, seqs[0]) -
                        PredictAnnMember(e.model, cm, e.inputs, seqs[0])) /
                       (2 * h);
  EXPECT_GT(std::abs(dd_dc - d0) / d0, 0.02);
  AnnNetwork one;
  AnnObjective(e.model, net, e.inputs, {seqs[0]}, {1.0}, &one);
  // dJ/dc = 2 (d - m) dd/dc for J = (d - m)^2.
  EXPECT_NEAR(one.c, 2 * (d0 - s0.measured_um) * dd_dc, 1e-6 * std::abs(one.c));
}

// A model with three random members for the prediction tests.
AnnModel RandomModel(const Encoded& e) {
  AnnModel m = e.model;
  for (uint64_t seed : {1, 2, 3}) {
    AnnNetwork n = InitialAnnNetwork(m, seed, EmpiricalLogK(e));
    n.v *= 5;
    n.a.col(m.state_column()) *= 2;
    for (Eigen::Index i = 0; i < n.q.size(); ++i) {
      n.q[i] = 0.01 * std::cos(static_cast<double>(seed + i));
    }
    m.members.push_back(n);
  }
  return m;
}

TEST(AnnModelTest, AnnIncrementalPredictionEqualsBatch) {
  const Encoded e = Encode(Mill(8, 10).data);
  const AnnModel model = RandomModel(e);
  ASSERT_TRUE(model.Validate().ok());
  const DatasetIndex index(e.data);
  std::vector<int> all(e.inputs.sequences.size());
  for (size_t s = 0; s < all.size(); ++s) all[s] = static_cast<int>(s);
  const std::vector<double> batch = PredictAnn(model, e.inputs, all);
  int checked = 0;
  for (size_t s = 0; s < all.size(); ++s) {
    const Observation& obs = e.stats.observations[s];
    const Mount& mount = e.data.mounts[obs.mount];
    AnnRollState state = MountRoll(model, e.stats.positions[obs.position],
                                   e.data.roll_types[mount.roll_type],
                                   mount.diameter_mm, mount.hardness_hb);
    double sum = 0;
    for (int pi : index.PassesOf(obs.campaign, mount.stand)) {
      const double inc =
          AddPass(model, PassInputOf(e.data, e.data.passes[pi]), &state);
      EXPECT_GT(inc, 0);
      sum += inc;
    }
    ASSERT_GT(batch[s], 0);
    EXPECT_NEAR(state.wear_um, batch[s], 1e-9 * batch[s]) << "sequence " << s;
    EXPECT_NEAR(sum, batch[s], 1e-9 * batch[s]);
    EXPECT_EQ(state.coils,
              e.inputs.sequences[s].end - e.inputs.sequences[s].begin);
    ++checked;
  }
  EXPECT_EQ(checked, static_cast<int>(e.stats.observations.size()));
  // An unknown roll type and grade are accepted (all-zero one-hot blocks).
  AnnRollState state = MountRoll(model, "F6/top", "NEW-TYPE", 700, 560);
  PassInput pass = PassInputOf(e.data, e.data.passes[0]);
  pass.grade = "NEW-GRADE";
  EXPECT_GT(AddPass(model, pass, &state), 0);
}

TEST(AnnModelTest, AnnLevelsWithoutTrainingDataAreUnknownLabels) {
  // A level that no training campaign shows would keep random initial
  // weights; it is left out of the model and encoded as an unknown label.
  const Dataset data = Mill(12, 10).data;
  const DatasetIndex index(data);
  const WearStatistics stats = *Aggregate(data, index, WearLaw::kWang);
  StatusOr<AnnModel> m = FitAnnScaling(data, index, stats, {0}, 10, 10);
  ASSERT_TRUE(m.ok()) << m.status().ToString();
  std::vector<bool> used(data.grades.size(), false);
  for (const Pass& p : data.passes) {
    if (p.campaign == 0) used[p.grade] = true;
  }
  int n_used = 0;
  for (size_t g = 0; g < used.size(); ++g) {
    n_used += used[g] ? 1 : 0;
    EXPECT_EQ(m->GradeLevel(data.grades[g]) >= 0, used[g]) << data.grades[g];
  }
  EXPECT_EQ(static_cast<int>(m->grades.size()), n_used);
  EXPECT_LT(n_used, static_cast<int>(data.grades.size()));
  const AnnInputs in = BuildAnnInputs(*m, data, index, stats);
  EXPECT_EQ(in.sequences.size(), stats.observations.size());
  EXPECT_TRUE(in.pass_input.allFinite());
}

TEST(AnnModelTest, AnnSerialisationRoundTripIsExact) {
  const Encoded e = Encode(Mill(9, 6).data, 4, 3);
  AnnModel model = RandomModel(e);
  model.roll_types.push_back("odd label %20 with spaces\tand tab");
  model.input_mean.conservativeResize(model.num_inputs());
  model.input_sd.conservativeResize(model.num_inputs());
  // Re-layout: insert the new one-hot column before hardness (zero scaling).
  const int col = model.num_static() - 3;
  for (int j = model.num_inputs() - 1; j > col; --j) {
    model.input_mean[j] = model.input_mean[j - 1];
    model.input_sd[j] = model.input_sd[j - 1];
  }
  model.input_mean[col] = 0;
  model.input_sd[col] = 1;
  for (AnnNetwork& n : model.members) {
    Eigen::MatrixXd a(n.a.rows(), n.a.cols() + 1);
    a << n.a.leftCols(col), Eigen::VectorXd::Constant(n.a.rows(), 1.0 / 3),
        n.a.rightCols(n.a.cols() - col);
    n.a = a;
    Eigen::VectorXd q(n.q.size() + 1);
    q << n.q.head(col), 0.25, n.q.tail(n.q.size() - col);
    n.q = q;
  }
  ASSERT_TRUE(model.Validate().ok()) << model.Validate().ToString();

  const std::string text = SerializeAnnModel(model);
  StatusOr<AnnModel> back = ParseAnnModel(text);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(back->positions, model.positions);
  EXPECT_EQ(back->roll_types, model.roll_types);
  EXPECT_EQ(back->grades, model.grades);
  EXPECT_EQ(back->hidden1, 4);
  EXPECT_EQ(back->hidden2, 3);
  EXPECT_TRUE((back->input_mean.array() == model.input_mean.array()).all());
  EXPECT_TRUE((back->input_sd.array() == model.input_sd.array()).all());
  ASSERT_EQ(back->members.size(), model.members.size());
  for (size_t m = 0; m < model.members.size(); ++m) {
    // Bitwise equality of every weight.
    EXPECT_TRUE((back->members[m].Flatten().array() ==
                 model.members[m].Flatten().array())
                    .all());
  }
  EXPECT_EQ(SerializeAnnModel(*back), text);
  EXPECT_LT(text.size(), 40000u);  // compact: a few hundred weights each

  // Damaged or foreign texts are rejected with a reason.
  StatusOr<AnnModel> v2 = ParseAnnModel("rollwear-ann-model 2\n" +
                                        text.substr(text.find('\n') + 1));
  ASSERT_FALSE(v2.ok());
  EXPECT_EQ(v2.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(v2.status().message().find("format version 2"), std::string::npos);
  StatusOr<AnnModel> cut = ParseAnnModel(text.substr(0, text.size() / 2));
  ASSERT_FALSE(cut.ok());
  EXPECT_NE(cut.status().message().find("token"), std::string::npos);
  EXPECT_FALSE(ParseAnnModel(text + " extra").ok());
  std::string nan_text = text;
  const size_t at = nan_text.find("\n c ") + 4;
  nan_text.replace(at, nan_text.find('\n', at) - at, "nan");
  EXPECT_FALSE(ParseAnnModel(nan_text).ok());
}

TEST(AnnTrainingTest, AnnTrainingIsDeterministicForASeed) {
  const Simulation sim = Mill(21, 30);
  AnnComparisonOptions o;
  o.training.members = 2;
  o.training.max_epochs = 15;
  o.training.threads = 1;
  StatusOr<AnnComparison> a = CompareAnnWithClassical(sim.data, o);
  ASSERT_TRUE(a.ok()) << a.status().ToString();
  o.training.threads = 2;  // members in parallel: same result
  StatusOr<AnnComparison> b = CompareAnnWithClassical(sim.data, o);
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(SerializeAnnModel(a->model), SerializeAnnModel(b->model));
  EXPECT_EQ(a->ann_val.gap_um, b->ann_val.gap_um);
  o.training.seed = 2;
  StatusOr<AnnComparison> c = CompareAnnWithClassical(sim.data, o);
  ASSERT_TRUE(c.ok());
  EXPECT_NE(SerializeAnnModel(a->model), SerializeAnnModel(c->model));
  // Same split as calibrate: same classical figures whatever the ANN seed.
  EXPECT_EQ(a->classical_val.gap_um, c->classical_val.gap_um);
  EXPECT_EQ(a->n_train + a->n_val,
            static_cast<int>(sim.data.measurements.size()));
}

// The comparison on paper-size simulated mills (395 campaigns, 2/3-1/3
// split as `calibrate`, ANN ensemble of 3 members). Over simulator seeds 1-6
// (docs/ann.md) the ANN/classical validation-gap ratio was 1.01-1.05 without
// a concealed effect and 0.92-0.96 with campaign_growth; the member-to-
// member spread of the validation gap is about 0.3 µm (1.5 %). The bounds
// below sit about 3 sd of that spread away from the worst case seen.
// Under the sanitizers (test_size.h) the mill stays paper-size (the ANN
// needs its 1,052 training measurements) and the ensemble is one member,
// a third of the training: the same bounds hold for each of the three
// members alone (Release, seeds 31/32: ratios 1.005-1.050 without effect,
// 0.947-0.967 with growth, training gap below classical for each).
constexpr int kStudyMembers = test_size::FullOr(3, 1);

AnnComparison Compare(const Simulation& sim) {
  AnnComparisonOptions o;
  o.training.members = kStudyMembers;
  StatusOr<AnnComparison> c = CompareAnnWithClassical(sim.data, o);
  EXPECT_TRUE(c.ok()) << c.status().ToString();
  return std::move(c).value();
}

TEST(AnnStudyTest, AnnIsNotBetterThanClassicalWithoutAConcealedEffect) {
  // The truth is Wang's law with option-1 K: the classical model has the
  // right structure and 19 free parameters; the ANN can only add variance.
  const AnnComparison c = Compare(Mill(31, 395));
  RecordProperty("classical_val_um", std::to_string(c.classical_val.gap_um));
  RecordProperty("ann_val_um", std::to_string(c.ann_val.gap_um));
  EXPECT_GT(c.ann_val.gap_um, 0.97 * c.classical_val.gap_um);
  // ... but it is a working estimator, not a broken one.
  EXPECT_LT(c.ann_val.gap_um, 1.15 * c.classical_val.gap_um);
  EXPECT_EQ(c.members.size(), static_cast<size_t>(kStudyMembers));
  for (const AnnMemberFigures& f : c.members) {
    EXPECT_GE(f.training.best_epoch, 1);
    EXPECT_LE(f.training.best_epoch, f.training.epochs);
  }
}

TEST(AnnStudyTest, AnnBeatsClassicalUnderCampaignGrowth) {
  // The wear rate grows with the rolled length: K of a coil depends on the
  // roll's state, which the recurrence feeds back and option 1 lacks.
  const AnnComparison c = Compare(Mill(32, 395, {"campaign_growth"}));
  RecordProperty("classical_val_um", std::to_string(c.classical_val.gap_um));
  RecordProperty("ann_val_um", std::to_string(c.ann_val.gap_um));
  EXPECT_LT(c.ann_val.gap_um, 0.98 * c.classical_val.gap_um);
  EXPECT_LT(c.ann_train.gap_um, c.classical_train.gap_um);
}

}  // namespace
}  // namespace rollwear
