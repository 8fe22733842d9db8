#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <random>
#include <vector>

namespace fscil {

// One epoch's mini-batches: the indices 0..samples-1 shuffled with `generator` (one shuffle_with
// of the identity order), cut into consecutive batches of `batch_size`, the last one shorter.
std::vector<torch::Tensor> shuffled_batches(std::int64_t samples, std::int64_t batch_size, std::mt19937_64& generator);

}  // namespace fscil
