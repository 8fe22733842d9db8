#pragma once
#include <torch/torch.h>

#include <functional>

#include "methods/common/stochastic_classifier.h"

namespace fscil {

struct SessionFinetuneSettings {
  int steps = 200;
  double learning_rate = 0.1;
  double lamda_proto = 0.0;
};

// The incremental update with the encoder frozen: `steps` full-batch SGD steps (momentum 0.9,
// dampening 0.9, no weight decay) on the classifier's mu and sigma, stochastic forward on,
// minimising `loss`. Returns the final loss.
double finetune_classifier_rows(StochasticClassifier& classifier, const SessionFinetuneSettings& settings,
                                const std::function<torch::Tensor()>& loss);

// PITS-SC's session loss: lamda_proto * CE(stored old-class means) + (1 - lamda_proto) *
// CE(support embeddings), over the first `seen` classes.
double finetune_session_rows(StochasticClassifier& classifier, const torch::Tensor& support_embeddings,
                             const torch::Tensor& support_labels, const torch::Tensor& old_means,
                             std::int64_t seen, const SessionFinetuneSettings& settings);

}  // namespace fscil
