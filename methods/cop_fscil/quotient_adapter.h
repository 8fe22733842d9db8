#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <string>

#include "metrics/model_cost.h"

namespace fscil {

// Householder reflections H(v) = I - 2 v v^T / v^T v applied to vectors, never formed as
// matrices. v: N x m x D (m reflections per sample), x: N x D.
// Q = H(v_m) ... H(v_1): apply_q applies H(v_1) first; apply_q_transpose undoes it.
torch::Tensor apply_q(const torch::Tensor& reflections, const torch::Tensor& x);
torch::Tensor apply_q_transpose(const torch::Tensor& reflections, const torch::Tensor& x);

struct QuotientAdapterOptions {
  std::int64_t dim = 256;
  std::int64_t reflections = 8;        // m
  std::int64_t invariant_dim = 192;    // d_inv = D - d_sen
  std::int64_t hidden = 0;             // g's hidden width; 0 = D
};

// PCQA, the probe-conditioned quotient adapter of CoP-FSCIL: an observation network
// g = Linear(D, H) - ReLU - Linear(H, m D) (H = D unless set) predicts m reflection vectors from
// the original sample's embedding z0; p = Q z splits into [p_inv; p_sen] and z_hat = Q^T [p_inv; 0].
class QuotientAdapterImpl : public torch::nn::Module {
 public:
  explicit QuotientAdapterImpl(const QuotientAdapterOptions& options);

  struct Projection {
    torch::Tensor invariant;  // p_inv, N x d_inv
    torch::Tensor quotient;   // z_hat, N x D
  };
  torch::Tensor reflections_of(const torch::Tensor& original);  // N x m x D
  // Projects z with the Q predicted from `original` (z0): its own embedding or a probe's.
  Projection project(const torch::Tensor& reflections, const torch::Tensor& z) const;
  torch::Tensor forward(const torch::Tensor& z) { return project(reflections_of(z), z).quotient; }

  const QuotientAdapterOptions& options() const { return options_; }
  // How far Q moves what it drops away from the fixed last D - d_inv coordinates: per sample
  // 1 - |E^T Q^T E|_F^2 / d_sen, E those coordinates' basis, averaged over the samples of
  // `originals` (N x D). 0 when PCQA drops fixed encoder channels, 1 when none of them.
  double dropped_share_off_fixed_channels(const torch::Tensor& originals);
  // Adds forward()'s cost for one embedding: the observation network, then Q and Q^T.
  void count_cost(ModelCost& cost, const std::string& name) const;

 private:
  QuotientAdapterOptions options_;
  torch::nn::Linear hidden_{nullptr}, output_{nullptr};
};
TORCH_MODULE(QuotientAdapter);

// What L_PIC compares (pic_space): the invariant coordinates as they are (raw, the paper's
// formula), those of the unit-length embedding (normalised: p_inv / |z|), or their direction
// (invariant: p_inv / |p_inv|). The classifier is a cosine, blind to z_hat's length, so raw and
// normalised can be lowered by shrinking p_inv, or by moving z's length into the dropped
// coordinates, rather than by making p_inv agree across probes; invariant cannot.
enum class PicSpace { raw, normalised, invariant };

// p_inv, the invariant coordinates of z (N x d_inv, from QuotientAdapterImpl::project), in `space`.
// Q keeps lengths, so p_inv / |z| is the p_inv of the unit-length z.
torch::Tensor pic_invariant(const torch::Tensor& invariant, const torch::Tensor& z, PicSpace space);

// L_PIC = mean over probes n of |p_inv^(0) - stopgrad(p_inv^(n))|^2 (mean over samples too).
// probe_invariants: N_cp x N x d_inv.
torch::Tensor probe_invariance_loss(const torch::Tensor& original_invariant, const torch::Tensor& probe_invariants);

}  // namespace fscil
