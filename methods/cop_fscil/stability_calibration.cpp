#include "methods/cop_fscil/stability_calibration.h"

namespace fscil {

torch::Tensor probe_instability(const torch::Tensor& original, const torch::Tensor& probes, bool normalised) {
  namespace F = torch::nn::functional;
  if (!normalised) return (probes - original.unsqueeze(0)).pow(2).sum(2).mean(0);
  const auto unit = F::NormalizeFuncOptions().dim(-1);
  return (F::normalize(probes, unit) - F::normalize(original, unit).unsqueeze(0)).pow(2).sum(2).mean(0);
}

torch::Tensor stability_weights(const torch::Tensor& instability, const torch::Tensor& labels, double beta) {
  torch::Tensor weights = torch::zeros_like(instability);
  const torch::Tensor classes = std::get<0>(torch::_unique(labels));
  for (std::int64_t k = 0; k < classes.size(0); ++k) {
    const torch::Tensor mask = labels == classes[k];
    weights.index_put_({mask}, torch::softmax(-beta * instability.index({mask}), 0));
  }
  return weights;
}

double effective_shots(const torch::Tensor& weights, const torch::Tensor& labels) {
  const torch::Tensor classes = std::get<0>(torch::_unique(labels));
  double sum = 0;
  for (std::int64_t k = 0; k < classes.size(0); ++k) {
    sum += 1.0 / weights.index({labels == classes[k]}).pow(2).sum().item<double>();
  }
  return sum / static_cast<double>(classes.size(0));
}

torch::Tensor calibrated_prototypes(const torch::Tensor& original, const torch::Tensor& probes,
                                    const torch::Tensor& weights, const torch::Tensor& labels,
                                    const std::vector<std::int64_t>& classes, bool mean_of_views) {
  const torch::Tensor mean_views =
      mean_of_views ? (original + probes.sum(0)) / static_cast<double>(probes.size(0) + 1) : original;
  std::vector<torch::Tensor> rows;
  for (std::int64_t label : classes) {
    const torch::Tensor mask = labels == label;
    rows.push_back((weights.index({mask}).unsqueeze(1) * mean_views.index({mask})).sum(0));
  }
  return torch::stack(rows);
}

torch::Tensor new_and_old_loss(StochasticClassifier& classifier, const torch::Tensor& support_embeddings,
                               const torch::Tensor& support_labels, const torch::Tensor& old_means,
                               std::int64_t old_classes, std::int64_t seen) {
  namespace F = torch::nn::functional;
  const torch::Tensor new_logits =
      classifier->forward(support_embeddings, seen, true).narrow(1, old_classes, seen - old_classes);
  torch::Tensor loss = F::cross_entropy(new_logits, support_labels - old_classes);
  if (old_classes > 0) {
    const torch::Tensor old_logits = classifier->forward(old_means, old_classes, true);
    loss = loss + F::cross_entropy(old_logits, torch::arange(old_classes, torch::kLong));
  }
  return loss;
}

}  // namespace fscil
