#pragma once
#include <set>
#include <string>
#include <vector>

#include "methods/common/step_rate.h"
#include "methods/method_registry.h"
#include "tools/fscil-bench/cells/bench_cells.h"
#include "tools/fscil-bench/commands/run_command.h"

namespace fscil {

class ParameterSet;

// This machine's rates for the command (methods/common/step_rate.h): from `step_rates.json` in
// its cache folder when that holds this CPU, kernels, threads, shape and batch; otherwise
// measured now (seconds; some 20 on the audio shapes) and stored there, unless the process had
// less than 90% of its threads' CPU time meanwhile (other work, or a host taking the VM's time:
// used for this plan, not kept), under --no-cache, or where the folder cannot be written. An
// entry that does not read is measured over.
StepRate machine_rates(const CommandSizes& sizes);
// The entry of `step_rates.json` that holds them; its leading version changes whenever what
// measure_step_rate() times changes.
std::string step_rates_key(const CommandSizes& sizes);

// One run's seconds at `rates`: its stages (MethodEntry::work) and what the runner does for every
// method: embedding the scored samples (once per run where the entry's sessions keep the
// embedding, every session otherwise) and the eight timed inference passes. A stage of the base
// session is left out when `base_trained` (a method of its cell with the same shared_base_key
// trained it); a stage the entry names in shared_stages is left out when `trained_stages` holds
// it, and added there otherwise (a later cell of the same seed continues from it).
double run_seconds(const MethodEntry& entry, const ParameterSet& read, const RunSizes& sizes, const StepRate& rates,
                   bool base_trained, std::set<std::string>& trained_stages);

// Fills every cell's estimated_seconds on this machine; prepares the dataset as the command would
// (from the cache, or built and cached). `one_after_another`: cells run in plan order in one
// place, so a later cell continues from a shared stage an earlier one trained (a whole command;
// cells run apart share it through the stage cache); otherwise (Slurm tasks at once), under a
// --selection other than last (no stage is shared then), --no-stage-cache or --no-cache, every
// cell trains its own.
void estimate_cells(const RunOptions& options, const std::vector<std::string>& grid, std::vector<BenchCell>& cells,
                    bool one_after_another = true);

}  // namespace fscil
