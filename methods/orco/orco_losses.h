#pragma once
#include <torch/torch.h>

#include <random>

namespace fscil {

// Supervised contrastive loss (Khosla et al.) on L2-normalised `views` (N x V x D): every view
// is an anchor, its positives are the other views with the same label; anchors without a
// positive are left out. Temperature and base temperature are equal, so no extra factor.
torch::Tensor supervised_contrastive_loss(const torch::Tensor& views, const torch::Tensor& labels, double temperature);

// The spread of a set of directions: mean over rows of log sum_j exp(cos(x_i, x_j)), self
// included (OrCo's "simplex" loss at temperature 1). Lower means more spread out.
torch::Tensor spread_loss(const torch::Tensor& directions);

// OrCo's orthogonality loss on a batch: the spread of the normalised class means of
// `projections` together with the assigned targets of classes absent from the batch and every
// unassigned target. `target_labels` are the classes of `assigned_targets` rows.
torch::Tensor orthogonality_loss(const torch::Tensor& projections, const torch::Tensor& labels,
                                 const torch::Tensor& assigned_targets, const torch::Tensor& target_labels,
                                 const torch::Tensor& unassigned_targets);

// The same over the samples of classes >= `from_class` only (OrCo's sessions: the new samples);
// zero, without a graph, when the batch has none.
torch::Tensor orthogonality_loss_from(std::int64_t from_class, const torch::Tensor& projections,
                                      const torch::Tensor& labels, const torch::Tensor& assigned_targets,
                                      const torch::Tensor& target_labels, const torch::Tensor& unassigned_targets);

// OrCo's cross-entropy (the reference's pull_loss): the mean CE of the base samples (label <
// `novel_from`) and that of the others, each over all of `logits`' classes, weighted apart. A
// part without samples or with weight 0 adds nothing.
torch::Tensor split_cross_entropy(const torch::Tensor& logits, const torch::Tensor& labels, std::int64_t novel_from,
                                  double base_weight, double novel_weight);

struct PerturbedTargets {
  torch::Tensor views;   // count x 2 x D, unit rows
  torch::Tensor labels;  // count
};

// `count` targets drawn without replacement (cycled when there are fewer), each seen twice with
// its own uniform noise (U[0,1) - offset) * epsilon per coordinate, then re-normalised.
PerturbedTargets perturb_targets(const torch::Tensor& targets, const torch::Tensor& labels, std::int64_t count,
                                 double epsilon, double offset, std::mt19937_64& generator);

}  // namespace fscil
