#pragma once
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "methods/method.h"

namespace fscil {

// A base stage that several methods train alike (MethodEntry::shared_stages), as a method files
// it in RunContext::stages and takes it back: `modules` (prefix, module) are copied in and out;
// the random streams, training log, diagnostics and clock go with them, so that a run taking the
// stage continues exactly as one that trained it.
using StageModules = std::vector<std::pair<std::string, torch::nn::Module*>>;

// Whether a run may take or file a shared stage: where the runner keeps them, and only when every
// epoch kept is the last (a selection keeps epochs by scores the sharing methods need not compute
// alike, and a kept epoch may span stages).
bool stages_shareable(const RunContext& context);
// The stage as `context` stands after it, with copies of `modules`.
TrainedStage file_stage(const RunContext& context, const StageModules& modules);
// `stage` written into `modules` and `context`, as if the run had just trained it.
void continue_from_stage(const TrainedStage& stage, const StageModules& modules, RunContext& context);
// The stage named `stage`: taken from the store when it holds one, else trained by `train` and
// filed for the others (both only where stages_shareable()).
void train_or_take_stage(const std::string& stage, const StageModules& modules, RunContext& context,
                         const std::function<void()>& train);

}  // namespace fscil
