#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/parameter_set.h"
#include "reports/run_record.h"
#include "tools/fscil-bench/commands/run_command.h"

namespace fscil {

// One independent unit of a run or sweep command: the methods that share one base session (the
// cop-fscil variants with the same base key stay together so that base is trained once), on one
// dataset, one grid cell and one seed. Cells are what `--cell K`, `run-cells` and a Slurm array
// task run; their result files together are the command's.
struct BenchCell {
  int index = 0;
  std::vector<std::string> methods;
  std::string dataset;
  GridCell grid;  // empty for a run command
  std::uint64_t seed = 0;
  // Epochs of the base session the cell trains (pretraining, pseudo-incremental, OrCo's base),
  // which dominate its cost: a rough size, not a time.
  std::int64_t epochs = 0;
  std::string cost_class() const;  // small (up to 12) | medium (up to 60) | large
  double estimated_seconds = -1;   // on this machine (cells/time_estimate.h); -1: not estimated
  // What its runs took: the total_seconds of their result files in --out; -1 while one is missing
  // or of another command (profile, threads, split, selection or precision).
  double measured_seconds = -1;
};

// The parameters `method` reads in the command `options` describes (dataset defaults, profile,
// --set), marked as read.
ParameterSet method_parameters(const RunOptions& options, const std::string& method);

// The cells of the command `options` describes (`grid`: the --grid texts of a sweep, empty for a
// run), in a fixed order: grid cell (as the sweep runs them), then method group (as --methods
// names them), then seed. Throws on what the command itself would refuse (unknown method, bad
// seeds or grid).
std::vector<BenchCell> plan_cells(const RunOptions& options, const std::vector<std::string>& grid);

// The run command of one cell: its methods and seed only, in its grid cell's folder, continuing
// what that folder holds of it.
RunOptions cell_run_options(const RunOptions& options, const BenchCell& cell);

// Whether every run of the cell has its result file.
bool cell_has_results(const RunOptions& options, const BenchCell& cell);

// Fills measured_seconds of every cell whose result files --out holds, so that `plan` puts each
// estimate beside the time the cell took. A result file that does not read is an error.
void add_measured_seconds(const RunOptions& options, std::vector<BenchCell>& cells);

// `fscil-bench plan`: one line per cell (index, methods, dataset, grid cell, seed, cost class,
// the estimated time where cells have one, and the measured time where --out has their results),
// then the count, the estimated total and, over the cells measured, measured against estimated.
std::string render_plan(const std::vector<BenchCell>& cells);
// Seconds as H:MM:SS, rounded up (as Slurm's --time takes it).
std::string clock_time(double seconds);

// `--cell K`: runs cell K of the command and writes its result files (no tables); CliError when
// the command has no cell K.
std::string run_cell(const RunOptions& options, const std::vector<std::string>& grid, int index);

// The result files below `results` (load_run_records) ordered as the command runs them: grid
// cells as `grid` gives them, then methods as `methods` names them (empty: as `list` does, the
// registry's order, which puts the CoP-FSCIL ablation in the paper's order), then seeds in number
// order; so every table and figure reads in the command's order. A file is refused unless of a
// profile and a method this program knows: a table must not carry a name nothing here can run (an
// out-of-tree method's results are tabulated by its own program, which registers it).
std::vector<RunRecord> load_command_records(const std::string& results, const std::string& methods,
                                            const std::vector<std::string>& grid);

// Every distinct grid cell checked as its run would check it (options, values, keys no one reads;
// the dataset prepared, the methods built) before a cell is listed, scripted or started: a bad
// --grid value fails here once, not in every task. A real dataset whose files are not on this
// machine cannot be checked here, and is not.
void check_every_cell(const RunOptions& options, const std::vector<std::string>& grid);

// Which classes the command's sessions remove (describe_removal, for its first cell and seed); ""
// when they only add classes, or where the dataset's files are not on this machine.
std::string removal_of_command(const RunOptions& options, const std::vector<std::string>& grid);

// CliError when `records` (of `results`) are not those of the command `methods` and `grid` name:
// a named method or grid cell without a result file, or a result file of a cell the grid does not
// name (report --methods/--grid on the wrong folder said nothing).
void require_results_of_the_command(const std::vector<RunRecord>& records, const std::string& results,
                                    const std::string& methods, const std::vector<std::string>& grid);

// The command's tables over every cell's result files in --out; returns the Markdown.
std::string write_command_tables(const RunOptions& options, const std::vector<std::string>& grid);

}  // namespace fscil
