#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <vector>

#include "methods/dsn/session_supports.h"

namespace fscil {

// AMFO's classifier over the encoder (models/AMFO.py L18-L33 at 7ea36354; models/backbone/Resnet.py
// L187, L241-L244 at f86d0844): `shallow` maps the pooled first-stage feature to the embedding's
// width (the release's fc_n, with bias), `fc1` projects either feature to the nodes (bias-free,
// not normalised), and two base heads score the projection by cosine: `positive` (fc2, trained
// with a positive margin) and `negative` (fc2_n, a negative margin). Sessions never train it.
class AmfoHeadImpl : public torch::nn::Module {
 public:
  AmfoHeadImpl(std::int64_t embedding_size, std::int64_t first_stage_width, std::int64_t nodes, std::int64_t base_classes);

  torch::nn::Linear shallow{nullptr}, fc1{nullptr}, positive{nullptr}, negative{nullptr};
};
TORCH_MODULE(AmfoHead);

// Each session's negative-margin head (fc_n{s}, AMFO.py L31), numbered from 1: saved as
// negative_heads.head{s}. The session's positive head (fc{s}), support branch (fc_aux{s}) and gate
// live in SessionSupports, as DSN's, which AMFO's code is built on: supports.head{s},
// supports.branch{s}, supports.gate{s}.
class NegativeHeadsImpl : public torch::nn::Module {
 public:
  void add_session(const torch::Tensor& rows);
  torch::Tensor& head(int session) { return heads_.at(session - 1); }
  const torch::Tensor& head(int session) const { return heads_.at(session - 1); }

 private:
  std::vector<torch::Tensor> heads_;
};
TORCH_MODULE(NegativeHeads);

// The two heads' cosines over every class of sessions 0..`sessions`, in class order.
struct HeadCosines {
  torch::Tensor positive, negative;
};

// AMFO.py forward (L63-L117): u = fc1 x on the deep feature x, unnormalised. The base columns:
// positive cos(u, fc2); negative cos(fc1 shallow(first stage), fc2_n) while no session has been
// learned and `first_stage` is given, otherwise cos(u, fc2_n): from the first session on the
// release feeds the deep feature to that branch too (L70-L72). Each session s: the node
// l2n(gamma u + gate_s x cos(x, branch_s)) scored by its positive and its negative head; every
// stored gate is used, except that `newest_gate`, when defined, replaces the newest session's.
HeadCosines amfo_cosines(AmfoHeadImpl& head, const SessionSupportsImpl& supports, const NegativeHeadsImpl& negative_heads,
                         const torch::Tensor& embeddings, const torch::Tensor& first_stage, double gamma,
                         const torch::Tensor& newest_gate = {});

}  // namespace fscil
