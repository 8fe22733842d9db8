#include "methods/common/class_members.h"

#include <fmt/format.h>

#include <numeric>

#include "core/error.h"

namespace fscil {

std::vector<std::vector<std::int64_t>> base_class_members(const torch::Tensor& labels, std::int64_t classes) {
  std::vector<std::vector<std::int64_t>> members(static_cast<std::size_t>(classes));
  const torch::Tensor contiguous = labels.contiguous();
  for (std::int64_t i = 0; i < contiguous.size(0); ++i) members.at(contiguous[i].item<std::int64_t>()).push_back(i);
  for (std::int64_t c = 0; c < classes; ++c) {
    if (members[c].empty()) throw MethodError(fmt::format("base class {} has no training samples", c));
  }
  return members;
}

std::vector<std::int64_t> class_range(std::int64_t first, std::int64_t end) {
  std::vector<std::int64_t> classes(static_cast<std::size_t>(end - first));
  std::iota(classes.begin(), classes.end(), first);
  return classes;
}

}  // namespace fscil
