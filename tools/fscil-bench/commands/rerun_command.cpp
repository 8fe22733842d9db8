#include "tools/fscil-bench/commands/rerun_command.h"

namespace fscil {

RunOptions rerun_options(const RunRecord& record, const RunOptions& where) {
  RunOptions run;
  run.out = where.out;
  run.resume = where.resume;
  run.data_root = where.data_root;
  run.cache_dir = where.cache_dir;
  run.no_cache = where.no_cache;
  run.no_stage_cache = where.no_stage_cache;
  run.features = where.features;
  run.save_model = where.save_model;
  run.save_embeddings = where.save_embeddings;
  run.quiet = where.quiet;

  run.methods = record.method;
  run.dataset = record.dataset;
  run.profile = record.profile;
  run.seeds = std::to_string(record.seed);
  run.threads = record.threads;
  run.evaluate_on = record.evaluated_on;
  run.selection = record.selection;
  run.grid = record.grid;
  for (const auto& [key, value] : record.parameters) {
    if (key == "base_training" || key == "selection") continue;  // how the base was obtained; the selection above
    if (key == "split_mode") {
      run.split_mode = value;
    } else if (key == "class_order") {
      run.class_order = value;
    } else if (key == "max_memory") {
      run.max_memory = value;  // bytes
    } else {
      run.assignments.push_back(key + "=" + value);
    }
  }
  return run;
}

}  // namespace fscil
