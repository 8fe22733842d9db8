#include "methods/pan/prototype_query_attention.h"

#include <vector>

namespace fscil {

namespace F = torch::nn::functional;

torch::Tensor pqa_logits(PanAttention& attention, const torch::Tensor& prototypes, const torch::Tensor& queries,
                         double temperature, std::int64_t chunk) {
  return pqa_logits([&](const torch::Tensor& tokens) { return attention->forward(tokens).tokens; }, prototypes, queries,
                    temperature, chunk);
}

torch::Tensor pqa_logits(const std::function<torch::Tensor(const torch::Tensor&)>& attend, const torch::Tensor& prototypes,
                         const torch::Tensor& queries, double temperature, std::int64_t chunk,
                         torch::Tensor* adapted_rows) {
  const bool shared = prototypes.dim() == 2;
  const std::int64_t classes = prototypes.size(shared ? 0 : 1), dim = prototypes.size(-1);
  std::vector<torch::Tensor> parts;
  for (std::int64_t first = 0; first < queries.size(0); first += chunk) {
    const std::int64_t n = std::min(chunk, queries.size(0) - first);
    const torch::Tensor own = shared ? prototypes.unsqueeze(0).expand({n, classes, dim})
                                     : prototypes.slice(0, first, first + n);
    const torch::Tensor tokens = torch::cat({own, queries.slice(0, first, first + n).unsqueeze(1)}, 1);
    const torch::Tensor out = attend(tokens);
    if (adapted_rows != nullptr) {
      const torch::Tensor sum = out.slice(1, 0, classes).sum(0);
      *adapted_rows = first == 0 ? sum : *adapted_rows + sum;
    }
    const torch::Tensor rows = F::normalize(out.slice(1, 0, classes), F::NormalizeFuncOptions().dim(-1));
    const torch::Tensor query = F::normalize(out.select(1, classes), F::NormalizeFuncOptions().dim(-1));
    parts.push_back(temperature * torch::bmm(rows, query.unsqueeze(2)).squeeze(2));
  }
  if (adapted_rows != nullptr) *adapted_rows = *adapted_rows / static_cast<double>(queries.size(0));
  return torch::cat(parts);
}

}  // namespace fscil
