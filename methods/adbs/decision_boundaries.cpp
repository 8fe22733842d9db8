#include "methods/adbs/decision_boundaries.h"

#include "methods/common/damped_momentum_steps.h"

namespace fscil {

namespace F = torch::nn::functional;

torch::Tensor inter_class_constraint(const torch::Tensor& margins, const torch::Tensor& rows) {
  const torch::Tensor unit = F::normalize(rows, F::NormalizeFuncOptions().p(2).dim(-1));
  const torch::Tensor cosine = unit.matmul(unit.t());  // w_i.w_j
  const torch::Tensor m_j = margins.view({1, -1});
  const torch::Tensor m_i = margins.view({-1, 1});
  return torch::relu((1 - cosine) - (m_j - m_i * cosine)).mean();
}

torch::Tensor train_new_margins(const torch::Tensor& cosine_logits, const torch::Tensor& labels,
                                const torch::Tensor& old_margins, const torch::Tensor& new_margins,
                                const torch::Tensor& rows, const MarginUpdate& update,
                                const std::function<void(int, double, double)>& after_step) {
  torch::Tensor trained = new_margins.detach().clone().set_requires_grad(true);
  const torch::Tensor fixed_logits = cosine_logits.detach();
  const torch::Tensor fixed_old = old_margins.detach();
  const torch::Tensor fixed_rows = rows.detach();
  torch::Tensor cross_entropy, constraint;
  damped_momentum_steps(
      {trained}, update.steps, update.learning_rate,
      [&] {
        const torch::Tensor margins = torch::cat({fixed_old, trained});
        cross_entropy = F::cross_entropy(fixed_logits * margins, labels);
        constraint = update.constraint_weight * inter_class_constraint(margins, fixed_rows);
        return cross_entropy + constraint;
      },
      "session margin update",
      [&](int step, double) {
        if (after_step) after_step(step, cross_entropy.item<double>(), constraint.item<double>());
      });
  return trained.detach();
}

}  // namespace fscil
