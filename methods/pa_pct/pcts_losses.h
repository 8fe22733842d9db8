#pragma once
#include <torch/torch.h>

namespace fscil {

// The two terms PA-PCT's pseudo class-variable training (PCTS) adds to the cross-entropy in its
// pseudo-removal half-step, L = CE + 0.8 L_FS + 1.0 L_T (cgq2971-afk/FCIAC PCA.py L176 at
// 6ccc2082; the paper names neither: docs/compared_methods.md, PA-PCT).

// Forgetting separation (PCA.py L27-L30): mean over every (forgotten, retained) pair of
// ReLU(margin - ||p_f - p_r||_2). `forgotten` F x D, the forgotten classes' adapted prototypes as
// they were before the removal (a snapshot); `retained` R x D, the retained classes' now.
torch::Tensor forgetting_separation_loss(const torch::Tensor& forgotten, const torch::Tensor& retained,
                                         double margin = 0.5);

// Laplacian-topology distillation (PCA.py L6-L25): with W_ij = exp(-(1 - cos(p_i, p_j)) / sigma)
// over the R retained prototypes and L = diag(W 1) - W, ||L_before - L_now||_F^2 / R^2; `before`
// (the snapshot) and `now` are R x D, row i the same class in both.
torch::Tensor topology_distillation_loss(const torch::Tensor& before, const torch::Tensor& now, double sigma = 0.5);

}  // namespace fscil
