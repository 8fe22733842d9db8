#include "methods/cop_fscil/context_probe.h"

#include <algorithm>

#include "methods/common/mixing.h"

namespace fscil {

namespace {

double uniform(double range, std::mt19937_64& generator) {
  return range > 0 ? std::uniform_real_distribution<double>(-range, range)(generator) : 0.0;
}

// Shifts along time by `shift` frames, repeating the edge frame into the vacated ones.
torch::Tensor padded_shift(const torch::Tensor& sample, std::int64_t shift) {
  if (shift == 0) return sample;
  const std::int64_t frames = sample.size(-1);
  const std::int64_t magnitude = std::min(std::abs(shift), frames);
  using torch::indexing::Slice;
  if (shift > 0) {
    const torch::Tensor edge = sample.index({"...", Slice(0, 1)}).expand({-1, -1, magnitude});
    return torch::cat({edge, sample.index({"...", Slice(0, frames - magnitude)})}, -1);
  }
  const torch::Tensor edge = sample.index({"...", Slice(frames - 1, frames)}).expand({-1, -1, magnitude});
  return torch::cat({sample.index({"...", Slice(magnitude, frames)}), edge}, -1);
}

}  // namespace

torch::Tensor random_view(const torch::Tensor& features, const ViewRanges& ranges, std::mt19937_64& generator) {
  const std::int64_t n = features.size(0), channels = features.size(1), mels = features.size(2),
                     frames = features.size(3);
  const auto max_shift = static_cast<std::int64_t>(ranges.max_shift_fraction * static_cast<double>(frames));
  const torch::Tensor tilt_profile =
      mels > 1 ? torch::linspace(-1.0, 1.0, mels, features.options()).view({1, mels, 1}) : torch::zeros({1, 1, 1});
  std::normal_distribution<double> unit_normal(0.0, 1.0);
  std::vector<torch::Tensor> views;
  for (std::int64_t i = 0; i < n; ++i) {
    const torch::Tensor sample = features[i];
    const double spread = sample.std().item<double>();
    torch::Tensor offset = torch::full({channels, 1, 1}, uniform(ranges.global_bias, generator) * spread,
                                       features.options());
    for (std::int64_t c = 0; c < channels; ++c) offset[c] += uniform(ranges.channel_bias, generator) * spread;
    const double tilt = uniform(ranges.tilt, generator) * spread;
    // Noise from the run's generator (not torch's), so a view depends only on the seed.
    torch::Tensor noise = torch::empty_like(sample);
    auto values = noise.accessor<float, 3>();
    for (std::int64_t c = 0; c < channels; ++c) {
      for (std::int64_t f = 0; f < mels; ++f) {
        for (std::int64_t t = 0; t < frames; ++t) {
          values[c][f][t] = static_cast<float>(ranges.noise * spread * unit_normal(generator));
        }
      }
    }
    const std::int64_t shift =
        max_shift > 0 ? std::uniform_int_distribution<std::int64_t>(-max_shift, max_shift)(generator) : 0;
    views.push_back(padded_shift(sample + offset + tilt * tilt_profile + noise, shift));
  }
  return torch::stack(views);
}

torch::Tensor channel_statistics(const torch::Tensor& features) {
  const torch::Tensor flat = features.flatten(2);
  return torch::cat({flat.mean(2), flat.std(2)}, 1);
}

void ContextStatisticBank::push(const torch::Tensor& statistics) {
  const torch::Tensor rows = statistics.detach().clone();
  for (std::int64_t i = 0; i < rows.size(0); ++i) {
    entries_.push_back(rows[i]);
    if (entries_.size() > capacity_) entries_.pop_front();
  }
}

torch::Tensor ContextStatisticBank::farthest_from(const torch::Tensor& statistics) const {
  TORCH_CHECK(!entries_.empty(), "the context statistic bank is empty");
  const torch::Tensor all = torch::stack(std::vector<torch::Tensor>(entries_.begin(), entries_.end()));
  return all[(all - statistics.detach()).pow(2).sum(1).argmax().item<std::int64_t>()];
}

torch::Tensor ContextStatisticBank::random_entry(std::mt19937_64& generator) const {
  TORCH_CHECK(!entries_.empty(), "the context statistic bank is empty");
  return entries_[std::uniform_int_distribution<std::size_t>(0, entries_.size() - 1)(generator)];
}

torch::Tensor transfer_statistics(const torch::Tensor& features, const ContextStatisticBank& bank,
                                  ReferenceChoice choice, double alpha, std::mt19937_64& generator) {
  const std::int64_t channels = features.size(1);
  const torch::Tensor own = channel_statistics(features);
  std::vector<torch::Tensor> outputs;
  for (std::int64_t i = 0; i < features.size(0); ++i) {
    torch::Tensor reference;
    if (bank.size() == 0) {
      reference = own[std::uniform_int_distribution<std::int64_t>(0, features.size(0) - 1)(generator)];
    } else {
      reference = choice == ReferenceChoice::farthest ? bank.farthest_from(own[i]) : bank.random_entry(generator);
    }
    const double lambda = sample_beta(alpha, alpha, generator);
    const torch::Tensor mixed = lambda * own[i] + (1 - lambda) * reference;
    const auto shape = std::vector<std::int64_t>{channels, 1, 1};
    const torch::Tensor mean = own[i].narrow(0, 0, channels).view(shape);
    const torch::Tensor spread = own[i].narrow(0, channels, channels).view(shape).clamp_min(1e-6);
    outputs.push_back(mixed.narrow(0, channels, channels).view(shape) * (features[i] - mean) / spread +
                      mixed.narrow(0, 0, channels).view(shape));
  }
  return torch::stack(outputs);
}

}  // namespace fscil
