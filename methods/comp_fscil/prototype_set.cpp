#include "methods/comp_fscil/prototype_set.h"

#include <cmath>

namespace fscil {

PrototypeSetImpl::PrototypeSetImpl(std::int64_t classes, std::int64_t dim, std::int64_t height, std::int64_t width) {
  // nn.Linear's and kaiming_uniform_(a = sqrt 5)'s bound: 1 / sqrt(fan in).
  const double row_bound = 1.0 / std::sqrt(static_cast<double>(dim));
  const double map_bound = 1.0 / std::sqrt(static_cast<double>(dim * height * width));
  rows = register_parameter("rows", torch::empty({classes, dim}).uniform_(-row_bound, row_bound));
  maps = register_parameter("maps", torch::empty({classes, dim, height, width}).uniform_(-map_bound, map_bound));
}

LearnedScaleImpl::LearnedScaleImpl(double start) { value = register_parameter("value", torch::tensor(start)); }

}  // namespace fscil
