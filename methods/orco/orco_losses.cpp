#include "methods/orco/orco_losses.h"

#include <ATen/CPUGeneratorImpl.h>

#include <vector>

#include "core/seeded_shuffle.h"

namespace fscil {

namespace F = torch::nn::functional;

torch::Tensor supervised_contrastive_loss(const torch::Tensor& views, const torch::Tensor& labels, double temperature) {
  const std::int64_t n = views.size(0), v = views.size(1);
  const torch::Tensor anchors = views.transpose(0, 1).reshape({n * v, views.size(2)});
  const torch::Tensor anchor_labels = labels.repeat({v});
  const torch::Tensor self = torch::eye(n * v, torch::kBool);
  const torch::Tensor positives = (anchor_labels.view({-1, 1}) == anchor_labels.view({1, -1})) & ~self;
  // Self-similarity is excluded from the denominator by filling it with -inf before the softmax.
  const torch::Tensor logits = (anchors.matmul(anchors.t()) / temperature).masked_fill(self, -INFINITY);
  const torch::Tensor log_probability = F::log_softmax(logits, F::LogSoftmaxFuncOptions(1));
  const torch::Tensor positive_count = positives.sum(1);
  const torch::Tensor has_positive = positive_count > 0;
  const torch::Tensor positive_log_probability =
      log_probability.masked_fill(~positives, 0.0).sum(1).index({has_positive}) /
      positive_count.index({has_positive}).to(views.scalar_type());
  return -positive_log_probability.mean();
}

torch::Tensor spread_loss(const torch::Tensor& directions) {
  const torch::Tensor unit = F::normalize(directions, F::NormalizeFuncOptions().dim(1));
  return torch::logsumexp(unit.matmul(unit.t()), 1).mean();
}

torch::Tensor orthogonality_loss(const torch::Tensor& projections, const torch::Tensor& labels,
                                 const torch::Tensor& assigned_targets, const torch::Tensor& target_labels,
                                 const torch::Tensor& unassigned_targets) {
  const torch::Tensor classes = std::get<0>(torch::_unique(labels, /*sorted=*/true));
  const torch::Tensor unit = F::normalize(projections, F::NormalizeFuncOptions().dim(1));
  std::vector<torch::Tensor> rows;
  for (std::int64_t i = 0; i < classes.size(0); ++i) rows.push_back(unit.index({labels == classes[i]}).mean(0));
  std::vector<torch::Tensor> parts = {torch::stack(rows)};
  const torch::Tensor absent = ~torch::isin(target_labels, classes);
  parts.push_back(assigned_targets.index({absent}));
  if (unassigned_targets.size(0) > 0) parts.push_back(unassigned_targets);
  return spread_loss(torch::cat(parts));
}

torch::Tensor orthogonality_loss_from(std::int64_t from_class, const torch::Tensor& projections,
                                      const torch::Tensor& labels, const torch::Tensor& assigned_targets,
                                      const torch::Tensor& target_labels, const torch::Tensor& unassigned_targets) {
  const torch::Tensor kept = labels >= from_class;
  if (!kept.any().item<bool>()) return torch::zeros({});
  return orthogonality_loss(projections.index({kept}), labels.index({kept}), assigned_targets, target_labels,
                            unassigned_targets);
}

torch::Tensor split_cross_entropy(const torch::Tensor& logits, const torch::Tensor& labels, std::int64_t novel_from,
                                  double base_weight, double novel_weight) {
  torch::Tensor loss = torch::zeros({});
  const torch::Tensor novel = labels >= novel_from;
  for (const auto& [rows, weight] : {std::pair{~novel, base_weight}, std::pair{novel, novel_weight}}) {
    if (weight == 0 || !rows.any().item<bool>()) continue;
    loss = loss + weight * F::cross_entropy(logits.index({rows}), labels.index({rows}));
  }
  return loss;
}

PerturbedTargets perturb_targets(const torch::Tensor& targets, const torch::Tensor& labels, std::int64_t count,
                                 double epsilon, double offset, std::mt19937_64& generator) {
  std::vector<std::int64_t> pool(static_cast<std::size_t>(targets.size(0)));
  std::vector<std::int64_t> chosen;
  while (static_cast<std::int64_t>(chosen.size()) < count) {
    for (std::size_t i = 0; i < pool.size(); ++i) pool[i] = static_cast<std::int64_t>(i);
    shuffle_with(pool, generator);
    for (std::int64_t index : pool) {
      if (static_cast<std::int64_t>(chosen.size()) == count) break;
      chosen.push_back(index);
    }
  }
  const torch::Tensor index = torch::tensor(chosen);
  const torch::Tensor picked = targets.index_select(0, index).unsqueeze(1).expand({count, 2, targets.size(1)});
  const at::Generator noise_source = at::detail::createCPUGenerator(generator());
  const torch::Tensor noise = (torch::rand(picked.sizes(), noise_source, targets.options()) - offset) * epsilon;
  return {F::normalize(picked + noise, F::NormalizeFuncOptions().dim(2)), labels.index_select(0, index)};
}

}  // namespace fscil
