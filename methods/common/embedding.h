#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <vector>

#include "methods/common/resnet18.h"
#include "methods/sample_rows.h"

namespace fscil {

// Embeds in eval mode without gradients, in batches to bound memory; restores the train flag.
// `after_input_norm` transforms each batch's map after bn0 (see InputNormHook).
torch::Tensor embed_in_batches(ResNet18Encoder& encoder, const SampleRows& features, std::int64_t batch_size = 256,
                               const InputNormHook& after_input_norm = {});

// The same for the encoder's last map before pooling (ResNet18EncoderImpl::forward_map): N x D x h x w.
torch::Tensor embed_maps_in_batches(ResNet18Encoder& encoder, const SampleRows& features, std::int64_t batch_size = 256);

// The embedding with, beside it, the first stage's pooled map (ResNet18EncoderImpl::
// forward_with_first_stage): N x (D + widths[0]), the embedding first.
torch::Tensor embed_with_first_stage_in_batches(ResNet18Encoder& encoder, const SampleRows& features,
                                                std::int64_t batch_size = 256);

// Mean embedding per class, rows in the order of `classes` (any shape per sample).
torch::Tensor class_means(const torch::Tensor& embeddings, const torch::Tensor& labels,
                          const std::vector<std::int64_t>& classes);

// Mean of L2-normalised embeddings per class, rows in the order of `classes`.
torch::Tensor normalized_class_means(const torch::Tensor& embeddings, const torch::Tensor& labels,
                                     const std::vector<std::int64_t>& classes);

}  // namespace fscil
