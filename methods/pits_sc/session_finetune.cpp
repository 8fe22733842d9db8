#include "methods/pits_sc/session_finetune.h"

namespace fscil {

double finetune_session_rows(StochasticClassifier& classifier, const torch::Tensor& support_embeddings,
                             const torch::Tensor& support_labels, const torch::Tensor& old_means,
                             std::int64_t seen, const SessionFinetuneSettings& settings) {
  namespace F = torch::nn::functional;
  torch::optim::SGD optimizer({classifier->mu, classifier->sigma},
                              torch::optim::SGDOptions(settings.learning_rate).momentum(0.9).dampening(0.9));
  const torch::Tensor old_labels = torch::arange(old_means.size(0), torch::kLong);
  classifier->train();
  double last = 0;
  for (int step = 0; step < settings.steps; ++step) {
    torch::Tensor loss = (1 - settings.lamda_proto) *
                         F::cross_entropy(classifier->forward(support_embeddings, seen, true), support_labels);
    if (settings.lamda_proto > 0) {
      loss = loss + settings.lamda_proto * F::cross_entropy(classifier->forward(old_means, seen, true), old_labels);
    }
    optimizer.zero_grad();
    loss.backward();
    optimizer.step();
    last = loss.item<double>();
  }
  classifier->eval();
  return last;
}

}  // namespace fscil
