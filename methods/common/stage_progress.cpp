#include "methods/common/stage_progress.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>

#include "methods/common/module_state.h"

namespace fscil {

namespace {

constexpr const char* kMomentum = "progress.momentum.";
constexpr const char* kEpochsDone = "progress.epochs_done";
constexpr const char* kFinished = "progress.finished";
constexpr const char* kLastLoss = "progress.last_loss";

bool keeps_progress(const StageKeeping& keeping, const RunContext& context) {
  return !keeping.modules.empty() && context.stage_progress != nullptr && context.selection == EpochSelection::last;
}

// The optimiser's parameters in a fixed order: group by group, as they were given.
std::vector<torch::Tensor> optimised_parameters(const torch::optim::SGD& optimizer) {
  std::vector<torch::Tensor> parameters;
  for (const auto& group : optimizer.param_groups()) {
    for (const auto& parameter : group.params()) parameters.push_back(parameter);
  }
  return parameters;
}

// The key torch::optim keeps a parameter's state under.
std::string state_key(const torch::Tensor& parameter) { return c10::guts::to_string(parameter.unsafeGetTensorImpl()); }

}  // namespace

void put_momentum(MethodState& state, const std::string& prefix, const torch::optim::SGD& optimizer) {
  const std::vector<torch::Tensor> parameters = optimised_parameters(optimizer);
  for (std::size_t i = 0; i < parameters.size(); ++i) {
    const auto found = optimizer.state().find(state_key(parameters[i]));
    if (found == optimizer.state().end()) continue;  // no step has reached it yet
    const auto& sgd = static_cast<const torch::optim::SGDParamState&>(*found->second);
    if (sgd.momentum_buffer().defined()) state[prefix + std::to_string(i)] = sgd.momentum_buffer().detach().clone();
  }
}

void take_momentum(const MethodState& state, const std::string& prefix, torch::optim::SGD& optimizer) {
  const std::vector<torch::Tensor> parameters = optimised_parameters(optimizer);
  for (const auto& [key, saved] : state) {
    if (key.rfind(prefix, 0) != 0) continue;
    const std::string position = key.substr(prefix.size());
    std::size_t i = 0;
    try {
      i = std::stoul(position);
    } catch (const std::exception&) {
      throw MethodError(fmt::format("state '{}': expected a parameter position after '{}'", key, prefix));
    }
    if (i >= parameters.size() || saved.sizes() != parameters[i].sizes()) {
      throw MethodError(fmt::format("state '{}' does not fit the optimiser's {} parameters", key, parameters.size()));
    }
    auto momentum = std::make_unique<torch::optim::SGDParamState>();
    momentum->momentum_buffer(saved.clone());
    optimizer.state()[state_key(parameters[i])] = std::move(momentum);
  }
}

StageResumption resume_stage(const std::string& stage, int epochs, const StageKeeping& keeping,
                             torch::optim::SGD& optimizer, RunContext& context) {
  if (!keeps_progress(keeping, context)) return {};
  const std::optional<TrainedStage> kept = context.stage_progress->find(stage);
  if (!kept) return {};
  StageResumption resumed;
  try {
    const auto one_value = [&](const char* key) {
      const torch::Tensor& value = take(kept->state, key);
      if (value.numel() != 1) throw MethodError(fmt::format("state '{}': expected one value", key));
      return value;
    };
    resumed = {static_cast<int>(std::clamp<std::int64_t>(one_value(kEpochsDone).item<std::int64_t>(), -1, epochs + 1)),
               one_value(kFinished).item<bool>(), one_value(kLastLoss).item<double>()};
    if (resumed.epochs_done < 0 || resumed.epochs_done > epochs) {
      throw MethodError(fmt::format("{} epochs done of a stage of {}", resumed.epochs_done, epochs));
    }
    // The kept training log and diagnostics are the session's so far, the stages before this one included.
    context.training_log.clear();
    context.diagnostics.clear();
    continue_from_stage(*kept, keeping.modules, context);
    take_momentum(kept->state, kMomentum, optimizer);
    if (keeping.take_more) keeping.take_more(kept->state);
  } catch (const std::exception& error) {  // MethodError, or LibTorch's about a tensor
    throw MethodError(fmt::format("{}: progress of stage '{}' that does not fit this run ({}); delete it to train "
                                  "that stage again", context.stage_progress->origin(stage), stage, error.what()));
  }
  if (context.progress != nullptr) {
    context.progress->note(fmt::format("{}: continuing after epoch {}, kept by an earlier process of this run", stage,
                                       resumed.epochs_done));
  }
  return resumed;
}

void keep_stage_progress(const std::string& stage, const StageKeeping& keeping, const torch::optim::SGD& optimizer,
                         const StageResumption& now, RunContext& context) {
  if (!keeps_progress(keeping, context) || (!now.finished && !context.stage_progress->due())) return;
  TrainedStage progress = file_stage(context, keeping.modules);
  put_momentum(progress.state, kMomentum, optimizer);
  if (keeping.save_more) keeping.save_more(progress.state);
  progress.state[kEpochsDone] = torch::tensor(static_cast<std::int64_t>(now.epochs_done));
  progress.state[kFinished] = torch::tensor(now.finished);
  progress.state[kLastLoss] = torch::tensor(now.last_loss, torch::kDouble);
  try {
    context.stage_progress->store(stage, progress);
  } catch (const std::exception& error) {  // a full disk costs the chance to continue, never the run
    if (context.progress != nullptr) context.progress->note(fmt::format("{}: progress not kept: {}", stage, error.what()));
  }
}

}  // namespace fscil
