#pragma once
#include <torch/torch.h>

#include <functional>

namespace fscil {

// PAN's session update (vinceasvp/FCAC models/stdu/Network.py L248-L266 at 9f784713): only the
// new rows train, from the shots' means, for `steps` full-batch SGD steps (momentum 0.9, dampening
// 0.9, no weight decay, L253) on CE(temperature x cos(shots, [old rows | new rows])), the old rows
// fixed. `after_step(step, loss)` follows each step (1-based). Returns the trained new rows.
torch::Tensor finetune_new_rows(const torch::Tensor& shots, const torch::Tensor& labels, const torch::Tensor& old_rows,
                                const torch::Tensor& new_rows, double temperature, int steps, double learning_rate,
                                const std::function<void(int, double)>& after_step = {});

}  // namespace fscil
