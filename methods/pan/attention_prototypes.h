#pragma once
#include <torch/torch.h>

#include <cstdint>

#include "methods/pan/pan_attention.h"

namespace fscil {

// PAN's attention prototypes (AP; vinceasvp/FCAC models/stdu/Network.py L52-L69, L97-L106 and
// incremental_train_helper.py L66-L68 at 9f784713), as released. For query n the tokens
// [s_1 .. s_S, x_n] pass through `attention` (`transatt_proto`), giving outputs O_n and raw scores
// R_n; support j's weight is the softmax of l_j = R_n[j, S] (not scaled by 1/sqrt(D)) over the
// supports of its group g = j mod W, W = S / shot; slot g becomes sum_j w_j O_n[j].
// `supports` is S x D in the release's order (the episode's base part then its novel part, each
// sample-major: index = shot x ways + class slot), so that group g mixes the shots of two classes as
// the release's does. Returns N x W x D.
torch::Tensor attention_prototypes(PanAttention& attention, const torch::Tensor& supports, const torch::Tensor& queries,
                                   std::int64_t shot);

// The release writes the attention prototypes over the class means through `.data`
// (Network.py L64-L69): the forward sees `replacement`, the gradient goes to `means` as if it had
// been used. Exact in the forward: replacement + (means - means) adds zeros.
inline torch::Tensor straight_through(const torch::Tensor& means, const torch::Tensor& replacement) {
  return replacement.detach() + (means - means.detach());
}

}  // namespace fscil
