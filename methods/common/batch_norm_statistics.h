#pragma once
#include <torch/torch.h>

#include <functional>

#include "methods/sample_rows.h"

namespace fscil {

// Recomputes every batch norm's running mean and variance in `module` as the average over the
// batches of `data` (cumulative, not exponential), forwarding each batch in training mode without
// gradients. Used after training on perturbed batches, so that inference normalises clean inputs
// with clean statistics. Restores each norm's momentum and the module's train flag.
void reestimate_batch_norm_statistics(torch::nn::Module& module, const SampleRows& data, std::int64_t batch_size,
                                      const std::function<void(const torch::Tensor&)>& forward);

}  // namespace fscil
