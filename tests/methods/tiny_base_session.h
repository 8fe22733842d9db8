#pragma once
#include <torch/torch.h>

#include "methods/method.h"

namespace fscil {

// 6 base classes x 25 samples; each raw signal is its class index on channel 0 and its
// sample index on channel 1, so a mixture shows exactly what it was mixed from.
inline SessionData tiny_base() {
  SessionData base;
  const std::int64_t n = 6 * 25, length = 16;
  base.labels = torch::div(torch::arange(n), 25, "floor");
  const torch::Tensor signals = torch::zeros({n, 2, length});
  signals.select(1, 0).copy_(base.labels.to(torch::kFloat).view({n, 1}).expand({n, length}));
  signals.select(1, 1).copy_(torch::arange(n).to(torch::kFloat).view({n, 1}).expand({n, length}));
  base.signals = signals;
  base.features = torch::randn({n, 2, 4, 4});
  for (std::int64_t c = 0; c < 6; ++c) base.new_classes.push_back(c);
  return base;
}

// A stand-in front end: each channel's mean, spread over a 4 x 4 map.
inline torch::Tensor mean_front_end(const torch::Tensor& signals) {
  return signals.mean(-1).view({signals.size(0), signals.size(1), 1, 1}).expand({-1, -1, 4, 4}).contiguous();
}

// Two new classes x 5 shots, features drawn from torch's generator.
inline SessionData tiny_support(std::int64_t first_class) {
  SessionData data;
  data.session = first_class == 6 ? 1 : 2;
  data.features = torch::randn({10, 2, 4, 4}) + 1.0;
  data.labels = torch::div(torch::arange(10), 5, "floor") + first_class;
  data.new_classes = {first_class, first_class + 1};
  return data;
}

// 6 base classes x 5 validation samples, features drawn from torch's generator.
inline SessionData tiny_validation() {
  SessionData data;
  data.features = torch::randn({30, 2, 4, 4});
  data.labels = torch::div(torch::arange(30), 5, "floor");
  for (std::int64_t c = 0; c < 6; ++c) data.new_classes.push_back(c);
  return data;
}

// The context of the tiny protocol: 10 classes, 6 of them base, 2 x 4 x 4 inputs.
inline RunContext tiny_context(std::uint64_t seed) {
  RunContext context;
  context.seed = seed;
  context.generator = std::mt19937_64(seed);
  context.total_classes = 10;
  context.base_classes = 6;
  context.input = {2, 4, 4, 16};
  context.front_end = mean_front_end;
  return context;
}

}  // namespace fscil
