#include "methods/common/damped_momentum_steps.h"

#include <fmt/format.h>

#include <cmath>

#include "core/error.h"
#include "core/stop_request.h"
#include "methods/diverged_training.h"

namespace fscil {

double damped_momentum_steps(const std::vector<torch::Tensor>& parameters, int steps, double learning_rate,
                             const std::function<torch::Tensor()>& loss, const std::string& what,
                             const std::function<void(int, double)>& after_step) {
  torch::optim::SGD optimizer(parameters, torch::optim::SGDOptions(learning_rate).momentum(0.9).dampening(0.9));
  double last = 0;
  for (int step = 0; step < steps; ++step) {
    const torch::Tensor value = loss();
    optimizer.zero_grad();
    value.backward();
    optimizer.step();
    stop_if_requested();
    last = value.item<double>();
    if (!std::isfinite(last)) {
      throw MethodError(diverged_training(fmt::format("{} step {} of {}", what, step + 1, steps),
                                          {{"loss", last}, {"lr", learning_rate}}));
    }
    if (after_step) after_step(step + 1, last);
  }
  return last;
}

}  // namespace fscil
