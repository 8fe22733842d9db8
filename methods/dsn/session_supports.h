#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <vector>

#include "methods/dsn/dsn_head.h"

namespace fscil {

// What DSN adds per incremental session (models/DSN.py L27-L34, L64-L79 at 5bc87b96): a support
// branch (an N x D projection that starts as a copy of fc1), the session's head rows, and the gate
// the branch's output is multiplied by (a row of `Alpha`). Sessions are numbered from 1.
class SessionSupportsImpl : public torch::nn::Module {
 public:
  // Registers session sessions() + 1 with `branch` (N x D) and `rows` (its classes x N) and a
  // zero gate, as the release's Alpha rows start (L32-L34).
  void add_session(const torch::Tensor& branch, const torch::Tensor& rows);
  int sessions() const { return static_cast<int>(branches_.size()); }
  std::int64_t classes_of(int session) const { return heads_.at(session - 1).size(0); }

  // a = cos(x, branch rows) on the raw embedding x: N values per sample (L64).
  torch::Tensor branch_cosines(int session, const torch::Tensor& embeddings) const;
  // l2n(gamma u + a * gate) (L77-L78): the session's node, its head scores it.
  static torch::Tensor node(const torch::Tensor& projected, const torch::Tensor& branch_cosines, const torch::Tensor& gate,
                            double gamma);
  // cos(node, head rows) (L79): the session's logits before the temperature.
  torch::Tensor head_cosines(int session, const torch::Tensor& projected, const torch::Tensor& branch_cosines,
                             const torch::Tensor& gate, double gamma) const;

  torch::Tensor& branch(int session) { return branches_.at(session - 1); }
  torch::Tensor& head(int session) { return heads_.at(session - 1); }
  const torch::Tensor& head(int session) const { return heads_.at(session - 1); }
  // The stored gate (N): what the session's support is multiplied by at test (L75-L76).
  torch::Tensor& gate(int session) { return gates_.at(session - 1); }
  const torch::Tensor& gate(int session) const { return gates_.at(session - 1); }

 private:
  std::vector<torch::Tensor> branches_, heads_, gates_;
};
TORCH_MODULE(SessionSupports);

// The training gate of the newest session (L68-L72): sigmoid((1 + epoch) * the batch's mean of a),
// one value per node; `epoch` is 0-based, so the gate sharpens toward 0 or 1 as epochs pass.
torch::Tensor training_gate(const torch::Tensor& branch_cosines, int epoch);

// Cosines of every class of sessions 0..`sessions` in class order: the base rows against u, then
// each session's head through its support. Every session's stored gate is used, except that
// `newest_gate`, when defined, replaces session `sessions`'s (the release's 'train' mode, L68-L74).
torch::Tensor dsn_cosines(const DsnHeadImpl& head, const SessionSupportsImpl& supports, const torch::Tensor& embeddings,
                          double gamma, int sessions, const torch::Tensor& newest_gate = {});

}  // namespace fscil
