#pragma once
#include <torch/torch.h>

#include <functional>
#include <string>
#include <vector>

namespace fscil {

// The session update of PITS-SC's release and of the methods written on its code (ADBS, PAN):
// `steps` full-batch steps of torch.optim.SGD(lr, momentum=0.9, dampening=0.9), no weight decay,
// over `parameters`, each minimising `loss()`. After each step: `after_step(step, loss)` (1-based),
// a requested stop (core/stop_request.h), and a MethodError naming `what` when the loss is not
// finite. Returns the last step's loss.
double damped_momentum_steps(const std::vector<torch::Tensor>& parameters, int steps, double learning_rate,
                             const std::function<torch::Tensor()>& loss, const std::string& what,
                             const std::function<void(int, double)>& after_step = {});

}  // namespace fscil
