#pragma once
#include <string>
#include <vector>

#include "tools/fscil-bench/commands/run_command.h"

namespace fscil {

// `fscil-bench run-cells --jobs J`: every cell of the command (tools/fscil-bench/cells/bench_cells.h) as a child
// process `executable ... --cell K`, J at a time, the threads (--threads, or every core) split
// evenly between them, the longest cells first (by this machine's estimate) when J > 1; each
// child's output in OUT/cell-logs/cell-K.log. A cell that needs a stage another cell is training
// waits for it through the stage cache (StageCache::claim) instead of training it too. Then the command's
// tables, as the command itself writes them. A stop (SIGTERM, SIGINT) is passed on to the
// running children, which keep their checkpoints; CliError names every cell that failed.
std::string run_cells(const RunOptions& options, const std::vector<std::string>& grid, int jobs,
                      const std::string& executable);

// Threads per cell when `jobs` cells share `threads` (0: every core): at least 1.
int threads_per_cell(int threads, int jobs);

}  // namespace fscil
