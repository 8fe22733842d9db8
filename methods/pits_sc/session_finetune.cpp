#include "methods/pits_sc/session_finetune.h"

#include "methods/common/damped_momentum_steps.h"

namespace fscil {

namespace F = torch::nn::functional;

double finetune_classifier_rows(StochasticClassifier& classifier, const SessionFinetuneSettings& settings,
                                const std::function<torch::Tensor()>& loss) {
  classifier->train();
  const double last = damped_momentum_steps({classifier->mu, classifier->sigma}, settings.steps,
                                            settings.learning_rate, loss, "session fine-tuning");
  classifier->eval();
  return last;
}

double finetune_session_rows(StochasticClassifier& classifier, const torch::Tensor& support_embeddings,
                             const torch::Tensor& support_labels, const torch::Tensor& old_means,
                             std::int64_t seen, const SessionFinetuneSettings& settings) {
  const torch::Tensor old_labels = torch::arange(old_means.size(0), torch::kLong);
  return finetune_classifier_rows(classifier, settings, [&] {
    torch::Tensor loss = (1 - settings.lamda_proto) *
                         F::cross_entropy(classifier->forward(support_embeddings, seen, true), support_labels);
    if (settings.lamda_proto > 0) {
      loss = loss + settings.lamda_proto * F::cross_entropy(classifier->forward(old_means, seen, true), old_labels);
    }
    return loss;
  });
}

}  // namespace fscil
