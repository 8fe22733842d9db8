#pragma once
#include <map>
#include <string>
#include <vector>

#include "reports/run_record.h"
#include "tools/fscil-bench/commands/run_command.h"

namespace fscil {

// fscil-bench sweep: the run `options` describes once per cell of the --grid axes (every
// combination of their values), each cell a run command of its own in OUT/cells/KEY=VALUE+.../
// (resumable like a run, the same checkpoints), then the sweep's tables over every cell in OUT,
// with a column per grid key. `selection` as a key sets --selection; any other key is a --set.
// Returns the Markdown tables.
std::string run_sweep(const RunOptions& options, const std::vector<std::string>& grid);

// The run command of one cell of a sweep: its values as --set assignments (or --selection, for
// the key selection), its own folder OUT/cells/KEY=VALUE+...; CliError on a key both fixed and swept.
RunOptions sweep_cell_options(const RunOptions& sweep, const GridCell& cell);

// The result files below a sweep's folder with the cells in the order of `grid` (the first axis
// varying slowest), so tables list them as the command named them.
std::vector<RunRecord> load_sweep_records(const std::string& out, const std::vector<std::string>& grid);

}  // namespace fscil
