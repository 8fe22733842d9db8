#include "methods/pan/new_row_finetune.h"

#include "methods/common/damped_momentum_steps.h"

namespace fscil {

namespace F = torch::nn::functional;

torch::Tensor finetune_new_rows(const torch::Tensor& shots, const torch::Tensor& labels, const torch::Tensor& old_rows,
                                const torch::Tensor& new_rows, double temperature, int steps, double learning_rate,
                                const std::function<void(int, double)>& after_step) {
  torch::Tensor trained = new_rows.detach().clone().set_requires_grad(true);
  const torch::Tensor fixed = old_rows.detach();
  const torch::Tensor unit_shots = F::normalize(shots.detach(), F::NormalizeFuncOptions().dim(-1));
  damped_momentum_steps(
      {trained}, steps, learning_rate,
      [&] {
        const torch::Tensor rows = F::normalize(torch::cat({fixed, trained}), F::NormalizeFuncOptions().dim(-1));
        return F::cross_entropy(temperature * unit_shots.matmul(rows.t()), labels);
      },
      "session fine-tuning", after_step);
  return trained.detach();
}

}  // namespace fscil
