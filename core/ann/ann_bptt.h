// Forward pass and exact gradient of the recurrent K-estimator over one
// campaign's coils (backpropagation through time, Werbos 1990, "Backprop-
// agation through time: what it does and how to do it", Proc. IEEE 78(10)).
//
// Forward, for the passes i = 1..n of a sequence (ann_model.h):
//   z1_i = A_s s + A_p p_i + a_u u_{i-1} + b1,  u_{i-1} = (W_{i-1}-mu_W)/sd_W
//   h1_i = selu(z1_i),  h2_i = sigmoid(B h1_i + b2),
//   o_i = v.h2_i + q_s.s + q_p.p_i + q_u u_{i-1} + c
//   K_i = exp(o_i),  W_i = W_{i-1} + K_i L_i,  d = W_n
// Backward, with g_i = dJ/dW_i (total derivative, through all later passes)
// and g_n = dJ/dd:
//   go_i  = g_i L_i K_i                          (= dJ/do_i)
//   gz2_i = go_i v * h2_i * (1 - h2_i)
//   gz1_i = (B' gz2_i) * selu'(z1_i)
//   g_{i-1} = g_i + (a_u . gz1_i + q_u go_i) / sd_W
//                  (the recurrence: W_i depends on W_{i-1} directly and
//                   through K_i, via layer 1 and the skip path)
// and the weight gradients are sums over i of the outer products
//   dA_p += gz1_i p_i',  dA_s += gz1_i s',  da_u += gz1_i u_{i-1},
//   db1 += gz1_i, dB += gz2_i h1_i', db2 += gz2_i, dv += go_i h2_i, dc += go_i
//   dq_s += go_i s,  dq_p += go_i p_i,  dq_u += go_i u_{i-1}
// (accumulated as matrix products over the whole sequence).
//
// Thread-safety: reentrant; one AnnWorkspace per thread.
#ifndef ROLLWEAR_CORE_ANN_ANN_BPTT_H_
#define ROLLWEAR_CORE_ANN_ANN_BPTT_H_

#include <vector>

#include <Eigen/Core>

#include "core/ann/ann_data.h"
#include "core/model/ann_model.h"

namespace rollwear {

// Activations of one sequence kept for the backward pass.
struct AnnWorkspace {
  Eigen::MatrixXd h1;   // H1 x n (first the layer-1 pre-activation part)
  Eigen::MatrixXd h2;   // H2 x n
  Eigen::VectorXd k;    // n
  Eigen::VectorXd u;    // n, scaled state input before each pass
  Eigen::VectorXd sp;   // H1, A_s s + b1
  Eigen::VectorXd lin;  // n, q_p . p_i + q_s . s + c
  Eigen::MatrixXd gz1;  // H1 x n
  Eigen::MatrixXd gz2;  // H2 x n
  Eigen::VectorXd go;   // n
};

// Predicted wear d of sequence `seq`; fills `ws` for AnnBackward.
double AnnForward(const AnnModel& model, const AnnNetwork& net,
                  const AnnInputs& inputs, const AnnSequence& seq,
                  AnnWorkspace* ws);

// Adds g_n * dd/dtheta to `grad` (same shape as net), using the activations
// of the last AnnForward on the same sequence.
void AnnBackward(const AnnModel& model, const AnnNetwork& net,
                 const AnnInputs& inputs, const AnnSequence& seq, double g_n,
                 AnnWorkspace* ws, AnnNetwork* grad);

// J = sum_k weights[k] * (d_k - m_k)^2 over the measured sequences
// seqs[k]; with `grad` non-null it is set to dJ/dtheta.
double AnnObjective(const AnnModel& model, const AnnNetwork& net,
                    const AnnInputs& inputs, const std::vector<int>& seqs,
                    const std::vector<double>& weights, AnnNetwork* grad);

// Predicted centre wear of sequence `seq` by one member network.
double PredictAnnMember(const AnnModel& model, const AnnNetwork& net,
                        const AnnInputs& inputs, int seq);
// Ensemble-mean predicted wear of each sequence in `seqs`.
std::vector<double> PredictAnn(const AnnModel& model, const AnnInputs& inputs,
                               const std::vector<int>& seqs);

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_ANN_ANN_BPTT_H_
