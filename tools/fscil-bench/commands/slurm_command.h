#pragma once
#include <string>
#include <vector>

#include "tools/fscil-bench/commands/run_command.h"

namespace fscil {

struct SlurmOptions {
  std::string partition;
  std::string time;        // --time of every task (Slurm's format: 2:00:00, 1-00:00:00)
  int cpus_per_task = 0;   // 0: --threads if given, else 1
  std::string mem;         // --mem of every task (Slurm's format: 8G)
  int max_parallel = 0;    // %K of --array: at most K tasks at once (0: no limit)
  std::vector<std::string> sbatch_arguments;  // more #SBATCH lines, e.g. --account=abc
  bool submit = false;
  bool missing_only = false;  // only the cells without their result files
};

// `fscil-bench slurm`: writes OUT/slurm/array.sbatch (one array task per cell of the command,
// tools/fscil-bench/cells/bench_cells.h, each `executable ... --cell $SLURM_ARRAY_TASK_ID --threads
// $SLURM_CPUS_PER_TASK`, SIGTERM 120 s before a time limit passed on to it, requeued on
// preemption, its log in OUT/cell-logs/) and OUT/slurm/merge.sbatch (fscil-bench report over the
// results, to run after the array); with `submit`, submits both through sbatch, the merge with
// --dependency=afterany on the array. Returns what was written or submitted, job ids included.
std::string run_slurm(const RunOptions& options, const std::vector<std::string>& grid, const SlurmOptions& slurm,
                      const std::string& executable);

// The #SBATCH --array value for the cell indices `cells` (ranges folded: 0-3,5,7-8) and `%K`.
std::string array_range(const std::vector<int>& cells, int max_parallel);

}  // namespace fscil
