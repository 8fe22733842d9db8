#include "methods/pan/new_row_finetune.h"

namespace fscil {

namespace F = torch::nn::functional;

torch::Tensor finetune_new_rows(const torch::Tensor& shots, const torch::Tensor& labels, const torch::Tensor& old_rows,
                                const torch::Tensor& new_rows, double temperature, int steps, double learning_rate,
                                const std::function<void(int, double)>& after_step) {
  torch::Tensor trained = new_rows.detach().clone().set_requires_grad(true);
  const torch::Tensor fixed = old_rows.detach();
  const torch::Tensor unit_shots = F::normalize(shots.detach(), F::NormalizeFuncOptions().dim(-1));
  torch::optim::SGD optimizer({trained}, torch::optim::SGDOptions(learning_rate).momentum(0.9).dampening(0.9));
  for (int step = 0; step < steps; ++step) {
    const torch::Tensor rows = F::normalize(torch::cat({fixed, trained}), F::NormalizeFuncOptions().dim(-1));
    const torch::Tensor loss = F::cross_entropy(temperature * unit_shots.matmul(rows.t()), labels);
    optimizer.zero_grad();
    loss.backward();
    optimizer.step();
    if (after_step) after_step(step + 1, loss.item<double>());
  }
  return trained.detach();
}

}  // namespace fscil
