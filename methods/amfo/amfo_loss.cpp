#include "methods/amfo/amfo_loss.h"

namespace fscil {

namespace F = torch::nn::functional;

torch::Tensor cosface_loss(const torch::Tensor& cosines, const torch::Tensor& labels, double scale, double margin) {
  const torch::Tensor target = F::one_hot(labels, cosines.size(1)).to(cosines.scalar_type());
  return F::cross_entropy(scale * (cosines - margin * target), labels);
}

AmfoLoss amfo_loss(const torch::Tensor& positive, const torch::Tensor& negative, const Fusion& fusion,
                   const torch::Tensor& labels, std::int64_t base_classes, const AmfoLossSettings& weights) {
  AmfoLoss loss;
  loss.margin = weights.margin * (cosface_loss(positive, labels, weights.cosface_scale, weights.positive_margin) +
                                  cosface_loss(negative, labels, weights.cosface_scale, weights.negative_margin));
  loss.fusion = weights.fusion * F::cross_entropy(weights.temperature * fusion.mixed, labels);
  loss.binary = weights.binary * F::cross_entropy(weights.temperature * fusion.binary, (labels >= base_classes).to(torch::kLong));
  loss.distillation = torch::zeros({});
  loss.sparsity = torch::zeros({});
  return loss;
}

void add_session_terms(AmfoLoss& loss, const torch::Tensor& positive, const torch::Tensor& teacher_cosines,
                       double temperature, const torch::Tensor& gate, double sparsity_floor) {
  constexpr double kDistillationTemperature = 0.5, kSparsityWeight = 0.1;  // AMFO.py L154, L151
  // The teacher's cosines are scaled by the temperature, the student's are not (L145 gets 16 x the
  // old network's output and the plain one of this). Everything the old columns read is frozen in
  // a session, so they are the teacher's own: the term's value is logged, its gradient is zero.
  const std::int64_t old = teacher_cosines.size(1);
  const torch::Tensor target = torch::softmax(temperature * teacher_cosines / kDistillationTemperature, 1);
  const torch::Tensor log_student = torch::log_softmax(positive.slice(1, 0, old) / kDistillationTemperature, 1);
  loss.distillation = -(target * log_student).sum(1).mean();
  if (gate.defined()) loss.sparsity = 2 * kSparsityWeight * torch::relu(gate.mean() - sparsity_floor);
}

}  // namespace fscil
