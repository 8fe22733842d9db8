#include "methods/common/embedding.h"

#include <fmt/format.h>

#include "methods/method.h"

namespace fscil {

namespace F = torch::nn::functional;

torch::Tensor embed_in_batches(ResNet18Encoder& encoder, const SampleRows& features, std::int64_t batch_size,
                               const InputNormHook& after_input_norm) {
  torch::NoGradGuard no_grad;
  const bool was_training = encoder->is_training();
  encoder->eval();
  const torch::Tensor embeddings = map_batches(
      features, batch_size, [&](const torch::Tensor& batch) { return encoder->forward(batch, after_input_norm); });
  encoder->train(was_training);
  return embeddings;
}

torch::Tensor embed_maps_in_batches(ResNet18Encoder& encoder, const SampleRows& features, std::int64_t batch_size) {
  torch::NoGradGuard no_grad;
  const bool was_training = encoder->is_training();
  encoder->eval();
  const torch::Tensor maps =
      map_batches(features, batch_size, [&](const torch::Tensor& batch) { return encoder->forward_map(batch).contiguous(); });
  encoder->train(was_training);
  return maps;
}

torch::Tensor class_means(const torch::Tensor& embeddings, const torch::Tensor& labels,
                          const std::vector<std::int64_t>& classes) {
  std::vector<torch::Tensor> means;
  for (std::int64_t label : classes) {
    const torch::Tensor mask = labels == label;
    if (mask.sum().item<std::int64_t>() == 0) throw MethodError(fmt::format("class {} has no samples to average", label));
    means.push_back(embeddings.index({mask}).mean(0));
  }
  return torch::stack(means);
}

torch::Tensor normalized_class_means(const torch::Tensor& embeddings, const torch::Tensor& labels,
                                     const std::vector<std::int64_t>& classes) {
  return class_means(F::normalize(embeddings, F::NormalizeFuncOptions().dim(1)), labels, classes);
}

}  // namespace fscil
