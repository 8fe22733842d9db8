#include "methods/common/mixing.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "protocols/seeded_shuffle.h"

namespace fscil {

double sample_beta(double a, double b, std::mt19937_64& generator) {
  const double x = std::gamma_distribution<double>(a, 1.0)(generator);
  const double y = std::gamma_distribution<double>(b, 1.0)(generator);
  return x + y > 0 ? x / (x + y) : 0.5;
}

CutMixBatch cutmix(const torch::Tensor& features, const torch::Tensor& labels, double alpha,
                   std::mt19937_64& generator) {
  const std::int64_t n = features.size(0), height = features.size(2), width = features.size(3);
  const double lambda = sample_beta(alpha, alpha, generator);
  const double cut = std::sqrt(1.0 - lambda);
  const auto cut_h = static_cast<std::int64_t>(static_cast<double>(height) * cut);
  const auto cut_w = static_cast<std::int64_t>(static_cast<double>(width) * cut);
  const std::int64_t centre_h = std::uniform_int_distribution<std::int64_t>(0, height - 1)(generator);
  const std::int64_t centre_w = std::uniform_int_distribution<std::int64_t>(0, width - 1)(generator);
  const std::int64_t top = std::clamp(centre_h - cut_h / 2, std::int64_t{0}, height);
  const std::int64_t bottom = std::clamp(centre_h + cut_h / 2, std::int64_t{0}, height);
  const std::int64_t left = std::clamp(centre_w - cut_w / 2, std::int64_t{0}, width);
  const std::int64_t right = std::clamp(centre_w + cut_w / 2, std::int64_t{0}, width);

  std::vector<std::int64_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  shuffle_with(order, generator);
  const torch::Tensor partners = torch::tensor(order);

  CutMixBatch batch;
  batch.features = features.clone();
  batch.partner_labels = labels.index_select(0, partners);
  if (bottom > top && right > left) {
    using torch::indexing::Slice;
    const std::vector<torch::indexing::TensorIndex> box = {Slice(), Slice(), Slice(top, bottom), Slice(left, right)};
    batch.features.index_put_(box, features.index_select(0, partners).index(box));
  }
  batch.kept_fraction = 1.0 - static_cast<double>((bottom - top) * (right - left)) / static_cast<double>(height * width);
  return batch;
}

}  // namespace fscil
