#include "methods/amfo/amfo_head.h"

#include <string>

#include "methods/dsn/dsn_head.h"

namespace fscil {

namespace F = torch::nn::functional;

AmfoHeadImpl::AmfoHeadImpl(std::int64_t embedding_size, std::int64_t first_stage_width, std::int64_t nodes,
                           std::int64_t base_classes) {
  // PyTorch's default Linear initialisation for each, as the release's.
  shallow = register_module("shallow", torch::nn::Linear(first_stage_width, embedding_size));
  fc1 = register_module("fc1", torch::nn::Linear(torch::nn::LinearOptions(embedding_size, nodes).bias(false)));
  positive = register_module("positive", torch::nn::Linear(torch::nn::LinearOptions(nodes, base_classes).bias(false)));
  negative = register_module("negative", torch::nn::Linear(torch::nn::LinearOptions(nodes, base_classes).bias(false)));
}

void NegativeHeadsImpl::add_session(const torch::Tensor& rows) {
  const std::string number = std::to_string(heads_.size() + 1);
  heads_.push_back(register_parameter("head" + number, rows.detach().clone()));
}

HeadCosines amfo_cosines(AmfoHeadImpl& head, const SessionSupportsImpl& supports, const NegativeHeadsImpl& negative_heads,
                         const torch::Tensor& embeddings, const torch::Tensor& first_stage, double gamma,
                         const torch::Tensor& newest_gate) {
  const int sessions = supports.sessions();
  const torch::Tensor projected = F::linear(embeddings, head.fc1->weight);
  const torch::Tensor shallow_projected = sessions == 0 && first_stage.defined()
                                              ? F::linear(head.shallow->forward(first_stage), head.fc1->weight)
                                              : projected;
  std::vector<torch::Tensor> positive{row_cosines(projected, head.positive->weight)};
  std::vector<torch::Tensor> negative{row_cosines(shallow_projected, head.negative->weight)};
  for (int session = 1; session <= sessions; ++session) {
    const torch::Tensor& gate = session == sessions && newest_gate.defined() ? newest_gate : supports.gate(session);
    const torch::Tensor node = SessionSupportsImpl::node(projected, supports.branch_cosines(session, embeddings), gate, gamma);
    positive.push_back(row_cosines(node, supports.head(session)));
    negative.push_back(row_cosines(node, negative_heads.head(session)));
  }
  return {torch::cat(positive, 1), torch::cat(negative, 1)};
}

}  // namespace fscil
