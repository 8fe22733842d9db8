#include "methods/common/batch_norm_statistics.h"

#include <vector>

namespace fscil {

void reestimate_batch_norm_statistics(torch::nn::Module& module, const SampleRows& data, std::int64_t batch_size,
                                      const std::function<void(const torch::Tensor&)>& forward) {
  torch::NoGradGuard no_grad;
  std::vector<torch::nn::BatchNorm2dImpl*> norms;
  std::vector<c10::optional<double>> momenta;
  for (auto& child : module.modules(/*include_self=*/false)) {
    if (auto* norm = child->as<torch::nn::BatchNorm2d>()) {
      norms.push_back(norm);
      momenta.push_back(norm->options.momentum());
      norm->reset_running_stats();
      norm->options.momentum(c10::nullopt);  // a cumulative average over the batches
    }
  }
  const bool was_training = module.is_training();
  module.train();
  for (std::int64_t first = 0; first < data.count(); first += batch_size) {
    forward(data.range(first, std::min(batch_size, data.count() - first)));
  }
  module.train(was_training);
  for (std::size_t i = 0; i < norms.size(); ++i) norms[i]->options.momentum(momenta[i]);
}

}  // namespace fscil
