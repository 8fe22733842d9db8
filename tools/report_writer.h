#pragma once
#include <filesystem>
#include <vector>

#include "reports/run_record.h"

namespace fscil {

// Writes summary.csv and results.tex into `out` and returns the Markdown table.
std::string write_reports(const std::filesystem::path& out, const std::vector<RunRecord>& records);

}  // namespace fscil
