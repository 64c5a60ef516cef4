#include "core/ann/ann_bptt.h"

#include <cmath>

namespace rollwear {

double AnnForward(const AnnModel& model, const AnnNetwork& net,
                  const AnnInputs& inputs, const AnnSequence& seq,
                  AnnWorkspace* ws) {
  const int n = seq.end - seq.begin;
  const int ns = model.num_static();
  const int np = model.num_pass();
  ws->h1.resize(model.hidden1, n);
  ws->h2.resize(model.hidden2, n);
  ws->k.resize(n);
  ws->u.resize(n);
  // Pass-dependent part of layer 1 for all passes at once (one GEMM).
  ws->h1.noalias() =
      net.a.middleCols(ns, np) * inputs.pass_input.middleCols(seq.begin, n);
  ws->sp = net.b1;
  ws->sp.noalias() += net.a.leftCols(ns) * seq.static_input;
  // Skip path without the state term: q_p . p_i + q_s . s + c.
  ws->lin.noalias() = inputs.pass_input.middleCols(seq.begin, n).transpose() *
                      net.q.segment(ns, np);
  ws->lin.array() += net.q.head(ns).dot(seq.static_input) + net.c;
  const double qu = net.q[model.state_column()];
  const auto au = net.a.col(model.state_column());
  const double mu_w = model.input_mean[model.state_column()];
  const double sd_w = model.input_sd[model.state_column()];
  double wear = 0;
  for (int i = 0; i < n; ++i) {
    const double u = (wear - mu_w) / sd_w;
    ws->u[i] = u;
    auto h1 = ws->h1.col(i);
    h1 += ws->sp + au * u;
    AnnSelu(&h1);
    auto h2 = ws->h2.col(i);
    h2.noalias() = net.b * h1;
    h2 += net.b2;
    AnnSigmoid(&h2);
    const double k = std::exp(ws->lin[i] + qu * u + net.v.dot(h2));
    ws->k[i] = k;
    wear += k * inputs.load[seq.begin + i];
  }
  return wear;
}

void AnnBackward(const AnnModel& model, const AnnNetwork& net,
                 const AnnInputs& inputs, const AnnSequence& seq, double g_n,
                 AnnWorkspace* ws, AnnNetwork* grad) {
  const int n = seq.end - seq.begin;
  const int ns = model.num_static();
  const int np = model.num_pass();
  const int h1n = model.hidden1;
  const int h2n = model.hidden2;
  ws->gz1.resize(h1n, n);
  ws->gz2.resize(h2n, n);
  ws->go.resize(n);
  const auto au = net.a.col(model.state_column());
  const double sd_w = model.input_sd[model.state_column()];
  const double qu = net.q[model.state_column()];
  double g = g_n;  // dJ/dW_i, walking backwards
  for (int i = n - 1; i >= 0; --i) {
    const double go = g * inputs.load[seq.begin + i] * ws->k[i];
    ws->go[i] = go;
    auto gz2 = ws->gz2.col(i);
    const auto h2 = ws->h2.col(i);
    for (int j = 0; j < h2n; ++j) {
      gz2[j] = go * net.v[j] * h2[j] * (1 - h2[j]);
    }
    auto gz1 = ws->gz1.col(i);
    gz1.noalias() = net.b.transpose() * gz2;
    const auto h1 = ws->h1.col(i);
    for (int j = 0; j < h1n; ++j) {
      // selu'(z) = lambda (z > 0), lambda*alpha*exp(z) = h1 + lambda*alpha.
      gz1[j] *=
          h1[j] > 0 ? kAnnSeluLambda : h1[j] + kAnnSeluLambda * kAnnSeluAlpha;
    }
    g += (au.dot(gz1) + qu * go) / sd_w;
  }
  grad->a.middleCols(ns, np).noalias() +=
      ws->gz1 * inputs.pass_input.middleCols(seq.begin, n).transpose();
  const Eigen::VectorXd sum1 = ws->gz1.rowwise().sum();
  grad->b1 += sum1;
  grad->a.leftCols(ns).noalias() += sum1 * seq.static_input.transpose();
  grad->a.col(model.state_column()).noalias() += ws->gz1 * ws->u;
  grad->b.noalias() += ws->gz2 * ws->h1.transpose();
  grad->b2 += ws->gz2.rowwise().sum();
  grad->v.noalias() += ws->h2 * ws->go;
  grad->c += ws->go.sum();
  grad->q.segment(ns, np).noalias() +=
      inputs.pass_input.middleCols(seq.begin, n) * ws->go;
  grad->q.head(ns) += ws->go.sum() * seq.static_input;
  grad->q[model.state_column()] += ws->go.dot(ws->u);
}

double AnnObjective(const AnnModel& model, const AnnNetwork& net,
                    const AnnInputs& inputs, const std::vector<int>& seqs,
                    const std::vector<double>& weights, AnnNetwork* grad) {
  AnnWorkspace ws;
  if (grad != nullptr) {
    *grad = AnnNetwork::Zero(model.num_inputs(), model.hidden1, model.hidden2);
  }
  double j = 0;
  for (size_t k = 0; k < seqs.size(); ++k) {
    const AnnSequence& seq = inputs.sequences[seqs[k]];
    const double r = AnnForward(model, net, inputs, seq, &ws) - seq.measured_um;
    j += weights[k] * r * r;
    if (grad != nullptr) {
      AnnBackward(model, net, inputs, seq, 2 * weights[k] * r, &ws, grad);
    }
  }
  return j;
}

double PredictAnnMember(const AnnModel& model, const AnnNetwork& net,
                        const AnnInputs& inputs, int seq) {
  AnnWorkspace ws;
  return AnnForward(model, net, inputs, inputs.sequences[seq], &ws);
}

std::vector<double> PredictAnn(const AnnModel& model, const AnnInputs& inputs,
                               const std::vector<int>& seqs) {
  std::vector<double> out(seqs.size(), 0.0);
  AnnWorkspace ws;
  for (const AnnNetwork& net : model.members) {
    for (size_t k = 0; k < seqs.size(); ++k) {
      out[k] += AnnForward(model, net, inputs, inputs.sequences[seqs[k]], &ws);
    }
  }
  for (double& d : out) d /= static_cast<double>(model.members.size());
  return out;
}

}  // namespace rollwear
