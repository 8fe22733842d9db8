#pragma once
#include "reports/run_record.h"
#include "tools/fscil-bench/commands/run_command.h"

namespace fscil {

// `fscil-bench rerun RESULT.json`: the run command that repeats the run which wrote `record`,
// exactly: its method, dataset, profile, seed, threads, scored split, selection, grid cell and
// every parameter it used (as --set). From `where` it takes only what does not shape the numbers:
// --out (and --resume), --data-root, the caches, --features, --save-model, --save-embeddings and
// --quiet; the command line refuses the other run options with rerun. An error in a parameter
// names `file`.
RunOptions rerun_options(const RunRecord& record, const std::string& file, const RunOptions& where);

}  // namespace fscil
