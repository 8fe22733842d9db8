#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <random>
#include <vector>

namespace fscil {

// OrCo's pseudo-targets: `count` random unit vectors of `dimension` moved apart by plain SGD on
// their spread loss (mean log-sum-exp of pairwise cosines), re-normalised after every step.
// Gradients are cleared every step (the reference lets them accumulate; ours, see docs).
torch::Tensor make_pseudo_targets(std::int64_t count, std::int64_t dimension, int steps, double learning_rate,
                                  std::mt19937_64& generator);

// Hungarian assignment of classes to free targets by the cosine of their mean projections
// (rows of `class_means`) to the targets: returns the target index of each class, all distinct,
// maximising the summed cosine.
std::vector<std::int64_t> assign_to_targets(const torch::Tensor& class_means, const torch::Tensor& targets,
                                            const std::vector<std::int64_t>& free_targets);

}  // namespace fscil
