#include "tools/fscil-bench/commands/sweep_command.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "core/parameter_set.h"
#include "reports/run_record.h"
#include "tools/fscil-bench/cells/bench_cells.h"
#include "core/error.h"
#include "tools/fscil-bench/cells/out_folder_lock.h"
#include "tools/fscil-bench/commands/report_writer.h"
#include "tools/fscil-bench/options/sweep_grid.h"

namespace fscil {

namespace fs = std::filesystem;

RunOptions sweep_cell_options(const RunOptions& sweep, const GridCell& cell) {
  RunOptions run = sweep;
  run.grid = cell;
  run.out = (fs::path(sweep.out) / "cells" / grid_cell_name(cell)).string();
  // A cell not started before the interruption starts now.
  run.resume = sweep.resume && fs::is_directory(run.out);
  for (const auto& [key, value] : cell) {
    for (const auto& assignment : sweep.assignments) {
      if (assignment.substr(0, assignment.find('=')) == key) {
        throw CliError(fmt::format("--set {} and --grid {}: a key is either fixed or swept", assignment, key));
      }
    }
    if (key == "selection") {
      if (sweep.selection != "last") {
        throw CliError(fmt::format("--selection {} and --grid selection: a choice is either fixed or swept",
                                   sweep.selection));
      }
      try {
        require_selection_name(value);
      } catch (const Error& error) {
        throw CliError(fmt::format("--grid {}", error.what()));
      }
      run.selection = value;
    } else {
      run.assignments.push_back(key + "=" + value);
    }
  }
  return run;
}

std::vector<RunRecord> load_sweep_records(const std::string& out, const std::vector<std::string>& grid) {
  const std::vector<GridAxis> axes = parse_grid(grid);
  std::vector<std::string> order, keys;
  for (const auto& cell : grid_cells(axes)) order.push_back(grid_cell_name(cell));
  for (const auto& axis : axes) keys.push_back(axis.key);
  std::vector<RunRecord> records = load_run_records(out);
  for (auto& record : records) record.grid = in_key_order(record.grid, keys);  // the command's order
  const auto position = [&](const RunRecord& record) {
    return std::find(order.begin(), order.end(), grid_cell_name(record.grid)) - order.begin();
  };
  std::stable_sort(records.begin(), records.end(),
                   [&](const RunRecord& a, const RunRecord& b) { return position(a) < position(b); });
  return records;
}

std::string run_sweep(const RunOptions& options, const std::vector<std::string>& grid) {
  const auto cells = grid_cells(parse_grid(grid));
  std::vector<RunOptions> runs;
  for (const auto& cell : cells) runs.push_back(sweep_cell_options(options, cell));
  check_every_cell(options, grid);  // a bad value in the last cell is refused before the first one trains
  const OutFolderLock lock(options.out);
  for (std::size_t c = 0; c < runs.size(); ++c) {
    if (!options.quiet) fmt::print(stderr, "== cell {} of {}: {}\n", c + 1, runs.size(), grid_cell_name(runs[c].grid));
    run_benchmark(runs[c]);
  }
  const std::string markdown = write_reports(options.out, load_command_records(options.out, options.methods, grid));
  return markdown + fmt::format("Sweep of {0} cells: tables over every cell in {1}/summary.csv, {1}/sessions.csv, "
                                "{1}/results.tex; each cell's own in {1}/cells/\n", runs.size(), options.out);
}

}  // namespace fscil
