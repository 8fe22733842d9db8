#include "methods/common/shared_stage.h"

#include "methods/common/module_state.h"
#include "methods/common/torch_random_state.h"

namespace fscil {

bool stages_shareable(const RunContext& context) {
  return context.stages != nullptr && context.selection == EpochSelection::last;
}

TrainedStage file_stage(const RunContext& context, const StageModules& modules) {
  TrainedStage stage{{}, context.generator, torch_random_state(), context.training_log, context.diagnostics,
                     context.session_clock.seconds()};
  for (const auto& [prefix, module] : modules) put_module(stage.state, prefix, *module);
  return stage;
}

void continue_from_stage(const TrainedStage& stage, const StageModules& modules, RunContext& context) {
  for (const auto& [prefix, module] : modules) take_module(stage.state, prefix, *module);
  context.generator = stage.generator;
  restore_torch_random_state(stage.torch_random_state);
  context.training_log.insert(context.training_log.begin(), stage.training_log.begin(), stage.training_log.end());
  context.diagnostics.insert(stage.diagnostics.begin(), stage.diagnostics.end());
  context.session_clock = Stopwatch::started_seconds_ago(stage.seconds);
}

void train_or_take_stage(const std::string& stage, const StageModules& modules, RunContext& context,
                         const std::function<void()>& train) {
  const bool shareable = stages_shareable(context);
  if (shareable) {
    if (const std::optional<TrainedStage> kept = context.stages->find(stage)) {
      continue_from_stage(*kept, modules, context);
      return;
    }
  }
  train();
  if (shareable) context.stages->store(stage, file_stage(context, modules));
}

}  // namespace fscil
