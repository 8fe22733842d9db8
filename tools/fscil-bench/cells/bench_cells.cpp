#include "tools/fscil-bench/cells/bench_cells.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <tuple>

#include "datasets/dataset_catalog.h"
#include "methods/method.h"
#include "methods/method_registry.h"
#include "core/parameter_set.h"
#include "protocols/profiles.h"
#include "reports/run_record.h"
#include "core/error.h"
#include "core/shown_text.h"
#include "tools/fscil-bench/options/run_option_table.h"
#include "tools/fscil-bench/options/dataset_defaults.h"
#include "tools/fscil-bench/cells/out_folder_lock.h"
#include "tools/fscil-bench/commands/report_writer.h"
#include "tools/fscil-bench/options/seed_list.h"
#include "tools/fscil-bench/commands/sweep_command.h"
#include "tools/fscil-bench/options/sweep_grid.h"
#include "core/number_text.h"
#include "core/parallel_for.h"
#include "core/text_file.h"

namespace fscil {

namespace fs = std::filesystem;

namespace {

// The methods of a command grouped by the base session they share (MethodEntry::shared_base_key), in
// the order --methods names them; with the epochs of that base.
struct MethodGroup {
  std::vector<std::string> methods;
  std::int64_t epochs = 0;
};

// The base session's epochs, which dominate a run's cost (sessions train on a few shots): the
// method's base-epoch parameters as it read them.
std::int64_t base_epochs(const std::string& method, const ParameterSet& read) {
  std::int64_t epochs = 0;
  for (const std::string& key : method_entry(method).base_epoch_keys) {
    if (const auto found = read.used().find(key); found != read.used().end()) {
      const auto value = parse_number<std::int64_t>(found->second);
      if (!value) throw ProtocolError(fmt::format("parameter {}='{}': expected an integer", key, found->second));
      epochs += *value;
    }
  }
  return epochs;
}

std::vector<MethodGroup> method_groups(const RunOptions& options) {
  std::vector<MethodGroup> groups;
  std::vector<std::string> keys;
  for (const auto& name : resolve_method_names(options.methods)) {
    const ParameterSet read = method_parameters(options, name);
    const std::string& key = method_entry(name).shared_base_key;
    const auto same = key.empty() ? keys.end() : std::find(keys.begin(), keys.end(), key);
    if (same == keys.end()) {
      groups.push_back({{name}, base_epochs(name, read)});
      keys.push_back(key);
    } else {
      auto& group = groups[static_cast<std::size_t>(same - keys.begin())];
      group.methods.push_back(name);
    }
  }
  return groups;
}

}  // namespace

ParameterSet method_parameters(const RunOptions& options, const std::string& method) {
  ParameterSet params;
  apply_dataset_defaults(options.dataset, params);
  apply_profile(options.profile, params);
  apply_assignments(options, params);
  create_method(method, params);  // marks the parameters it reads
  return params;
}

std::string BenchCell::cost_class() const {
  if (epochs <= 12) return "small";
  if (epochs <= 60) return "medium";
  return "large";
}

std::vector<BenchCell> plan_cells(const RunOptions& options, const std::vector<std::string>& grid) {
  if (options.methods.empty() || options.dataset.empty()) throw CliError("--methods and --dataset are required");
  std::vector<GridCell> grid_cells_of_command = {{}};
  if (!grid.empty()) grid_cells_of_command = grid_cells(parse_grid(grid));
  const auto seeds = parse_seed_list(options.seeds);
  std::vector<BenchCell> cells;
  for (const auto& grid_cell : grid_cells_of_command) {
    const RunOptions run = grid.empty() ? options : sweep_cell_options(options, grid_cell);
    for (const auto& group : method_groups(run)) {
      for (std::uint64_t seed : seeds) {
        cells.push_back({static_cast<int>(cells.size()), group.methods, options.dataset, grid_cell, seed, group.epochs});
      }
    }
  }
  return cells;
}

namespace {

// Where the run `method` of `cell` writes its result file, in the cell's folder `run.out`.
fs::path result_file_of(const RunOptions& run, const BenchCell& cell, const std::string& method) {
  RunRecord name;
  name.method = method;
  name.dataset = cell.dataset;
  name.seed = cell.seed;
  return fs::path(run.out) / "results" / run_record_file_name(name);
}

}  // namespace

RunOptions cell_run_options(const RunOptions& options, const BenchCell& cell) {
  RunOptions run = cell.grid.empty() ? options : sweep_cell_options(options, cell.grid);
  run.methods = fmt::format("{}", fmt::join(cell.methods, ","));
  run.seeds = std::to_string(cell.seed);
  run.cell = cell.index;
  run.resume = fs::is_directory(run.out);  // a requeued or repeated cell continues
  return run;
}

namespace {

// The result of every run of the cell, in cell.methods' order, each file read once; nothing when
// one is missing. A damaged file is one error naming it, never a cell counted as done.
std::optional<std::vector<RunRecord>> cell_records(const RunOptions& run, const BenchCell& cell) {
  std::vector<RunRecord> records;
  for (const std::string& method : cell.methods) {
    const fs::path file = result_file_of(run, cell, method);
    if (!fs::exists(file)) return std::nullopt;
    records.push_back(read_run_record(file));
  }
  return records;
}

}  // namespace

bool cell_has_results(const RunOptions& options, const BenchCell& cell) {
  return cell_records(cell_run_options(options, cell), cell).has_value();
}

namespace {

// Whether `record` is the run `method` of `cell` makes under `run`: the same run, seed, profile,
// threads, split, selection and precision, and every value the method reads as the command gives it.
bool is_run_of(const RunRecord& record, const RunOptions& run, const BenchCell& cell, const std::string& method) {
  if (record.method != method || record.dataset != cell.dataset || record.seed != cell.seed ||
      record.profile != run.profile || record.threads != thread_count(run.threads) ||
      record.evaluated_on != run.evaluate_on || record.selection != run.selection ||
      precision_of(record) != run.precision) {
    return false;
  }
  const auto recorded_as = [&](const std::string& key, const std::string& value) {
    const auto recorded = record.parameters.find(key);
    return recorded != record.parameters.end() && recorded->second == value;
  };
  const ParameterSet read = method_parameters(run, method);
  return std::all_of(read.used().begin(), read.used().end(),
                     [&](const auto& value) { return recorded_as(value.first, value.second); }) &&
         std::all_of(run.assignments.begin(), run.assignments.end(), [&](const std::string& assignment) {
           const auto equals = assignment.find('=');
           return recorded_as(assignment.substr(0, equals), assignment.substr(equals + 1));
         });
}

}  // namespace

void add_measured_seconds(const RunOptions& options, std::vector<BenchCell>& cells) {
  for (BenchCell& cell : cells) {
    const RunOptions run = cell_run_options(options, cell);
    const auto records = cell_records(run, cell);
    if (!records) continue;
    double seconds = 0;
    bool of_this_command = true;
    for (std::size_t i = 0; i < records->size(); ++i) {
      of_this_command = of_this_command && is_run_of((*records)[i], run, cell, cell.methods[i]);
      // A run continuing from a base another run of its cell trained counts only its sessions.
      seconds += (*records)[i].total_seconds;
    }
    if (of_this_command) cell.measured_seconds = seconds;
  }
}

std::string render_plan(const std::vector<BenchCell>& cells) {
  const auto any = [&](auto has) { return std::any_of(cells.begin(), cells.end(), has); };
  const bool estimated = any([](const BenchCell& cell) { return cell.estimated_seconds >= 0; });
  const bool measured = any([](const BenchCell& cell) { return cell.measured_seconds >= 0; });
  const auto shown = [](double seconds) { return seconds >= 0 ? clock_time(seconds) : std::string("-"); };
  const auto last_columns = [&](const std::string& cost, const std::string& estimate, const std::string& took) {
    std::string text = estimated || measured ? fmt::format("{:<30}  {:>8}", cost, estimate) : cost;
    return measured ? fmt::format("{}  {:>8}", text, took) : text;
  };
  std::string text = fmt::format("{:>5}  {:<40}  {:<14}  {:<24}  {:>5}  {}\n", "cell", "methods", "dataset", "grid",
                                 "seed", last_columns("cost", "estimate", "measured"));
  double total = 0, measured_total = 0, estimated_of_measured = 0;
  int measured_cells = 0;
  for (const auto& cell : cells) {
    text += fmt::format("{:>5}  {:<40}  {:<14}  {:<24}  {:>5}  {}", cell.index,
                        fmt::format("{}", fmt::join(cell.methods, ",")), cell.dataset,
                        cell.grid.empty() ? "-" : grid_cell_name(cell.grid), cell.seed,
                        last_columns(fmt::format("{} ({} base epochs)", cell.cost_class(), cell.epochs),
                                     shown(cell.estimated_seconds), shown(cell.measured_seconds)));
    text += "\n";
    total += std::max(cell.estimated_seconds, 0.0);
    if (cell.measured_seconds >= 0) {
      ++measured_cells;
      measured_total += cell.measured_seconds;
      estimated_of_measured += std::max(cell.estimated_seconds, 0.0);
    }
  }
  text += fmt::format("{} cells; run one with --cell K, all with run-cells --jobs J or fscil-bench slurm\n", cells.size());
  if (estimated) {
    text += fmt::format("estimated {} for all cells one after another on this machine (training and scoring at "
                        "rates measured here; not the dataset's preparation)\n", clock_time(total));
  }
  if (measured) {
    text += fmt::format("measured {} for the {} of {} cells whose result files --out holds (their runs' total "
                        "seconds, on the machine and load they ran with)", clock_time(measured_total), measured_cells,
                        cells.size());
    if (estimated && estimated_of_measured > 0) {
      text += fmt::format(", estimated {} for them: measured / estimated {:.2f}", clock_time(estimated_of_measured),
                          measured_total / estimated_of_measured);
    }
    text += "\n";
  }
  return text;
}

std::string clock_time(double seconds) {
  // Bounded, so the conversion is defined whatever an estimate comes to (1e15 s: 3e7 years).
  const auto whole = static_cast<long long>(std::ceil(seconds > 0 ? std::min(seconds, 1e15) : 0.0));
  return fmt::format("{}:{:02}:{:02}", whole / 3600, whole / 60 % 60, whole % 60);
}

std::string run_cell(const RunOptions& options, const std::vector<std::string>& grid, int index) {
  const auto cells = plan_cells(options, grid);
  if (index < 0 || index >= static_cast<int>(cells.size())) {
    throw CliError(fmt::format("--cell {}: this command has {} cells, 0 to {} (see: fscil-bench plan)", index,
                               cells.size(), cells.size() - 1));
  }
  const RunOptions run = cell_run_options(options, cells[static_cast<std::size_t>(index)]);
  if (grid.empty()) return run_benchmark(run);
  const OutFolderLock sweep_folder = OutFolderLock::shared(options.out);  // no whole-sweep command meanwhile
  return run_benchmark(run);
}

namespace {

void require_known_names(const std::vector<RunRecord>& records) {
  for (const auto& record : records) {
    require_profile(record.profile, record.source);
    const auto& registry = method_registry();
    if (std::none_of(registry.begin(), registry.end(), [&](const MethodEntry& entry) { return entry.name == record.method; })) {
      throw ReportError(fmt::format("{}: field 'method': expected a method this program runs (fscil-bench list), found "
                                    "'{}'; an out-of-tree method's results are tabulated by its own program",
                                    record.source, shown_text(record.method)));
    }
  }
}

}  // namespace

std::vector<RunRecord> load_command_records(const std::string& results, const std::string& methods,
                                            const std::vector<std::string>& grid) {
  std::vector<RunRecord> records = grid.empty() ? load_run_records(results) : load_sweep_records(results, grid);
  require_known_names(records);
  // Files written before results carried the method's note get the one this program has for it.
  for (RunRecord& record : records) {
    if (record.method_note.empty()) record.method_note = method_entry(record.method).table_note;
  }
  const std::vector<std::string> order = resolve_method_names(methods.empty() ? "all" : methods);
  std::vector<std::string> cells;  // as load_sweep_records ordered them
  for (const auto& record : records) {
    if (std::find(cells.begin(), cells.end(), grid_cell_name(record.grid)) == cells.end()) {
      cells.push_back(grid_cell_name(record.grid));
    }
  }
  const auto position = [&](const RunRecord& record) {
    return std::make_tuple(std::find(cells.begin(), cells.end(), grid_cell_name(record.grid)) - cells.begin(),
                           std::find(order.begin(), order.end(), record.method) - order.begin(), record.seed);
  };
  std::stable_sort(records.begin(), records.end(),
                   [&](const RunRecord& a, const RunRecord& b) { return position(a) < position(b); });
  return records;
}

std::string removal_of_command(const RunOptions& options, const std::vector<std::string>& grid) {
  try {
    return command_sizes(grid.empty() ? options : sweep_cell_options(options, grid_cells(parse_grid(grid)).front())).removal;
  } catch (const DataNotHere&) {
    return "";
  }
}

void check_every_cell(const RunOptions& options, const std::vector<std::string>& grid) {
  std::vector<GridCell> cells = {{}};
  if (!grid.empty()) cells = grid_cells(parse_grid(grid));
  for (const auto& cell : cells) {
    try {
      command_sizes(grid.empty() ? options : sweep_cell_options(options, cell));
    } catch (const DataNotHere&) {
      return;
    }
  }
}

void require_results_of_the_command(const std::vector<RunRecord>& records, const std::string& results,
                                    const std::string& methods, const std::vector<std::string>& grid) {
  const auto any_of = [&](const auto& matches) { return std::any_of(records.begin(), records.end(), matches); };
  if (!methods.empty()) {
    for (const std::string& method : resolve_method_names(methods)) {
      if (!any_of([&](const RunRecord& record) { return record.method == method; })) {
        throw CliError(fmt::format("--methods: {} holds no result file of {}", results, method));
      }
    }
  }
  if (grid.empty()) return;
  std::vector<std::string> cells;
  for (const auto& cell : grid_cells(parse_grid(grid))) cells.push_back(grid_cell_name(cell));
  for (const std::string& cell : cells) {
    if (!any_of([&](const RunRecord& record) { return grid_cell_name(record.grid) == cell; })) {
      throw CliError(fmt::format("--grid: {} holds no result file of cell {}", results, cell));
    }
  }
  for (const RunRecord& record : records) {
    if (std::find(cells.begin(), cells.end(), grid_cell_name(record.grid)) == cells.end()) {
      throw CliError(fmt::format("--grid: {} is of cell '{}', which this --grid does not name", record.source,
                                 grid_cell_name(record.grid)));
    }
  }
}

std::string write_command_tables(const RunOptions& options, const std::vector<std::string>& grid) {
  return write_reports(options.out, load_command_records(options.out, options.methods, grid));
}

}  // namespace fscil
