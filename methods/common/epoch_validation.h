#pragma once
#include <torch/torch.h>

#include <functional>
#include <optional>

#include "methods/method.h"
#include "metrics/convergence.h"

namespace fscil {

// The top-1 accuracy in percent of `logits_of(data)` on `data`, without gradients.
inline double top1_accuracy(const SessionData& data, const std::function<torch::Tensor(const SessionData&)>& logits_of) {
  torch::NoGradGuard no_grad;
  return 100.0 * (logits_of(data).argmax(1) == data.labels).to(torch::kDouble).mean().item<double>();
}

// Scores the epoch just logged on base validation: its "base_validation" value, what the training
// verdict reads (metrics/convergence.h), by what the stage trains (`logits_of`) on `part` of the
// split (all of it by default). Nothing when that is empty. `logits_of` must score in eval mode
// without random draws, so that the training is the same with or without it.
inline std::optional<double> record_epoch_validation(
    RunContext& context, const std::function<torch::Tensor(const SessionData&)>& logits_of,
    const std::function<SessionData(const SessionData&)>& part = {}) {
  if (context.validation == nullptr) return std::nullopt;
  const SessionData scored = part ? part(*context.validation) : *context.validation;
  if (scored.labels.size(0) == 0) return std::nullopt;
  const double accuracy = top1_accuracy(scored, logits_of);
  context.training_log.back().values[kBaseValidationKey] = accuracy;
  return accuracy;
}

}  // namespace fscil
