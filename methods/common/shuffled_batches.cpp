#include "methods/common/shuffled_batches.h"

#include <algorithm>
#include <numeric>

#include "core/seeded_shuffle.h"

namespace fscil {

std::vector<torch::Tensor> shuffled_batches(std::int64_t samples, std::int64_t batch_size, std::mt19937_64& generator) {
  std::vector<std::int64_t> order(static_cast<std::size_t>(samples));
  std::iota(order.begin(), order.end(), 0);
  shuffle_with(order, generator);
  std::vector<torch::Tensor> batches;
  for (std::int64_t first = 0; first < samples; first += batch_size) {
    const std::int64_t size = std::min(batch_size, samples - first);
    batches.push_back(torch::tensor(std::vector<std::int64_t>(order.begin() + first, order.begin() + first + size)));
  }
  return batches;
}

}  // namespace fscil
