#include "methods/orco/pseudo_targets.h"

#include <ATen/CPUGeneratorImpl.h>

#include "methods/common/hungarian_assignment.h"
#include "methods/orco/orco_losses.h"

namespace fscil {

namespace F = torch::nn::functional;

torch::Tensor make_pseudo_targets(std::int64_t count, std::int64_t dimension, int steps, double learning_rate,
                                  std::mt19937_64& generator) {
  const at::Generator source = at::detail::createCPUGenerator(generator());
  torch::Tensor points =
      F::normalize(torch::randn({count, dimension}, source, torch::kFloat), F::NormalizeFuncOptions().dim(1));
  points.set_requires_grad(true);
  torch::optim::SGD optimizer({points}, torch::optim::SGDOptions(learning_rate));
  for (int step = 0; step < steps; ++step) {
    optimizer.zero_grad();
    spread_loss(points).backward();
    optimizer.step();
    torch::NoGradGuard no_grad;
    points.copy_(F::normalize(points, F::NormalizeFuncOptions().dim(1)));
  }
  return points.detach().clone();
}


std::vector<std::int64_t> assign_to_targets(const torch::Tensor& class_means, const torch::Tensor& targets,
                                            const std::vector<std::int64_t>& free_targets) {
  const torch::Tensor candidates = targets.index_select(0, torch::tensor(free_targets, torch::kLong));
  const torch::Tensor cosine =
      F::normalize(class_means, F::NormalizeFuncOptions().dim(1))
          .matmul(F::normalize(candidates, F::NormalizeFuncOptions().dim(1)).t())
          .to(torch::kDouble)
          .contiguous();
  std::vector<std::vector<double>> score(static_cast<std::size_t>(cosine.size(0)));
  const auto values = cosine.accessor<double, 2>();
  for (std::int64_t i = 0; i < cosine.size(0); ++i) {
    for (std::int64_t j = 0; j < cosine.size(1); ++j) score[static_cast<std::size_t>(i)].push_back(values[i][j]);
  }
  std::vector<std::int64_t> chosen;
  for (std::size_t column : max_score_assignment(score)) chosen.push_back(free_targets[column]);
  return chosen;
}

}  // namespace fscil
