#include "tools/fscil-bench/commands/rerun_command.h"

#include <fmt/format.h>

#include <variant>

#include "tools/fscil-bench/options/run_option_table.h"

namespace fscil {

RunOptions rerun_options(const RunRecord& record, const std::string& file, const RunOptions& where) {
  RunOptions run;
  const std::string origin = fmt::format("rerun {}: \"parameters\"", file);
  // Where and how this command runs: its own options; the rest comes from the record.
  for (const auto& option : run_option_table()) {
    if (!option.from_result_file) std::visit([&](auto member) { run.*member = where.*member; }, option.member);
  }
  run.resume = where.resume;

  run.methods = record.method;
  run.dataset = record.dataset;
  run.profile = record.profile;
  run.seeds = std::to_string(record.seed);
  run.threads = record.threads;
  run.evaluate_on = record.evaluated_on;
  run.selection = record.selection;
  run.grid = record.grid;
  run.rerun_of = file;
  run.rerun_parameters = record.parameters;
  for (const auto& [key, value] : record.parameters) {
    if (key == "base_training" || key == "selection") continue;  // how the base was obtained; the selection above
    if (key == "split_mode") {
      run.split_mode = value;
    } else if (key == "class_order") {
      run.class_order = value;
    } else if (key == "max_memory") {
      run.max_memory = value;  // bytes
    } else if (key == "precision") {
      run.precision = value;
    } else {
      run.assignments.push_back(key + "=" + value);
      run.assignment_origins[key] = origin;
    }
  }
  return run;
}

}  // namespace fscil
