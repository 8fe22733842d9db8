#include "methods/cop_fscil/context_probe.h"

#include <ATen/CPUGeneratorImpl.h>

#include <algorithm>
#include <vector>

#include "core/random_draws.h"

namespace fscil {

namespace {

// n draws of U(-range, range) as a float tensor (zeros when the range is 0).
torch::Tensor uniform_draws(std::int64_t n, double range, std::mt19937_64& generator) {
  std::vector<float> values(static_cast<std::size_t>(n), 0.0f);
  if (range > 0) {
    for (auto& value : values) value = static_cast<float>(uniform_real(generator, -range, range));
  }
  return torch::tensor(values);
}

// Shifts each sample along time by its own number of frames, repeating the edge frame into the
// vacated ones: output frame t reads input frame clamp(t - shift, 0, T - 1).
torch::Tensor padded_shift(const torch::Tensor& features, const std::vector<std::int64_t>& shifts) {
  const std::int64_t frames = features.size(3);
  const torch::Tensor time = torch::arange(frames, torch::kLong).view({1, frames});
  const torch::Tensor source = (time - torch::tensor(shifts).view({-1, 1})).clamp(0, frames - 1);
  return features.gather(3, source.view({-1, 1, 1, frames}).expand(features.sizes()));
}

}  // namespace

torch::Tensor random_view(const torch::Tensor& features, const ViewRanges& ranges, bool in_sample_spread_units,
                          std::mt19937_64& generator) {
  const std::int64_t n = features.size(0), channels = features.size(1), mels = features.size(2),
                     frames = features.size(3);
  const torch::Tensor spread = in_sample_spread_units ? features.flatten(1).std(1).view({n, 1, 1, 1})
                                                      : torch::ones({n, 1, 1, 1}, features.options());
  const torch::Tensor global = uniform_draws(n, ranges.global_bias, generator).view({n, 1, 1, 1});
  const torch::Tensor channel = uniform_draws(n * channels, ranges.channel_bias, generator).view({n, channels, 1, 1});
  const torch::Tensor tilt = uniform_draws(n, ranges.tilt, generator).view({n, 1, 1, 1});
  const torch::Tensor tilt_profile =
      mels > 1 ? torch::linspace(-1.0, 1.0, mels, features.options()).view({1, 1, mels, 1})
               : torch::zeros({1, 1, 1, 1}, features.options());
  // Noise from a torch generator seeded by the run's, so a view depends only on the seed.
  const at::Generator noise_source = at::detail::createCPUGenerator(generator());
  const torch::Tensor noise = torch::randn(features.sizes(), noise_source, features.options());
  const auto max_shift = static_cast<std::int64_t>(ranges.max_shift_fraction * static_cast<double>(frames));
  std::vector<std::int64_t> shifts(static_cast<std::size_t>(n), 0);
  if (max_shift > 0) {
    for (auto& shift : shifts) shift = uniform_int(generator, -max_shift, max_shift);
  }
  const torch::Tensor perturbed =
      features + spread * (global + channel + tilt * tilt_profile + ranges.noise * noise);
  return padded_shift(perturbed, shifts);
}

torch::Tensor transfer_statistics(const torch::Tensor& features, const ContextStatisticBank& bank,
                                  const ContextProbeSettings& settings, std::int64_t rank, std::mt19937_64& generator) {
  const std::int64_t n = features.size(0), channels = features.size(1);
  const torch::Tensor own = channel_statistics(features);
  torch::Tensor reference;
  if (bank.size() == 0) {
    std::vector<std::int64_t> picked(static_cast<std::size_t>(n));
    for (auto& index : picked) index = uniform_int(generator, 0, n - 1);
    reference = own.index_select(0, torch::tensor(picked));
  } else {
    reference = settings.reference == ReferenceChoice::farthest
                    ? bank.farthest_from(own, settings.ranked_references ? rank : 0, settings.standardised_distance)
                    : bank.random_entries(n, generator);
  }
  std::vector<float> lambdas(static_cast<std::size_t>(n));
  for (auto& lambda : lambdas) lambda = static_cast<float>(beta(generator, settings.mix_alpha, settings.mix_alpha));
  const torch::Tensor lambda = torch::tensor(lambdas).view({n, 1});
  const torch::Tensor mixed = lambda * own + (1 - lambda) * reference;
  const auto shape = std::vector<std::int64_t>{n, channels, 1, 1};
  const torch::Tensor mean = own.narrow(1, 0, channels).reshape(shape);
  const torch::Tensor spread = own.narrow(1, channels, channels).reshape(shape).clamp_min(1e-6);
  return mixed.narrow(1, channels, channels).reshape(shape) * (features - mean) / spread +
         mixed.narrow(1, 0, channels).reshape(shape);
}

torch::Tensor ContextProbe::intervene(const torch::Tensor& features, std::mt19937_64& generator,
                                       std::int64_t rank) const {
  torch::NoGradGuard no_grad;
  return transfer_statistics(view(features.detach(), generator), bank_, settings_, rank, generator);
}

}  // namespace fscil
