#pragma once
#include <torch/torch.h>

#include <random>

namespace fscil {

// A Beta(a, b) draw from the run's generator (as X / (X + Y), X ~ Gamma(a), Y ~ Gamma(b)).
double sample_beta(double a, double b, std::mt19937_64& generator);

struct CutMixBatch {
  torch::Tensor features;        // each sample with a box pasted from its partner
  torch::Tensor partner_labels;  // labels of the partners
  double kept_fraction = 1.0;    // area of each sample left as it was (the effective lambda)
};

// CutMix on N x C x F x T log-Mel batches: lambda ~ Beta(alpha, alpha), one box of area
// (1 - lambda) of F x T at a uniform centre (clipped at the edges) pasted from a permuted batch.
CutMixBatch cutmix(const torch::Tensor& features, const torch::Tensor& labels, double alpha,
                   std::mt19937_64& generator);

}  // namespace fscil
