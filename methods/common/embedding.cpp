#include "methods/common/embedding.h"

#include <fmt/format.h>

#include <functional>

#include "methods/method.h"

namespace fscil {

namespace F = torch::nn::functional;

namespace {

// Runs `encode` over the samples in batches, in eval mode without gradients; restores the train flag.
torch::Tensor encode_in_eval_batches(ResNet18Encoder& encoder, const SampleRows& features, std::int64_t batch_size,
                                     const std::function<torch::Tensor(const torch::Tensor&)>& encode) {
  torch::NoGradGuard no_grad;
  const bool was_training = encoder->is_training();
  encoder->eval();
  const torch::Tensor encoded = map_batches(features, batch_size, encode);
  encoder->train(was_training);
  return encoded;
}

}  // namespace

torch::Tensor embed_in_batches(ResNet18Encoder& encoder, const SampleRows& features, std::int64_t batch_size,
                               const InputNormHook& after_input_norm) {
  return encode_in_eval_batches(encoder, features, batch_size,
                                [&](const torch::Tensor& batch) { return encoder->forward(batch, after_input_norm); });
}

torch::Tensor embed_maps_in_batches(ResNet18Encoder& encoder, const SampleRows& features, std::int64_t batch_size) {
  return encode_in_eval_batches(encoder, features, batch_size,
                                [&](const torch::Tensor& batch) { return encoder->forward_map(batch).contiguous(); });
}

torch::Tensor embed_with_first_stage_in_batches(ResNet18Encoder& encoder, const SampleRows& features,
                                                std::int64_t batch_size) {
  return encode_in_eval_batches(encoder, features, batch_size, [&](const torch::Tensor& batch) {
    const auto [embedding, first_stage] = encoder->forward_with_first_stage(batch);
    return torch::cat({embedding, first_stage}, 1);
  });
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
