#pragma once
#include <torch/torch.h>

#include <vector>

#include "methods/common/stochastic_classifier.h"

namespace fscil {

// PSPC weights: U_i = mean over probes of |z_hat^(n)_i - z_hat^(0)_i|^2 (on unit-length
// embeddings when `normalised`), and alpha_i = softmax(-beta U_i) over the samples of each
// class. probes: N_ps x N x D.
torch::Tensor probe_instability(const torch::Tensor& original, const torch::Tensor& probes, bool normalised);
torch::Tensor stability_weights(const torch::Tensor& instability, const torch::Tensor& labels, double beta);

// How many support samples a class's weights effectively use, 1 / sum_i alpha_i^2 (K for equal
// weights, 1 for one-hot), averaged over the classes of `labels`.
double effective_shots(const torch::Tensor& weights, const torch::Tensor& labels);

// Calibrated prototypes: per class, sum_i alpha_i * zbar_i, with zbar_i the mean of sample i's
// embedding over the original and its probes (`mean_of_views`) or its original embedding.
torch::Tensor calibrated_prototypes(const torch::Tensor& original, const torch::Tensor& probes,
                                    const torch::Tensor& weights, const torch::Tensor& labels,
                                    const std::vector<std::int64_t>& classes, bool mean_of_views);

// PSPC's incremental loss with sampled (stochastic) prototypes: L_new, cross-entropy of the
// support embeddings over the new classes' rows [old_classes, seen) only, plus L_old,
// cross-entropy of the stored old-class means over the old classes' rows [0, old_classes) only.
torch::Tensor new_and_old_loss(StochasticClassifier& classifier, const torch::Tensor& support_embeddings,
                               const torch::Tensor& support_labels, const torch::Tensor& old_means,
                               std::int64_t old_classes, std::int64_t seen);

}  // namespace fscil
