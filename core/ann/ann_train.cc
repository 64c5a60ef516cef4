#include "core/ann/ann_train.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>

#include "core/ann/ann_bptt.h"
#include "core/base/parallel.h"
#include "core/base/random.h"

namespace rollwear {
namespace {

// Member seeds: SplitMix64 (random.h) of the seed and the member.
uint64_t MemberSeed(uint64_t seed, int member) {
  return SplitMix64(SplitMix64(seed) ^ static_cast<uint64_t>(member + 1));
}

// Eq. 9 weights 1 / (P n_p) of the sequences `seqs`, times `scale`.
std::vector<double> PaperWeights(const AnnInputs& in,
                                 const std::vector<int>& seqs, double scale) {
  std::map<int, int> n_p;
  for (int s : seqs) ++n_p[in.sequences[s].position];
  std::vector<double> w;
  w.reserve(seqs.size());
  for (int s : seqs) {
    w.push_back(scale / (static_cast<double>(n_p.size()) *
                         n_p[in.sequences[s].position]));
  }
  return w;
}

struct MemberOutcome {
  AnnNetwork net;
  AnnMemberReport report;
};

MemberOutcome TrainMember(const AnnModel& model, const AnnInputs& in,
                          const std::vector<int>& train,
                          const AnnTrainingOptions& o, int member) {
  const auto start = std::chrono::steady_clock::now();
  MemberOutcome out;
  const uint64_t seed = MemberSeed(o.seed, member);
  out.report.seed = seed;
  Random rng(seed);

  // Held-out campaigns for early stopping (whole campaigns, seeded).
  std::vector<int> campaigns;
  for (int s : train) campaigns.push_back(in.sequences[s].campaign);
  std::sort(campaigns.begin(), campaigns.end());
  campaigns.erase(std::unique(campaigns.begin(), campaigns.end()),
                  campaigns.end());
  rng.Shuffle(&campaigns);
  // At least one campaign on each side (TrainAnn checks there are >= 2).
  const size_t n_hold = std::clamp<size_t>(
      static_cast<size_t>(std::lround(o.holdout_fraction * campaigns.size())),
      1, campaigns.size() - 1);
  std::vector<bool> held(
      *std::max_element(campaigns.begin(), campaigns.end()) + 1, false);
  for (size_t i = 0; i < n_hold; ++i) held[campaigns[i]] = true;
  std::vector<int> fit, hold;
  for (int s : train) {
    (held[in.sequences[s].campaign] ? hold : fit).push_back(s);
  }
  out.report.n_fit = static_cast<int>(fit.size());
  out.report.n_holdout = static_cast<int>(hold.size());

  // Scale s_m of the measurements and the constant-K start log(sum m/sum L).
  double sum_m = 0, sum_m2 = 0, sum_load = 0;
  for (int s : fit) {
    const AnnSequence& q = in.sequences[s];
    sum_m += q.measured_um;
    sum_m2 += q.measured_um * q.measured_um;
    sum_load += in.load.segment(q.begin, q.end - q.begin).sum();
  }
  const double nf = static_cast<double>(fit.size());
  const double var_m = std::max(sum_m2 / nf - (sum_m / nf) * (sum_m / nf), 1.0);
  const double log_k0 =
      std::log(std::max(sum_m, 1e-9) / std::max(sum_load, 1e-12));
  // Eq. 9 weights over the fitted set, scaled to mean 1 per observation
  // (N / (P n_p)) and by 1 / s_m^2; divided by the batch size per step.
  const std::vector<double> w_fit = PaperWeights(in, fit, nf / var_m);
  std::vector<double> w_of(in.sequences.size(), 0.0);
  for (size_t k = 0; k < fit.size(); ++k) w_of[fit[k]] = w_fit[k];

  AnnNetwork net = InitialAnnNetwork(model, seed, log_k0);
  Eigen::VectorXd theta = net.Flatten();
  const Eigen::VectorXd mask = net.WeightMask();
  Eigen::VectorXd m1 = Eigen::VectorXd::Zero(theta.size());
  Eigen::VectorXd m2 = Eigen::VectorXd::Zero(theta.size());
  double b1t = 1, b2t = 1;

  AnnNetwork best = net;
  double best_cost = std::numeric_limits<double>::infinity();
  double best_gap = 0;
  AnnNetwork grad;
  std::vector<int> order = fit;
  std::vector<int> batch;
  std::vector<double> batch_w;
  std::vector<double> pred(hold.size());
  std::vector<int> hold_pos(hold.size());
  std::vector<double> hold_meas(hold.size());
  for (size_t k = 0; k < hold.size(); ++k) {
    hold_pos[k] = in.sequences[hold[k]].position;
    hold_meas[k] = in.sequences[hold[k]].measured_um;
  }
  AnnWorkspace ws;
  int epoch = 0;
  for (epoch = 1; epoch <= o.max_epochs; ++epoch) {
    rng.Shuffle(&order);
    for (size_t b0 = 0; b0 < order.size(); b0 += o.batch_size) {
      const size_t b1 = std::min(order.size(), b0 + o.batch_size);
      batch.assign(order.begin() + b0, order.begin() + b1);
      batch_w.clear();
      for (int s : batch) batch_w.push_back(w_of[s] / (b1 - b0));
      AnnObjective(model, net, in, batch, batch_w, &grad);
      if (!o.linear_skip) grad.q.setZero();  // q stays 0
      const Eigen::VectorXd g = grad.Flatten();
      m1 = o.adam_beta1 * m1 + (1 - o.adam_beta1) * g;
      m2 = o.adam_beta2 * m2 + (1 - o.adam_beta2) * g.cwiseProduct(g);
      b1t *= o.adam_beta1;
      b2t *= o.adam_beta2;
      const Eigen::ArrayXd step =
          (m1.array() / (1 - b1t)) /
          ((m2.array() / (1 - b2t)).sqrt() + o.adam_epsilon);
      theta.array() -= o.learning_rate *
                       (step + o.weight_decay * mask.array() * theta.array());
      net.Unflatten(theta);
    }
    // Early stopping on the held-out campaigns (Eq. 9 cost).
    double abs_sum = 0;
    for (size_t k = 0; k < hold.size(); ++k) {
      pred[k] = AnnForward(model, net, in, in.sequences[hold[k]], &ws);
      abs_sum += std::abs(pred[k] - hold_meas[k]);
    }
    const double cost = PaperCost(hold_pos, hold_meas, pred);
    if (!std::isfinite(cost)) break;
    if (!o.early_stopping) {
      best_cost = cost;
      best_gap = abs_sum / std::max<size_t>(hold.size(), 1);
      best = net;
      out.report.best_epoch = epoch;
    } else if (cost < best_cost) {
      best_cost = cost;
      best_gap = abs_sum / std::max<size_t>(hold.size(), 1);
      best = net;
      out.report.best_epoch = epoch;
    } else if (epoch - out.report.best_epoch >= o.patience) {
      break;
    }
  }
  out.report.epochs = std::min(epoch, o.max_epochs);
  out.report.holdout_cost = best_cost;
  out.report.holdout_gap_um = best_gap;
  out.net = std::move(best);
  out.report.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  return out;
}

}  // namespace

bool AnnTrainingOptions::IsValid(std::string* error) const {
  auto fail = [error](const char* m) {
    *error = m;
    return false;
  };
  if (hidden1 < 1 || hidden2 < 1) return fail("hidden layers need >= 1 neuron");
  if (members < 1 || members > 1000)
    return fail("members must be in [1, 1000]");
  if (!(holdout_fraction > 0 && holdout_fraction < 1)) {
    return fail("holdout_fraction must be in (0, 1)");
  }
  if (batch_size < 1) return fail("batch_size must be >= 1");
  if (max_epochs < 1 || patience < 1) {
    return fail("max_epochs and patience must be >= 1");
  }
  if (!(learning_rate > 0) || !(weight_decay >= 0)) {
    return fail("learning_rate must be > 0 and weight_decay >= 0");
  }
  if (!(adam_beta1 >= 0 && adam_beta1 < 1 && adam_beta2 >= 0 &&
        adam_beta2 < 1 && adam_epsilon > 0)) {
    return fail("Adam needs 0 <= beta < 1 and epsilon > 0");
  }
  if (threads < 1) return fail("threads must be >= 1");
  return true;
}

AnnNetwork InitialAnnNetwork(const AnnModel& model, uint64_t seed,
                             double log_k0) {
  Random rng(SplitMix64(seed ^ 0x5eedULL));
  const int d = model.num_inputs();
  AnnNetwork n = AnnNetwork::Zero(d, model.hidden1, model.hidden2);
  const double sd_a = 1 / std::sqrt(static_cast<double>(d));  // LeCun
  for (Eigen::Index i = 0; i < n.a.size(); ++i)
    n.a.data()[i] = sd_a * rng.Normal();
  const double sd_b =
      std::sqrt(2.0 / (model.hidden1 + model.hidden2));  // Glorot
  for (Eigen::Index i = 0; i < n.b.size(); ++i)
    n.b.data()[i] = sd_b * rng.Normal();
  const double sd_v = 0.1 / std::sqrt(static_cast<double>(model.hidden2));
  for (Eigen::Index i = 0; i < n.v.size(); ++i) n.v[i] = sd_v * rng.Normal();
  // sigmoid(0) = 1/2: o = c + v.h2 ~ c + sum(v)/2 = log_k0 at the start.
  n.c = log_k0 - 0.5 * n.v.sum();
  return n;
}

StatusOr<AnnTrainingResult> TrainAnn(const AnnModel& skeleton,
                                     const AnnInputs& inputs,
                                     const std::vector<int>& train,
                                     const AnnTrainingOptions& options) {
  std::string error;
  if (!options.IsValid(&error)) return Status::InvalidArgument(error);
  if (skeleton.hidden1 != options.hidden1 ||
      skeleton.hidden2 != options.hidden2) {
    return Status::InvalidArgument(
        "ann: the skeleton's hidden sizes differ from the options'");
  }
  std::vector<int> campaigns;
  for (int s : train) {
    if (!inputs.sequences[s].measured) {
      return Status::InvalidArgument("ann: training sequence " +
                                     std::to_string(s) + " has no measurement");
    }
    campaigns.push_back(inputs.sequences[s].campaign);
  }
  std::sort(campaigns.begin(), campaigns.end());
  if (std::unique(campaigns.begin(), campaigns.end()) - campaigns.begin() < 2) {
    return Status::FailedPrecondition(
        "ann: training needs at least 2 measured campaigns (one is held out "
        "for early stopping)");
  }
  const auto start = std::chrono::steady_clock::now();
  std::vector<MemberOutcome> outcomes(options.members);
  ParallelFor(options.members, options.threads, [&](int m) {
    outcomes[m] = TrainMember(skeleton, inputs, train, options, m);
  });

  AnnTrainingResult r;
  r.model = skeleton;
  for (int m = 0; m < options.members; ++m) {
    r.all_members.push_back(outcomes[m].net);
    r.members.push_back(outcomes[m].report);
    if (outcomes[m].report.holdout_cost <
        outcomes[r.best_member].report.holdout_cost) {
      r.best_member = m;
    }
  }
  if (!std::isfinite(r.members[r.best_member].holdout_cost)) {
    return Status::NumericalFailure(
        "ann: every member diverged (non-finite holdout cost)");
  }
  if (options.ensemble == AnnEnsembleMode::kMean) {
    for (int m = 0; m < options.members; ++m) {
      if (std::isfinite(r.members[m].holdout_cost)) {
        r.model.members.push_back(r.all_members[m]);
      }
    }
  } else {
    r.model.members.push_back(r.all_members[r.best_member]);
  }
  r.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  return r;
}

}  // namespace rollwear
