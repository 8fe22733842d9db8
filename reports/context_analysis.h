#pragma once
#include <string>
#include <vector>

#include "reports/run_record.h"

namespace fscil {

// The context-to-class dispersion R recorded in result files, per (method, dataset) and
// session, averaged over seeds: CSV (method,dataset,seeds,AA,session,R_mean,R_max) and a
// Markdown table. Throws ReportError when no result file carries R.
std::string render_context_analysis_csv(const std::vector<RunRecord>& records);
std::string render_context_analysis_markdown(const std::vector<RunRecord>& records);

}  // namespace fscil
