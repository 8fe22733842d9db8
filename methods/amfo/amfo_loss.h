#pragma once
#include <torch/torch.h>

#include <cstdint>

#include "methods/amfo/fusion_net.h"

namespace fscil {

// CosFace (AngularPenaltySMLoss, models/AMFO.py L168-L213 at 7ea36354): cross-entropy of
// s x cosines with the target class's cosine lowered by `margin` first, s (cos_y - m); a negative
// margin makes the target easier.
torch::Tensor cosface_loss(const torch::Tensor& cosines, const torch::Tensor& labels, double scale, double margin);

// The weights of one AMFO loss's parts and its constants (AMFO.py get_loss, L129-L151).
struct AmfoLossSettings {
  double fusion = 1, margin = 1, binary = 1;
  double temperature = 16, cosface_scale = 32, positive_margin = 0.1, negative_margin = -0.5;
};

// AMFO's loss in its parts. Base session (train.py L134): the first three; sessions
// (Inc_train.py L451) all five.
struct AmfoLoss {
  torch::Tensor margin;        // margin weight x (CosFace(positive, m_p) + CosFace(negative, m_n))
  torch::Tensor fusion;        // fusion weight x CE(temperature x mixed)
  torch::Tensor binary;        // binary weight x CE(temperature x b, label >= base classes)
  torch::Tensor distillation;  // soft-target CE to the network before the session: no gradient here (see .cpp)
  torch::Tensor sparsity;      // 0.1 x relu(mean gate - r), counted twice (alpha and alpha_n are equal)
  torch::Tensor total() const { return margin + fusion + binary + distillation + sparsity; }
};

// `positive`, `negative`: the two heads' cosines over the seen classes; `fusion`: fuse() of them;
// `base_classes`: labels from there on are "novel" for the binary target.
AmfoLoss amfo_loss(const torch::Tensor& positive, const torch::Tensor& negative, const Fusion& fusion,
                   const torch::Tensor& labels, std::int64_t base_classes, const AmfoLossSettings& weights);

// The session's extra terms: the distillation of `positive`'s first `teacher_cosines.size(1)`
// columns to the network before the session (AMFO.py L144-L145, L154-L164), and the gate penalty
// (L147-L151) when `gate` is defined (the batch held a row of the session's classes).
void add_session_terms(AmfoLoss& loss, const torch::Tensor& positive, const torch::Tensor& teacher_cosines,
                       double temperature, const torch::Tensor& gate, double sparsity_floor);

}  // namespace fscil
