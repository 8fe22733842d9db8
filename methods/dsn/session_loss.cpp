#include "methods/dsn/session_loss.h"

namespace fscil {

namespace F = torch::nn::functional;

DsnSessionLoss dsn_session_loss(const torch::Tensor& cosines, const torch::Tensor& labels,
                                const torch::Tensor& teacher_cosines, const torch::Tensor& gate, double temperature) {
  constexpr double kDistillationTemperature = 0.5, kCompressionWeight = 0.1;  // L99, L101
  const torch::Tensor logits = temperature * cosines;
  const std::int64_t old = teacher_cosines.size(1);
  const torch::Tensor target = torch::softmax(temperature * teacher_cosines / kDistillationTemperature, 1);
  const torch::Tensor log_student = torch::log_softmax(logits.slice(1, 0, old) / kDistillationTemperature, 1);
  DsnSessionLoss loss;
  loss.cross_entropy = F::cross_entropy(logits, labels);
  loss.distillation = -(target * log_student).sum(1).mean();
  loss.compression = gate.defined() ? kCompressionWeight * gate.mean() : torch::zeros({});
  return loss;
}

}  // namespace fscil
