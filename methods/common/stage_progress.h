#pragma once
#include <torch/torch.h>

#include <functional>
#include <string>

#include "methods/common/shared_stage.h"
#include "methods/method.h"

namespace fscil {

// What a long base stage keeps at its epoch boundaries (RunContext::stage_progress), so that a run
// stopped within it continues from the last epoch kept as if it had not stopped: the modules it
// trains (parameters and buffers), its optimiser's momentum, whatever else it accumulates
// (`save_more`, given back by `take_more`: a statistic bank, loss means), and what every stage
// carries (both random streams, the training log, the diagnostics and the session clock). Kept
// only where the last epoch is kept (RunContext::selection): a kept best epoch is not part of it.
struct StageKeeping {
  StageModules modules;  // empty: the stage keeps nothing
  std::function<void(MethodState&)> save_more;
  std::function<void(const MethodState&)> take_more;
};

// Where a stage stands when it begins: 0 epochs done, or those of the progress kept.
struct StageResumption {
  int epochs_done = 0;
  bool finished = false;  // the stage had ended: nothing of it is to run again
  double last_loss = 0;   // the mean loss of its last epoch done, for loops that return it
};

// The progress of `stage` (of `epochs` at most) kept by an earlier process of this run, written
// back into the modules, `optimizer`, the extras and `context`; {0, false, 0} and nothing changed
// when none is kept. MethodError naming the file when the progress does not fit the run.
StageResumption resume_stage(const std::string& stage, int epochs, const StageKeeping& keeping,
                             torch::optim::SGD& optimizer, RunContext& context);
// After an epoch of `stage`: keeps where it stands when a keeping is due, and always once it has
// finished (so a run stopped in a later stage never trains this one again). A stop (SIGTERM) within
// an epoch keeps nothing: the run continues from the last keeping. A keeping that cannot be
// written is noted and the run goes on.
void keep_stage_progress(const std::string& stage, const StageKeeping& keeping, const torch::optim::SGD& optimizer,
                         const StageResumption& now, RunContext& context);

// An SGD optimiser's momentum buffers into `state` under `prefix` (by parameter position), and back
// into an optimiser over the same parameters; MethodError when one does not fit.
void put_momentum(MethodState& state, const std::string& prefix, const torch::optim::SGD& optimizer);
void take_momentum(const MethodState& state, const std::string& prefix, torch::optim::SGD& optimizer);

}  // namespace fscil
