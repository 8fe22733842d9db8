#pragma once
#include <torch/torch.h>

#include <random>

namespace fscil {

// Where one CutMix pastes its box and which sample each box comes from: drawn once per batch,
// applied wherever CutMix acts (on the input, or after the encoder's input norm as PITS-SC's
// released code does).
struct CutMixPlan {
  std::int64_t top = 0, bottom = 0, left = 0, right = 0;  // the box, in Mel bins and frames
  torch::Tensor partners;                                 // N, the sample each box is taken from
  double kept_fraction = 1.0;                             // area of each sample left as it was

  // `maps` (N x C x F x T, the plan's batch) with the box pasted from each partner.
  torch::Tensor apply(const torch::Tensor& maps) const;
};

// lambda ~ Beta(alpha, alpha), a box of area (1 - lambda) of F x T at a uniform centre
// (clipped at the edges), partners a permutation of the batch.
CutMixPlan plan_cutmix(std::int64_t batch, std::int64_t height, std::int64_t width, double alpha,
                       std::mt19937_64& generator);

}  // namespace fscil
