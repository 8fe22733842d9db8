#pragma once
#include <filesystem>
#include <string>

#include "reports/run_record.h"

namespace fscil {

// A run's training log as CSV: one line per (session, stage, epoch) with a column per value any
// epoch reported (loss, its terms, lr, selection_score, seconds), empty where an epoch has none.
std::string render_training_log_csv(const RunRecord& record);

// Where a run's training log goes below a results folder: logs/METHOD__DATASET__seedN.csv, and
// below its sweep cell's folder name (logs/CELL/...) when the folder's runs span several cells.
std::filesystem::path training_log_path(const RunRecord& record, bool several_cells);

}  // namespace fscil
