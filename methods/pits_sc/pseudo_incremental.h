#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <functional>
#include <random>
#include <vector>

#include "methods/common/loss_parts.h"
#include "methods/common/resnet18.h"
#include "methods/common/stochastic_classifier.h"
#include "methods/method.h"
#include "methods/pits_sc/pits_sc_settings.h"

namespace fscil {

// How many base classes an episode draws, how many keep their labels, how many pairs are mixed
// into pseudo-novel classes. PITS-SC's 20 / 10 / 5; a protocol with fewer base classes (or
// fewer novel rows) gets a proportionally smaller episode.
struct PitEpisodeShape {
  int way = 0, kept = 0, pairs = 0, shot = 0, query = 0;
  int per_class() const { return shot + query; }
};
PitEpisodeShape pit_episode_shape(const PitsScSettings& settings, int base_classes, int novel_rows);

// The raw-signal mixture lambda x s_first[i] + (1 - lambda) x s_second[i] of base samples.
torch::Tensor mix_signals(const SampleRows& signals, const std::vector<std::int64_t>& first,
                          const std::vector<std::int64_t>& second, double lambda);

// One pseudo-incremental episode. Mixed samples are pair-major: pair j holds its `shot`
// mixed shots, then its `query` mixed queries; mixed sample i of pair j is
// lambda * (sample i of first_class[j]) + (1 - lambda) * (sample i of second_class[j]), on the raw signal.
struct PitEpisode {
  torch::Tensor kept_features, kept_labels;
  torch::Tensor mixed_signals, mixed_features;
  std::vector<std::int64_t> first_class, second_class;
  // The samples (indices into the base session) each pair mixed, pair-major like mixed_signals:
  // what a method that mixes the episode's classes again draws from (PA-PCT's second half-step).
  std::vector<std::int64_t> first_samples, second_samples;
  double lambda = 0;
  std::vector<std::int64_t> novel_rows;  // per pair: the classifier row its prototype goes to
  torch::Tensor query_labels;            // pair j's queries carry novel_rows[j]
  // Rows the method's network replaces by probes of themselves (cop-fscil's CPI): indices into
  // kept_features and mixed_features; undefined = none (PITS-SC).
  torch::Tensor kept_probe_rows, mixed_probe_rows;
};

using FrontEnd = std::function<torch::Tensor(const torch::Tensor&)>;

// Draws episodes from the base session's training data with the run's generator.
class PitEpisodeSampler {
 public:
  PitEpisodeSampler(const SessionData& base, int base_classes, int total_classes, const PitsScSettings& settings);
  PitEpisode draw(std::mt19937_64& generator, const FrontEnd& front_end) const;
  const PitEpisodeShape& shape() const { return shape_; }

 private:
  std::vector<std::int64_t> pick_samples(std::int64_t base_class, std::mt19937_64& generator) const;

  const SessionData& base_;
  int base_classes_, total_classes_;
  PitsScSettings settings_;
  PitEpisodeShape shape_;
  std::vector<std::vector<std::int64_t>> members_;  // per base class: its sample indices
};

// What the trained network gives a batch in training mode: the embedding the classifier sees
// and a loss the method adds beside the classification loss (cop-fscil's lambda L_PIC;
// undefined when there is none).
struct TrainingEmbedding {
  torch::Tensor embedding;
  torch::Tensor side_loss;
};
// A batch through the network in training mode; `probe_rows` (undefined = none) are replaced by
// probes of themselves inside the network.
using TrainingEmbedder =
    std::function<TrainingEmbedding(const torch::Tensor& features, const torch::Tensor& probe_rows)>;

// The episode's loss: the mean embedding of each pair's mixed shots (no gradient) becomes its
// novel row of mu (other novel rows zero); one cross-entropy with the stochastic classifier
// over every row, on the kept classes' samples and the mixed queries; plus the embedder's
// side losses, weighted by the samples they cover.
LossParts pit_episode_loss(const TrainingEmbedder& embedder, StochasticClassifier& classifier,
                           const PitEpisode& episode, const PitEpisodeShape& shape, int base_classes,
                           int total_classes);

}  // namespace fscil
