#pragma once
#include <filesystem>
#include <optional>
#include <vector>

#include "reports/run_record.h"

namespace fscil {

// The paper's tables as shipped in the source tree.
std::filesystem::path default_paper_tables();

// Writes summary.csv, sessions.csv, results.tex, costs.csv, costs.tex, each run's training log
// (logs/), the figures of every dataset (figures/: accuracy per session on all, base and novel
// classes and their harmonic mean, R per session, efficiency), with `paper_tables`
// paper_comparison.csv (ours, paper, ours - paper per matching dataset and method), and the report
// page index.html into `out`, as one FileBatch: a failure while writing them leaves the earlier
// tables as they were. Returns the Markdown tables (accuracy, cost, then the paper's).
std::string write_reports(const std::filesystem::path& out, const std::vector<RunRecord>& records,
                          const std::optional<std::filesystem::path>& paper_tables = std::nullopt);

}  // namespace fscil
