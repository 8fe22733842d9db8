#include "methods/pa_pct/pcts_episode.h"

#include "methods/pa_pct/pcts_losses.h"
#include "methods/pan/prototype_query_attention.h"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

namespace fscil {

PctsAddition pcts_addition(const std::function<torch::Tensor(const torch::Tensor&)>& embed,
                           const std::function<torch::Tensor(const torch::Tensor&)>& attend,
                           const torch::Tensor& base_rows, std::int64_t total_classes, const PitEpisode& episode,
                           const PitEpisodeShape& shape, double temperature) {
  const torch::Tensor kept = embed(episode.kept_features);
  const torch::Tensor mixed = embed(episode.mixed_features).view({shape.pairs, shape.per_class(), -1});
  const std::int64_t base_classes = base_rows.size(0), dim = base_rows.size(1);
  torch::Tensor rows = torch::cat({base_rows, torch::zeros({total_classes - base_classes, dim}, base_rows.options())});
  const torch::Tensor prototypes = mixed.narrow(1, 0, shape.shot).mean(1);
  for (int j = 0; j < shape.pairs; ++j) rows[episode.novel_rows[j]] = prototypes[j];
  rows = rows.detach();
  const torch::Tensor queries =
      torch::cat({kept, mixed.narrow(1, shape.shot, shape.query).reshape({shape.pairs * shape.query, dim})});
  const torch::Tensor labels = torch::cat({episode.kept_labels, episode.query_labels});
  torch::Tensor adapted;
  const torch::Tensor logits = pqa_logits(attend, rows, queries, temperature, 256, &adapted);
  return {torch::nn::functional::cross_entropy(logits, labels), rows, adapted.detach()};
}

PctsRemoval pcts_removal(const std::function<torch::Tensor(const torch::Tensor&)>& embed,
                         const std::function<torch::Tensor(const torch::Tensor&)>& attend,
                         const PctsAddition& addition, std::int64_t base_classes, const SessionData& base,
                         const FrontEnd& front_end, const PitEpisode& episode, const PitEpisodeShape& shape,
                         double lambda, double temperature, const PctsRemovalWeights& weights) {
  PctsRemoval result;
  const int retained_pseudo = shape.pairs - weights.forgotten;
  if (weights.forgotten < 1 || retained_pseudo < 1) {
    throw MethodError(fmt::format("PCTS forgets {} of an episode's {} pseudo-classes: at least one must go and one stay",
                                  weights.forgotten, shape.pairs));
  }
  for (std::int64_t c = 0; c < base_classes; ++c) result.retained_rows.push_back(c);
  for (int j = 0; j < shape.pairs; ++j) {
    (j < retained_pseudo ? result.retained_rows : result.forgotten_rows).push_back(episode.novel_rows[j]);
  }
  torch::Tensor rows = addition.rows.clone();
  for (std::int64_t row : result.forgotten_rows) rows[row].zero_();

  // The episode's mixed classes in the release's order (its pairs' first classes, then their
  // second ones), each with its per_class samples; class k is now mixed with class r + k.
  const std::int64_t per_class = shape.per_class();
  const auto samples_of = [&](int mixed_class) {
    const std::vector<std::int64_t>& pool = mixed_class < shape.pairs ? episode.first_samples : episode.second_samples;
    const std::int64_t offset = (mixed_class % shape.pairs) * per_class;
    return std::vector<std::int64_t>(pool.begin() + offset, pool.begin() + offset + per_class);
  };
  std::vector<std::int64_t> first, second;
  for (int k = 0; k < retained_pseudo; ++k) {
    const auto a = samples_of(k), b = samples_of(retained_pseudo + k);
    first.insert(first.end(), a.begin(), a.end());
    second.insert(second.end(), b.begin(), b.end());
  }
  torch::Tensor kept, mixed;
  {
    torch::NoGradGuard frozen;  // the release sets the encoder's requires_grad to false (PCA.py L130-L131)
    kept = embed(episode.kept_features);
    mixed = embed(front_end(mix_signals(base.signals, first, second, lambda))).view({retained_pseudo, per_class, -1});
  }
  const torch::Tensor queries =
      torch::cat({kept, mixed.narrow(1, shape.shot, shape.query).reshape({retained_pseudo * shape.query, -1})});
  std::vector<std::int64_t> pseudo_labels;
  for (int k = 0; k < retained_pseudo; ++k) pseudo_labels.insert(pseudo_labels.end(), shape.query, episode.novel_rows[k]);
  const torch::Tensor labels = torch::cat({episode.kept_labels, torch::tensor(pseudo_labels)});

  torch::Tensor adapted;
  const torch::Tensor logits = pqa_logits(attend, rows, queries, temperature, 256, &adapted);
  const torch::Tensor retained = torch::tensor(result.retained_rows), forgotten = torch::tensor(result.forgotten_rows);
  result.classification = torch::nn::functional::cross_entropy(logits, labels);
  result.separation = forgetting_separation_loss(addition.adapted.index_select(0, forgotten),
                                                 adapted.index_select(0, retained), weights.separation_margin);
  result.topology = topology_distillation_loss(addition.adapted.index_select(0, retained),
                                               adapted.index_select(0, retained), weights.topology_sigma);
  result.loss = result.classification + weights.separation_weight * result.separation +
                weights.topology_weight * result.topology;
  return result;
}

}  // namespace fscil
