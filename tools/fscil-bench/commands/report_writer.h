#pragma once
#include <filesystem>
#include <vector>

#include "reports/run_record.h"

namespace fscil {

// Writes summary.csv, sessions.csv, results.tex, costs.csv, costs.tex, each run's training log
// (logs/), the figures of every dataset (figures/: accuracy per session on all, base and novel
// classes and their harmonic mean, R per session, efficiency) and the report page index.html into
// `out`, and returns the Markdown tables (accuracy, then cost).
std::string write_reports(const std::filesystem::path& out, const std::vector<RunRecord>& records);

// The paper's tables as shipped in the source tree.
std::filesystem::path default_paper_tables();
// Writes paper_comparison.csv (ours, paper, ours - paper per matching dataset and method) into
// `out` and returns it as Markdown.
std::string write_paper_comparison(const std::filesystem::path& out, const std::vector<RunRecord>& records,
                                   const std::filesystem::path& paper_tables);

}  // namespace fscil
