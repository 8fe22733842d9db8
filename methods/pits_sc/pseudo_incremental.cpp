#include "methods/pits_sc/pseudo_incremental.h"

#include <fmt/format.h>

#include <algorithm>
#include <numeric>

#include "core/random_draws.h"
#include "core/seeded_shuffle.h"
#include "methods/common/class_members.h"

namespace fscil {

PitEpisodeShape pit_episode_shape(const PitsScSettings& settings, int base_classes, int novel_rows) {
  PitEpisodeShape shape{settings.pit_way, settings.pit_kept, (settings.pit_way - settings.pit_kept) / 2,
                        settings.pit_shot, settings.pit_query};
  if (base_classes < shape.way) {
    shape.way = base_classes;
    shape.pairs = std::min(shape.pairs, std::max(1, base_classes / 4));
    shape.kept = shape.way - 2 * shape.pairs;
  }
  shape.pairs = std::min(shape.pairs, novel_rows);
  shape.kept = std::min(shape.kept, shape.way - 2 * shape.pairs);
  if (shape.pairs < 1 || shape.kept < 1) {
    throw MethodError(fmt::format("pseudo-incremental training needs at least 3 base classes and 1 novel class; "
                                  "the protocol has {} base and {} novel", base_classes, novel_rows));
  }
  return shape;
}

PitEpisodeSampler::PitEpisodeSampler(const SessionData& base, int base_classes, int total_classes,
                                     const PitsScSettings& settings)
    : base_(base),
      base_classes_(base_classes),
      total_classes_(total_classes),
      settings_(settings),
      shape_(pit_episode_shape(settings, base_classes, total_classes - base_classes)),
      members_(base_class_members(base.labels, base_classes)) {}

std::vector<std::int64_t> PitEpisodeSampler::pick_samples(std::int64_t base_class, std::mt19937_64& generator) const {
  std::vector<std::int64_t> pool = members_[base_class];
  const auto wanted = static_cast<std::size_t>(shape_.per_class());
  if (pool.size() >= wanted) {  // without replacement when the class has enough samples
    shuffle_with(pool, generator);
    pool.resize(wanted);
    return pool;
  }
  std::vector<std::int64_t> picked(wanted);
  for (auto& index : picked) index = pool[uniform_index(generator, pool.size())];
  return picked;
}

torch::Tensor mix_signals(const SampleRows& signals, const std::vector<std::int64_t>& first,
                          const std::vector<std::int64_t>& second, double lambda) {
  return lambda * signals.gather(torch::tensor(first)) + (1 - lambda) * signals.gather(torch::tensor(second));
}

PitEpisode PitEpisodeSampler::draw(std::mt19937_64& generator, const FrontEnd& front_end) const {
  std::vector<std::int64_t> classes(base_classes_);
  std::iota(classes.begin(), classes.end(), 0);
  shuffle_with(classes, generator);
  classes.resize(shape_.way);

  PitEpisode episode;
  std::vector<std::int64_t> kept_index;
  for (int k = 0; k < shape_.kept; ++k) {
    const auto picked = pick_samples(classes[k], generator);
    kept_index.insert(kept_index.end(), picked.begin(), picked.end());
  }
  const torch::Tensor kept = torch::tensor(kept_index);
  episode.kept_features = base_.features.gather(kept);
  episode.kept_labels = base_.labels.index_select(0, kept);

  episode.lambda = beta(generator, settings_.pit_alpha, settings_.pit_alpha);
  for (int j = 0; j < shape_.pairs; ++j) {
    episode.first_class.push_back(classes[shape_.kept + j]);
    episode.second_class.push_back(classes[shape_.kept + shape_.pairs + j]);
    const auto first = pick_samples(episode.first_class.back(), generator);
    const auto second = pick_samples(episode.second_class.back(), generator);
    episode.first_samples.insert(episode.first_samples.end(), first.begin(), first.end());
    episode.second_samples.insert(episode.second_samples.end(), second.begin(), second.end());
  }
  episode.mixed_signals = mix_signals(base_.signals, episode.first_samples, episode.second_samples, episode.lambda);
  episode.mixed_features = front_end(episode.mixed_signals);

  std::vector<std::int64_t> rows(total_classes_ - base_classes_);
  std::iota(rows.begin(), rows.end(), base_classes_);
  shuffle_with(rows, generator);
  episode.novel_rows.assign(rows.begin(), rows.begin() + shape_.pairs);
  std::vector<std::int64_t> query_labels;
  for (int j = 0; j < shape_.pairs; ++j) query_labels.insert(query_labels.end(), shape_.query, episode.novel_rows[j]);
  episode.query_labels = torch::tensor(query_labels);
  return episode;
}

LossParts pit_episode_loss(const TrainingEmbedder& embedder, StochasticClassifier& classifier,
                           const PitEpisode& episode, const PitEpisodeShape& shape, int base_classes,
                           int total_classes) {
  const TrainingEmbedding kept = embedder(episode.kept_features, episode.kept_probe_rows);
  const TrainingEmbedding mixed_batch = embedder(episode.mixed_features, episode.mixed_probe_rows);
  const torch::Tensor& kept_embeddings = kept.embedding;
  const torch::Tensor mixed = mixed_batch.embedding.view({shape.pairs, shape.per_class(), -1});
  const torch::Tensor prototypes = mixed.narrow(1, 0, shape.shot).mean(1).detach();
  classifier->set_mu_rows(base_classes, torch::zeros({total_classes - base_classes, prototypes.size(1)}));
  for (int j = 0; j < shape.pairs; ++j) classifier->set_mu_rows(episode.novel_rows[j], prototypes.narrow(0, j, 1));
  const torch::Tensor queries = mixed.narrow(1, shape.shot, shape.query).reshape({shape.pairs * shape.query, -1});
  const torch::Tensor logits = torch::cat({classifier->forward(kept_embeddings, total_classes, true),
                                           classifier->forward(queries, total_classes, true)});
  LossParts loss;
  loss.classification =
      torch::nn::functional::cross_entropy(logits, torch::cat({episode.kept_labels, episode.query_labels}));
  if (kept.side_loss.defined()) {
    const double kept_share = static_cast<double>(kept_embeddings.size(0)) /
                              static_cast<double>(kept_embeddings.size(0) + mixed_batch.embedding.size(0));
    loss.side = kept_share * kept.side_loss + (1 - kept_share) * mixed_batch.side_loss;
  }
  return loss;
}

}  // namespace fscil
