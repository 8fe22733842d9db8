#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <functional>

namespace fscil {

// ADBS's adaptive decision boundaries: one learnable scalar margin m_c per class of the protocol,
// initialised to 1 (models/adbs/Network.py L30-L31 at 756414c3), that scales the class's cosine
// logit. Tests scale by |m_c| (L38); the session update scales by m_c itself (helper.py L33).
class DecisionBoundariesImpl : public torch::nn::Module {
 public:
  explicit DecisionBoundariesImpl(std::int64_t classes)
      : margin(register_parameter("margin", torch::ones({classes}))) {}
  // Cosine logits of the first `seen` classes scaled by their |m_c|.
  torch::Tensor scale(const torch::Tensor& cosine_logits, std::int64_t seen) const {
    return cosine_logits * margin.slice(0, 0, seen).abs();
  }
  torch::Tensor margin;
};
TORCH_MODULE(DecisionBoundaries);

// The inter-class constraint (IC) loss: mean over every ordered pair (i, j), the diagonal
// included, of relu(D_ij) with D_ij = (1 - w_i.w_j) - (m_j - m_i w_i.w_j) on the L2-normalised
// rows w (helper.py L57-L64, L84-L90). Zero when each class's boundary keeps clear of the others.
torch::Tensor inter_class_constraint(const torch::Tensor& margins, const torch::Tensor& rows);

// One session's update (helper.py L9-L55): only the new classes' margins train, from
// `new_margins`, for `steps` full-batch SGD steps (momentum 0.9, dampening 0.9, no weight decay,
// L15-L18) on CE(cosine_logits x m) + weight x IC(m, rows), where m is `old_margins` (fixed) then
// the new ones. `cosine_logits` are the support's temperature x cosine logits over every seen
// class, `rows` the seen classes' prototypes; neither gets a gradient. `after_step(step, loss)`
// is called after each step (1-based). Returns the trained new margins.
struct MarginUpdate {
  int steps = 10;
  double learning_rate = 0.1;
  double constraint_weight = 0.01;
};
torch::Tensor train_new_margins(const torch::Tensor& cosine_logits, const torch::Tensor& labels,
                                const torch::Tensor& old_margins, const torch::Tensor& new_margins,
                                const torch::Tensor& rows, const MarginUpdate& update,
                                const std::function<void(int, double, double)>& after_step = {});

}  // namespace fscil
