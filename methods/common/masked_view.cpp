#include "methods/common/masked_view.h"

#include <vector>

#include "core/random_draws.h"

namespace fscil {

namespace {

// Per sample a [start, start + width) band of `length` positions as an N x length bool mask.
torch::Tensor random_bands(std::int64_t n, std::int64_t length, double fraction, std::mt19937_64& generator) {
  const auto widest = static_cast<std::int64_t>(fraction * static_cast<double>(length));
  std::vector<std::int64_t> starts(static_cast<std::size_t>(n), 0), ends(static_cast<std::size_t>(n), 0);
  for (std::size_t i = 0; i < starts.size(); ++i) {
    const std::int64_t width = uniform_int(generator, 0, widest);
    starts[i] = uniform_int(generator, 0, length - width);
    ends[i] = starts[i] + width;
  }
  const torch::Tensor position = torch::arange(length, torch::kLong).view({1, length});
  return (position >= torch::tensor(starts).view({-1, 1})) & (position < torch::tensor(ends).view({-1, 1}));
}

}  // namespace

torch::Tensor masked_view(const torch::Tensor& features, double time_fraction, double mel_fraction,
                          std::mt19937_64& generator) {
  const std::int64_t n = features.size(0), mels = features.size(2), frames = features.size(3);
  const torch::Tensor time_band = random_bands(n, frames, time_fraction, generator).view({n, 1, 1, frames});
  const torch::Tensor mel_band = random_bands(n, mels, mel_fraction, generator).view({n, 1, mels, 1});
  const torch::Tensor mean = features.flatten(1).mean(1).view({n, 1, 1, 1}).expand(features.sizes());
  return torch::where(time_band | mel_band, mean, features);
}

}  // namespace fscil
