#pragma once
#include <filesystem>
#include <vector>

#include "reports/run_record.h"

namespace fscil {

// Writes summary.csv, results.tex, costs.csv and costs.tex into `out` and returns the Markdown
// tables (accuracy, then cost).
std::string write_reports(const std::filesystem::path& out, const std::vector<RunRecord>& records);

}  // namespace fscil
