#pragma once
#include <torch/torch.h>

#include <functional>

#include "methods/common/named_module.h"
#include "metrics/model_cost.h"

namespace fscil {

// The inference cost of a forward pass no cost walker knows (module_cost.h walks ours), from the
// ATen operations `forward` runs on one sample as the dispatcher reports them with their inputs
// and outputs, by metrics/model_cost.h's rules:
// - convolutions of any dimension, transposed too, with their bias;
// - matrix products (mm, addmm, bmm, baddbmm, mv, addmv, dot; so linear, matmul and einsum)
//   and cdist: output elements x the length they sum over;
// - batch, layer, group and instance norm: 1 per input element;
// - pooling: kernel area per output; adaptive pooling: every input element.
// An operation inside a counted one (conv2d's backend kernel) is its own; element-wise operations
// count 0, as ours do, so a norm applied by hand as a broadcast scale and shift counts 0 too.
// `modules` give the parameters, trained in sessions as each module says.
ModelCost traced_cost(const std::function<void()>& forward, const NamedModules& modules);

}  // namespace fscil
