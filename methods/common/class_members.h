#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <vector>

namespace fscil {

// Per class c of [0, classes): the indices of its samples in `labels`, in order. Throws
// MethodError "base class c has no training samples" for the first class that has none: the
// episode samplers of the base session draw from every class.
std::vector<std::vector<std::int64_t>> base_class_members(const torch::Tensor& labels, std::int64_t classes);

// The classes first, first + 1, ..., end - 1 (class_means' list of classes).
std::vector<std::int64_t> class_range(std::int64_t first, std::int64_t end);

}  // namespace fscil
