#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <functional>
#include <vector>

#include "methods/pa_pct/pa_pct_settings.h"
#include "methods/pits_sc/pseudo_incremental.h"

namespace fscil {

// PCTS's first half-step, pseudo-addition (cgq2971-afk/FCIAC PCA.py L81-L120 at 6ccc2082), on an
// episode drawn as PITS-SC draws its own (PitEpisodeSampler with PCTS's shape: 10 kept classes,
// 5 pairs mixed on the raw signal, 20 samples each): every kept sample is a query with its label;
// each pair's prototype is the mean of its first `shot` mixed embeddings, written into its novel
// row after every novel row is zeroed; its other mixed samples are queries of that row. The loss
// is the cross-entropy of temperature x cos after `attend` (the gated PQA) over every row as
// tokens, the rows detached (P L98, L112).
struct PctsAddition {
  torch::Tensor loss;
  torch::Tensor rows;     // C x D: the rows the episode scored against (base rows, zeros, its prototypes)
  torch::Tensor adapted;  // C x D: the rows after the attention, averaged over the queries (detached)
};
PctsAddition pcts_addition(const std::function<torch::Tensor(const torch::Tensor&)>& embed,
                           const std::function<torch::Tensor(const torch::Tensor&)>& attend,
                           const torch::Tensor& base_rows, std::int64_t total_classes, const PitEpisode& episode,
                           const PitEpisodeShape& shape, double temperature);

// PCTS's second half-step, pseudo-removal (PCA.py L122-L183): the last `forgotten` pseudo rows
// are zeroed; the others and every base class are retained; with the encoder frozen (no
// gradient), the episode's mixed classes are re-mixed in new pairs (class k with class r + k of
// the first 2r mixed classes, r retained pseudo rows, one new lambda), whose queries carry the
// retained pseudo rows' labels (the release's; those rows hold the first pairs' prototypes), and
// the kept samples are queries again. Loss = CE + separation_weight L_FS(the forgotten rows'
// adapted prototypes before, the retained ones now) + topology_weight L_T(retained before, now).
struct PctsRemoval {
  torch::Tensor loss, classification, separation, topology;
  std::vector<std::int64_t> forgotten_rows, retained_rows;
};
PctsRemoval pcts_removal(const std::function<torch::Tensor(const torch::Tensor&)>& embed,
                         const std::function<torch::Tensor(const torch::Tensor&)>& attend,
                         const PctsAddition& addition, std::int64_t base_classes, const SessionData& base,
                         const FrontEnd& front_end, const PitEpisode& episode, const PitEpisodeShape& shape,
                         double lambda, double temperature, const PctsRemovalWeights& weights = {});

}  // namespace fscil
