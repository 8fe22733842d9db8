#include "methods/pa_pct/session_attention_step.h"

#include "methods/pan/prototype_query_attention.h"

namespace fscil {

torch::Tensor session_attention_loss(const std::function<torch::Tensor(const torch::Tensor&)>& attend,
                                     const torch::Tensor& shots, const torch::Tensor& labels,
                                     const std::vector<std::int64_t>& classes, double temperature) {
  std::vector<torch::Tensor> means, firsts;
  for (const std::int64_t cls : classes) {
    const torch::Tensor members = (labels == cls).nonzero().squeeze(1);
    means.push_back(shots.index_select(0, members).mean(0));
    firsts.push_back(shots[members[0].item<std::int64_t>()]);
  }
  const torch::Tensor logits = pqa_logits(attend, torch::stack(means), torch::stack(firsts), temperature);
  return torch::nn::functional::cross_entropy(logits, torch::arange(static_cast<std::int64_t>(classes.size())));
}

}  // namespace fscil
