#include "methods/pits_sc/session_finetune.h"

#include <fmt/format.h>

#include <cmath>

#include "core/error.h"
#include "methods/diverged_training.h"
#include "core/stop_request.h"

namespace fscil {

namespace F = torch::nn::functional;

double finetune_classifier_rows(StochasticClassifier& classifier, const SessionFinetuneSettings& settings,
                                const std::function<torch::Tensor()>& loss) {
  torch::optim::SGD optimizer({classifier->mu, classifier->sigma},
                              torch::optim::SGDOptions(settings.learning_rate).momentum(0.9).dampening(0.9));
  classifier->train();
  double last = 0;
  for (int step = 0; step < settings.steps; ++step) {
    const torch::Tensor value = loss();
    optimizer.zero_grad();
    value.backward();
    optimizer.step();
    stop_if_requested();
    last = value.item<double>();
    if (!std::isfinite(last)) {
      throw MethodError(diverged_training(fmt::format("session fine-tuning step {} of {}", step + 1, settings.steps),
                                          {{"loss", last}, {"lr", settings.learning_rate}}));
    }
  }
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
