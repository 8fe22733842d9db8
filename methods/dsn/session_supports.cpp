#include "methods/dsn/session_supports.h"

#include <string>

namespace fscil {

void SessionSupportsImpl::add_session(const torch::Tensor& branch, const torch::Tensor& rows) {
  const std::string number = std::to_string(sessions() + 1);
  branches_.push_back(register_parameter("branch" + number, branch.detach().clone()));
  heads_.push_back(register_parameter("head" + number, rows.detach().clone()));
  gates_.push_back(register_buffer("gate" + number, torch::zeros({branch.size(0)})));
}

torch::Tensor SessionSupportsImpl::branch_cosines(int session, const torch::Tensor& embeddings) const {
  return row_cosines(embeddings, branches_.at(session - 1));
}

torch::Tensor SessionSupportsImpl::node(const torch::Tensor& projected, const torch::Tensor& branch_cosines,
                                        const torch::Tensor& gate, double gamma) {
  return dsn_l2_norm(gamma * projected + branch_cosines * gate);
}

torch::Tensor SessionSupportsImpl::head_cosines(int session, const torch::Tensor& projected,
                                                const torch::Tensor& branch_cosines, const torch::Tensor& gate,
                                                double gamma) const {
  return row_cosines(node(projected, branch_cosines, gate, gamma), heads_.at(session - 1));
}

torch::Tensor training_gate(const torch::Tensor& branch_cosines, int epoch) {
  return torch::sigmoid((1.0 + epoch) * branch_cosines.mean(0));
}

torch::Tensor dsn_cosines(const DsnHeadImpl& head, const SessionSupportsImpl& supports, const torch::Tensor& embeddings,
                          double gamma, int sessions, const torch::Tensor& newest_gate) {
  const torch::Tensor projected = head.project(embeddings);
  std::vector<torch::Tensor> parts{head.base_cosines(projected)};
  for (int session = 1; session <= sessions; ++session) {
    const bool newest = session == sessions && newest_gate.defined();
    parts.push_back(supports.head_cosines(session, projected, supports.branch_cosines(session, embeddings),
                                          newest ? newest_gate : supports.gate(session), gamma));
  }
  return torch::cat(parts, 1);
}

}  // namespace fscil
