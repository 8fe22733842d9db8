#pragma once
#include <torch/torch.h>

#include <random>

namespace fscil {

// A SpecAugment-style view of N x C x n_mels x frames log-Mel inputs: per sample one band of
// time frames (width uniform in [0, time_fraction * frames]) and one band of Mel bins (width
// uniform in [0, mel_fraction * n_mels]) set to the sample's mean; all channels share the bands.
torch::Tensor masked_view(const torch::Tensor& features, double time_fraction, double mel_fraction,
                          std::mt19937_64& generator);

}  // namespace fscil
