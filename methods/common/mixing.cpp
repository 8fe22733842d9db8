#include "methods/common/mixing.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/random_draws.h"
#include "core/seeded_shuffle.h"

namespace fscil {

CutMixPlan plan_cutmix(std::int64_t batch, std::int64_t height, std::int64_t width, double alpha,
                       std::mt19937_64& generator) {
  const double lambda = beta(generator, alpha, alpha);
  const double cut = std::sqrt(1.0 - lambda);
  const auto cut_h = static_cast<std::int64_t>(static_cast<double>(height) * cut);
  const auto cut_w = static_cast<std::int64_t>(static_cast<double>(width) * cut);
  const std::int64_t centre_h = uniform_int(generator, 0, height - 1);
  const std::int64_t centre_w = uniform_int(generator, 0, width - 1);
  CutMixPlan plan;
  plan.top = std::clamp(centre_h - cut_h / 2, std::int64_t{0}, height);
  plan.bottom = std::clamp(centre_h + cut_h / 2, std::int64_t{0}, height);
  plan.left = std::clamp(centre_w - cut_w / 2, std::int64_t{0}, width);
  plan.right = std::clamp(centre_w + cut_w / 2, std::int64_t{0}, width);

  std::vector<std::int64_t> order(static_cast<std::size_t>(batch));
  std::iota(order.begin(), order.end(), 0);
  shuffle_with(order, generator);
  plan.partners = torch::tensor(order);
  plan.kept_fraction = 1.0 - static_cast<double>((plan.bottom - plan.top) * (plan.right - plan.left)) /
                                 static_cast<double>(height * width);
  return plan;
}

torch::Tensor CutMixPlan::apply(const torch::Tensor& maps) const {
  torch::Tensor mixed = maps.clone();
  if (bottom > top && right > left) {
    using torch::indexing::Slice;
    const std::vector<torch::indexing::TensorIndex> box = {Slice(), Slice(), Slice(top, bottom), Slice(left, right)};
    mixed.index_put_(box, maps.index_select(0, partners).index(box));
  }
  return mixed;
}

}  // namespace fscil
